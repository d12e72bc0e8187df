// Mechanisms shared by several tests, built through the C++ API.
#pragma once

#include "support.hpp"

#include <numbers>

namespace linx::test {

/// Planar slider-crank in the x-y plane (hinge axes along z, gravity -z): crank r = 0.1 m hinged
/// to the world at the origin and driven by a motor, rod l = 0.3 m, piston on a slider along x.
/// Over-constrained in 3-D (three parallel hinges and a slider): 20 rows for 17 independent
/// constraints, so A is singular.
struct SliderCrank {
  static constexpr double r = 0.1, l = 0.3;
  World world;
  BodyId crank, rod, piston;
  JointId crank_hinge;

  explicit SliderCrank(const SolverSettings& solver, double speed = 2.0 * std::numbers::pi,
                       double h = 1e-3)
      : world(WorldSettings{.gravity = Vec3(0, 0, -9.81), .timestep = h, .solver = solver}) {
    crank = world.createBody(boxBody("crank", 1.0, Vec3(r, 0.02, 0.02), Vec3(r / 2, 0, 0)));
    rod = world.createBody(boxBody("rod", 1.0, Vec3(l, 0.02, 0.02), Vec3(r + l / 2, 0, 0)));
    piston = world.createBody(boxBody("piston", 0.5, Vec3(0.05, 0.05, 0.05), Vec3(r + l, 0, 0)));
    crank_hinge = world.createJoint(
        "hinge", JointDef{.name = "crank",
                          .body1 = crank,
                          .anchor = Vec3::Zero(),
                          .axis = Vec3::UnitZ(),
                          .coordinates = {CoordinateDef{
                              .motor = JointMotor{.target_velocity = speed, .max_force = 100.0}}}});
    world.createJoint("hinge", JointDef{.name = "crank_pin",
                                        .body1 = rod,
                                        .body2 = crank,
                                        .anchor = Vec3(r, 0, 0),
                                        .axis = Vec3::UnitZ()});
    world.createJoint("hinge", JointDef{.name = "piston_pin",
                                        .body1 = piston,
                                        .body2 = rod,
                                        .anchor = Vec3(r + l, 0, 0),
                                        .axis = Vec3::UnitZ()});
    world.createJoint("slider", JointDef{.name = "piston_slider",
                                         .body1 = piston,
                                         .anchor = Vec3(r + l, 0, 0),
                                         .axis = Vec3::UnitX()});
  }

  /// Piston position from the closed-form kinematics for the crank angle phi.
  static double pistonX(double phi) {
    const double s = std::sin(phi);
    return r * std::cos(phi) + std::sqrt(l * l - r * r * s * s);
  }
};

}  // namespace linx::test
