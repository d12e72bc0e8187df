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

// The mechanisms of the integrator table (linx-bench --integrators, docs/integrators.md): smooth
// jointed motion without contacts, each with an independent truth. Each runs `duration` seconds.

/// IFToMM A01: a 1 kg mass (inertia 1e-4 kg m^2) 1 m from a hinge at the origin, released
/// horizontal under g = 9.81 m/s^2 along -y; h = 0.01 s. Its centre against the physical
/// pendulum's closed form (Jacobi's sn), energy conserved.
Scene pendulumA01(double duration);
/// IFToMM A02: the N-four-bar mechanism, N = 40: 41 cranks hinged to the ground 1 m apart and 40
/// couplers, 1 m, 1 kg rods, 80 loop-closing hinges (redundant in the plane), singular whenever
/// the cranks are horizontal; h = 0.01 s. Point B0, the top of the first crank, against the
/// library's published reference positions at 0.05, 0.5, 1, 2, 5, 10 and 20 s; energy conserved.
Scene fourBarA02(double duration);
/// The heavy symmetric top in steady precession (Goldstein, section 5.7): 1 kg, centre 0.1 m
/// from the fixed tip (a ball joint), tilted 0.5 rad, precessing at 1.5 rad/s; h = 1 ms. Its
/// centre against the closed form (a circle at constant height); energy conserved.
Scene heavyTop(double duration);
/// The 5-link hinge chain of hingeChain(5) at h = 1 ms (issue 19's chain): energy conserved, no
/// closed form.
Scene swingingChain(double duration);
/// The spatial slider-crank of bench/spatial_slider_crank.hpp with a ball joint at each end of the
/// rod (every engine has them; the symmetric rod never spins about itself), at rest with the crank
/// 30 degrees up; h = 0.01 s. The crank pin against Lagrange's equation in the crank angle
/// (one_dof_reference.hpp); energy conserved.
Scene spatialSliderCrank(double duration);
/// IFToMM A05, the stiff flyball governor of bench/flyball_governor.hpp (as
/// examples/benchmarks/iftomm_a05_flyball_governor.json, less the slider's travel limits, which it
/// never reaches and Simbody's adapter does not take), turning at 2 pi rad/s at the start; h =
/// 0.01 s. The slider's centre against the reduced-coordinate solution; energy not conserved (the
/// dampers).
Scene flyballGovernorA05(double duration);

}  // namespace bench
