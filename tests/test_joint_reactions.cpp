// Joint reactions: the force and torque a joint applies to its first body, against statics and
// the closed forms of a swinging rod and a saturated servo.
#include "support.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>

namespace linx {
namespace {

constexpr double kG = 9.81;

struct Rod {
  World world;
  BodyId rod;
  JointId hinge;
};

// A 1 kg, 1 m rod hinged at one end (the origin) about y, lying along x, or hanging along -z.
Rod makeRod(SolverType type, bool hanging, bool gravity = true) {
  WorldSettings s;
  if (!gravity) s.gravity.setZero();
  s.solver.type = type;
  if (type == SolverType::Soft) s.solver.substeps = 4;
  Rod r{World(s), {}, {}};
  BodyDef d = test::boxBody("rod", 1.0, Vec3(1.0, 0.02, 0.02), Vec3(0.5, 0, 0));
  if (hanging) {
    d.position = Vec3(0, 0, -0.5);
    d.orientation = Quat(Eigen::AngleAxisd(std::numbers::pi / 2, Vec3::UnitY()));
  }
  r.rod = r.world.createBody(d);
  r.hinge = r.world.createJoint(
      "hinge",
      JointDef{.name = "pivot", .body1 = r.rod, .anchor = Vec3::Zero(), .axis = Vec3::UnitY()});
  return r;
}

// The solver's name, for messages (solverTypeName's views are of string literals).
TEST(JointReaction, HeldRodCarriesItsWeightAndItsMoment) {
  // Held still by a motor at zero speed, the rod's weight hangs on the pivot: the joint pushes up
  // with m g and turns it with -m g L/2 about y (gravity's moment about the pivot is +m g L/2).
  // Hanging, the moment is zero.
  for (const SolverType type : {SolverType::Auto, SolverType::Pgs, SolverType::Soft}) {
    for (const bool hanging : {false, true}) {
      Rod r = makeRod(type, hanging);
      if (!hanging)
        r.world.joint(r.hinge).setMotor(JointMotor{.target_velocity = 0.0, .max_force = 100.0});
      for (int i = 0; i < 100; ++i) r.world.step();
      const JointReaction j = r.world.jointReaction(r.hinge);
      const Vec3 moment = hanging ? Vec3::Zero() : Vec3(0, -0.5 * kG, 0);
      std::printf("%s, %s: force (%.9f, %.3g, %.3g) N, torque (%.3g, %.9f, %.3g) N m\n",
                  test::solverName(type), hanging ? "hanging" : "held", j.force.x(), j.force.y(),
                  j.force.z(), j.torque.x(), j.torque.y(), j.torque.z());
      EXPECT_LT((j.force - Vec3(0, 0, kG)).norm(), 1e-6 * kG);
      EXPECT_LT((j.torque - moment).norm(), 1e-6 * kG);
    }
  }
}

TEST(JointReaction, SwingingRodPullsTwoAndAHalfTimesItsWeightAtTheBottom) {
  // Released horizontal, a uniform rod passes the bottom with omega^2 = 2 m g d / I_p (d = L/2,
  // I_p = m L^2 / 3): the pivot then pulls m g + m omega^2 d = 2.5 m g straight up, and no torque
  // (a free hinge passes none). The accurate integrator's reaction is its mean over the frame,
  // the torque taken about the anchor as it moves.
  for (const IntegratorType integrator : {IntegratorType::Step, IntegratorType::Accurate}) {
    Rod r = makeRod(SolverType::Auto, false);
    r.world.settings().integrator.type = integrator;
    double previous_x = r.world.body(r.rod).position().x(), force = 0.0, torque = 0.0, when = 0.0;
    for (int i = 0; i < 1000; ++i) {
      r.world.step();
      const double x = r.world.body(r.rod).position().x();
      if (previous_x > 0.0 && x <= 0.0) {  // the bottom: the centre passes under the pivot
        force = r.world.jointReaction(r.hinge).force.z();
        torque = r.world.jointReaction(r.hinge).torque.norm();
        when = r.world.time();
        break;
      }
      previous_x = x;
    }
    std::printf("%s: at the bottom (t = %.3f s): %.6f N up (2.5 m g = %.6f), torque %.3g N m\n",
                std::string(integratorTypeName(integrator)).c_str(), when, force, 2.5 * kG, torque);
    // The force is the mean over the frame: within a frame of the bottom, omega h = 5e-3 rad off.
    EXPECT_NEAR(force, 2.5 * kG, 2e-3 * kG);
    // A free hinge passes no torque about its axis, and nothing bends the rod out of its plane.
    EXPECT_LT(torque, 1e-9);
  }
}

TEST(JointReaction, SaturatedServoTurnsWithItsMaximumTorque) {
  // No gravity, a far target and at most 2 N m: about the axis the joint turns the rod with
  // exactly 2 N m; the pivot's force is what keeps the centre on its circle.
  // The accurate integrator applies the servo as a force.
  for (const IntegratorType integrator : {IntegratorType::Step, IntegratorType::Accurate}) {
    for (const SolverType type : {SolverType::Auto, SolverType::Soft}) {
      Rod r = makeRod(type, false, false);
      r.world.settings().integrator.type = integrator;
      r.world.joint(r.hinge).setMotor(
          JointMotor{.max_force = 2.0, .target_position = 10.0, .stiffness = 1e6});
      for (int i = 0; i < 300; ++i) r.world.step();
      const JointReaction j = r.world.jointReaction(r.hinge);
      std::printf("%s, %s: torque about the axis %.12f N m\n",
                  std::string(integratorTypeName(integrator)).c_str(), test::solverName(type),
                  j.torque.dot(Vec3::UnitY()));
      EXPECT_EQ(r.world.lastIntegratorReport().bodies,
                integrator == IntegratorType::Accurate ? 1 : 0);
      EXPECT_NEAR(j.torque.dot(Vec3::UnitY()), 2.0, 1e-9);
    }
  }
}

}  // namespace
}  // namespace linx
