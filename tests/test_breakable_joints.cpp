// Breakable joints: a joint whose reaction over a step passes its break_force or break_torque
// breaks at the end of that step and acts no more. Closed forms: a weight pulled down by a growing
// force F = c t hangs in equilibrium, so its joint carries m g + F and breaks in the first step
// where that passes the threshold, after which the weight falls freely; a welded cantilever with
// a growing tip load carries the torque m g l/2 + F l about its root.
#include "support.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <stdexcept>

namespace linx {
namespace {

constexpr double kG = 9.81;

class BreakableJoint : public testing::TestWithParam<SolverType> {};

TEST_P(BreakableJoint, HangingWeightBreaksAtItsThresholdThenFalls) {
  constexpr double m = 2.0, rate = 10.0, threshold = 30.005, h = 1e-3;
  World world(test::solverSettings(GetParam()));
  const BodyId weight =
      world.createBody(test::boxBody("weight", m, Vec3(0.1, 0.1, 0.1), Vec3(0, 0, 1)));
  const JointId hook = world.createJoint(
      "ball",
      JointDef{
          .name = "hook", .body1 = weight, .anchor = Vec3(0, 0, 1.5), .break_force = threshold});
  // Step k pulls with c t at its start: the hook carries m g + c (k - 1) h over it.
  const int expected = static_cast<int>(std::floor((threshold - m * kG) / (rate * h))) + 2;
  while (world.jointBreaks().empty() && world.stepCount() < 2000) {
    world.body(weight).applyForce(Vec3(0, 0, -rate * world.time()));
    world.step();
  }
  ASSERT_EQ(world.jointBreaks().size(), 1u);
  const JointBreak& b = world.jointBreaks()[0];
  const double carried = m * kG + rate * (b.step - 1) * h;
  std::printf("%s: broke in step %lld (expected %d) at t = %.3f s, force %.9f N (m g + F = %.9f)\n",
              test::solverName(GetParam()), static_cast<long long>(b.step), expected, b.time,
              b.reaction.force.norm(), carried);
  EXPECT_EQ(b.joint, hook);
  EXPECT_EQ(b.step, expected);
  EXPECT_NEAR(b.time, expected * h, 1e-12);
  EXPECT_NEAR(b.reaction.force.z(), carried, 1e-6 * carried);
  EXPECT_FALSE(world.joint(hook).enabled());
  // Free fall from rest: symplectic Euler's v_n = -g n h, z_n = z0 - g h^2 n (n + 1) / 2.
  const double z0 = world.body(weight).position().z();
  for (int n = 1; n <= 200; ++n) world.step();
  EXPECT_NEAR(world.body(weight).linearVelocity().z(), -kG * 200 * h, 1e-9);
  EXPECT_NEAR(world.body(weight).position().z(), z0 - 0.5 * kG * h * h * 200 * 201, 1e-9);
  EXPECT_EQ(world.jointError(hook), 0.0);
  EXPECT_EQ(world.jointReaction(hook).force, Vec3::Zero());
  EXPECT_EQ(world.jointBreaks().size(), 1u);  // broken once
}

TEST_P(BreakableJoint, CantileverBreaksAtItsTorqueThreshold) {
  // A 1 kg, 1 m bar welded to the world at its end x = 0; a tip load F = c t at x = 1.
  constexpr double m = 1.0, l = 1.0, rate = 2.0, threshold = 6.0, h = 1e-3;
  World world(test::solverSettings(GetParam()));
  const BodyId bar =
      world.createBody(test::boxBody("bar", m, Vec3(l, 0.05, 0.05), Vec3(l / 2, 0, 0)));
  const JointId weld = world.createJoint(
      "fixed",
      JointDef{.name = "weld", .body1 = bar, .anchor = Vec3::Zero(), .break_torque = threshold});
  const int expected =
      static_cast<int>(std::floor((threshold - m * kG * l / 2) / (rate * l * h))) + 2;
  while (world.jointBreaks().empty() && world.stepCount() < 2000) {
    world.body(bar).applyForceAtPoint(Vec3(0, 0, -rate * world.time()), Vec3(l, 0, 0));
    world.step();
  }
  ASSERT_EQ(world.jointBreaks().size(), 1u);
  const JointBreak& b = world.jointBreaks()[0];
  const double carried = m * kG * l / 2 + rate * (b.step - 1) * h * l;
  std::printf("%s: broke in step %lld (expected %d), torque %.9f N m (m g l/2 + F l = %.9f)\n",
              test::solverName(GetParam()), static_cast<long long>(b.step), expected,
              b.reaction.torque.norm(), carried);
  EXPECT_EQ(b.joint, weld);
  EXPECT_EQ(b.step, expected);
  // The weld holds the bar up: its torque on the bar about the root is -y (x cross z).
  EXPECT_NEAR(b.reaction.torque.y(), -carried, 1e-6 * carried);
}

INSTANTIATE_TEST_SUITE_P(Solvers, BreakableJoint,
                         testing::Values(SolverType::Auto, SolverType::Exact, SolverType::Pgs,
                                         SolverType::Soft),
                         [](const auto& info) {
                           return std::string(test::solverName(info.param));
                         });

TEST(BreakableJointDefinition, RefusedWithTheFieldNamed) {
  World world;
  const BodyId b = world.createBody(test::boxBody("b", 1.0, Vec3(0.1, 0.1, 0.1), Vec3::Zero()));
  const auto message = [&](const JointDef& def) -> std::string {
    try {
      world.createJoint("ball", def);
    } catch (const std::invalid_argument& e) {
      return e.what();
    }
    return "accepted";
  };
  EXPECT_EQ(message(JointDef{.name = "a", .body1 = b, .anchor = Vec3::Zero(), .break_force = 0.0}),
            "break_force: must be finite and > 0");
  EXPECT_EQ(
      message(JointDef{.name = "b", .body1 = b, .anchor = Vec3::Zero(), .break_torque = -1.0}),
      "break_torque: must be finite and > 0");
  EXPECT_EQ(message(JointDef{.name = "c",
                             .body1 = b,
                             .anchor = Vec3::Zero(),
                             .break_force = 1.0,
                             .break_torque = 2.0}),
            "accepted");
}

TEST(BreakableJointDefinition, DisabledByHandActsNoMore) {
  World world(test::solverSettings(SolverType::Auto));
  const BodyId bob =
      world.createBody(test::boxBody("bob", 1.0, Vec3(0.1, 0.1, 0.1), Vec3(0, 0, -1)));
  const JointId pivot = world.createJoint(
      "hinge",
      JointDef{.name = "pivot", .body1 = bob, .anchor = Vec3::Zero(), .axis = Vec3::UnitY()});
  for (int n = 0; n < 10; ++n) world.step();
  EXPECT_NEAR(world.body(bob).position().z(), -1.0, 1e-12);  // hangs still
  world.joint(pivot).setEnabled(false);
  for (int n = 1; n <= 100; ++n) world.step();
  EXPECT_NEAR(world.body(bob).linearVelocity().z(), -kG * 100 * 1e-3, 1e-9);
  EXPECT_TRUE(world.jointBreaks().empty());  // switched off, not broken
}

}  // namespace
}  // namespace linx
