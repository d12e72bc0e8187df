// The scenes of the benchmark (issue 4), built in engine-neutral form. docs/performance.md
// describes each one; the runner (main.cpp) picks sizes from the command line.
#pragma once

#include "scene.hpp"

#include <vector>

namespace bench {

/// n links (0.1 m, 1 kg boxes 0.1 x 0.02 x 0.02 m) along +x, link 0 hinged to the world at the
/// origin, hinge axes along y, released horizontal; h = 1/240 s, 2 s. last_mass sets the last
/// link's mass (1000 for the mass-ratio chain). No shapes: a pure mechanism.
Scene hingeChain(int n, double last_mass = 1.0);
/// A two-dimensional pyramid of 0.2 m cubes (1 kg) with `base` boxes in its bottom row,
/// base (base + 1) / 2 in all, on a plane, friction 0.6; h = 1/60 s, 10 s.
Scene pyramid(int base);
/// `count` spheres (radius 0.05 m, 0.1 kg) in a jittered lattice falling into an open box of five
/// static walls, friction 0.5; h = 1/60 s, 2 s.
Scene pouredSpheres(int count);
/// The planar slider-crank of examples/slider_crank.json: crank r = 0.1 m driven at 2 pi rad/s
/// (at most 100 N m), rod l = 0.3 m, piston on a slider; h = 1 ms, 2 s.
Scene sliderCrank();
/// `count` ragdolls of 11 capsule bodies joined by 10 limited hinges, dropped in a grid onto a
/// plane, friction 0.5; h = 1/60 s, 4 s.
Scene ragdolls(int count);

}  // namespace bench
