// Dry friction in a joint: a bounded row holding the coordinate's rate at zero with at most the
// friction force. Closed forms: a block on a vertical rail slides down at g - f / m when its weight
// beats the friction, and stays put when it does not; a wheel on an axle spins down at T / I and
// stops for good at t = I w0 / T, after turning I w0^2 / (2 T).
#include "support.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

namespace linx {
namespace {

constexpr double kG = 9.81;

// The step's solvers, each: with "auto" an island of joints alone would take the accurate
// integrator, whose friction (a switched row, the same closed forms) test_row_events checks.
WorldSettings settings(SolverType type, bool gravity) {
  WorldSettings s = test::solverSettings(type);
  s.integrator.type = IntegratorType::Step;
  if (!gravity) s.gravity.setZero();
  return s;
}

struct Rail {
  World world;
  BodyId block;
  JointId slider;
};

// A 2 kg block on a rail along a tilted direction with a vertical component, gravity along -z.
Rail makeRail(SolverType type, const Vec3& axis, double friction) {
  Rail r{World(settings(type, true)), {}, {}};
  r.block = r.world.createBody(test::boxBody("block", 2.0, Vec3(0.1, 0.1, 0.1), Vec3(0, 0, 1)));
  r.slider =
      r.world.createJoint("slider", JointDef{.name = "rail",
                                             .body1 = r.block,
                                             .axis = axis,
                                             .coordinates = {CoordinateDef{.friction = friction}}});
  return r;
}

class JointFriction : public testing::TestWithParam<SolverType> {};

TEST_P(JointFriction, BlockSlidesDownARailAtGravityLessFriction) {
  // Along the rail: m s'' = -m g cos(a) + f (while sliding down), cos(a) the rail's z component.
  const Vec3 axis = Vec3(1, 0, 2).normalized();
  const double m = 2.0, f = 5.0, a = -kG * axis.z() + f / m;
  Rail r = makeRail(GetParam(), axis, f);
  const double h = r.world.settings().timestep;
  double worst = 0.0;
  for (int n = 1; n <= 1000; ++n) {
    r.world.step();
    // Symplectic Euler under a constant acceleration: s_n = h^2 a n (n + 1) / 2.
    const double exact = 0.5 * h * h * a * n * (n + 1.0);
    worst = std::max(worst, std::abs(r.world.jointCoordinates(r.slider)[0] - exact));
  }
  std::printf("%s: s(1 s) %.9f m (closed form %.9f), worst %.2e m\n", test::solverName(GetParam()),
              r.world.jointCoordinates(r.slider)[0], 0.5 * a * 1.001, worst);
  EXPECT_LT(worst, 1e-6);
}

TEST_P(JointFriction, BlockHeldWhenFrictionExceedsItsWeight) {
  Rail r = makeRail(GetParam(), Vec3::UnitZ(), 30.0);  // m g = 19.62 N < 30 N
  for (int n = 0; n < 500; ++n) r.world.step();
  std::printf("%s: held at %.2e m, reaction %.6f N (weight %.6f N)\n", test::solverName(GetParam()),
              r.world.jointCoordinates(r.slider)[0], r.world.jointReaction(r.slider).force.z(),
              2.0 * kG);
  EXPECT_NEAR(r.world.jointCoordinates(r.slider)[0], 0.0, 1e-6);
  // Friction carries the whole weight: the joint pushes the block up by m g.
  EXPECT_NEAR(r.world.jointReaction(r.slider).force.z(), 2.0 * kG, 1e-3);
}

TEST_P(JointFriction, WheelSpinsDownAtFrictionTorqueAndStops) {
  World world(settings(GetParam(), false));
  const double m = 3.0, size = 0.4, inertia = m * size * size / 6.0;  // cube about its axis
  BodyDef d = test::boxBody("wheel", m, Vec3(size, size, size), Vec3::Zero());
  const double w0 = 3.0, torque = 0.2;
  d.angular_velocity = Vec3(0, 0, w0);
  const BodyId wheel = world.createBody(d);
  const JointId axle =
      world.createJoint("hinge", JointDef{.name = "axle",
                                          .body1 = wheel,
                                          .anchor = Vec3::Zero(),
                                          .axis = Vec3::UnitZ(),
                                          .coordinates = {CoordinateDef{.friction = torque}}});
  const double t_stop = inertia * w0 / torque, turned = inertia * w0 * w0 / (2.0 * torque);
  const double h = world.settings().timestep;
  double worst_rate = 0.0;
  while (world.time() < t_stop - 0.5 * h) {
    world.step();
    const double w = world.body(wheel).angularVelocity().z();
    worst_rate = std::max(worst_rate, std::abs(w - (w0 - torque / inertia * world.time())));
  }
  for (int n = 0; n < 500; ++n) world.step();
  const double angle = world.jointCoordinates(axle)[0];
  std::printf(
      "%s: rate within %.2e rad/s of w0 - T t / I, stopped after %.6f rad (closed form %.6f), "
      "rate after %.2e rad/s\n",
      test::solverName(GetParam()), worst_rate, angle, turned,
      world.body(wheel).angularVelocity().norm());
  // In the step that stops it the friction row is not at its bound: its softness lets through
  // kFrictionSoftness of the rate change the friction impulse makes, 1e-6 h T / I = 2.5e-9 rad/s.
  EXPECT_LT(worst_rate, 3e-9);
  EXPECT_NEAR(angle, turned, 2.0 * w0 * h);  // the last step's share of the stop
  EXPECT_LT(world.body(wheel).angularVelocity().norm(), 1e-9);
}

TEST_P(JointFriction, LimitAndFrictionHoldTogether) {
  // An arm pressed onto its hinge's limit by gravity, with friction in the hinge, then swung back
  // against both: the limit and the friction row hold the same rate (a pair the direct solvers
  // must not find singular); the arm never passes the limit.
  World world(settings(GetParam(), true));
  BodyDef d = test::boxBody("arm", 1.0, Vec3(0.5, 0.05, 0.05), Vec3(0.25, 0, 0));
  d.angular_velocity = Vec3(0, 3.0, 0);  // down: positive about y, towards the limit
  const BodyId arm = world.createBody(d);
  const JointId hinge = world.createJoint(
      "hinge",
      JointDef{.name = "h",
               .body1 = arm,
               .anchor = Vec3::Zero(),
               .axis = Vec3::UnitY(),
               .coordinates = {CoordinateDef{.limits = JointLimits{-1.0, 0.2}, .friction = 0.3}}});
  double highest = -kInfinity;
  for (int n = 0; n < 2000; ++n) {
    world.step();
    highest = std::max(highest, world.jointCoordinates(hinge)[0]);
    // Thrown back up (the step keeps the angular momentum about the hinge: 5 rad/s).
    if (n == 1000) world.body(arm).setAngularVelocity(Vec3(0, -20.0, 0));
  }
  std::printf("%s: highest %.9f rad (limit 0.2), rests at %.9f\n", test::solverName(GetParam()),
              highest, world.jointCoordinates(hinge)[0]);
  EXPECT_LT(highest, 0.2 + 1e-6);
  EXPECT_NEAR(world.jointCoordinates(hinge)[0], 0.2, 1e-6);  // back on it
}

INSTANTIATE_TEST_SUITE_P(Solvers, JointFriction,
                         testing::Values(SolverType::Auto, SolverType::Exact, SolverType::Pgs,
                                         SolverType::Soft),
                         [](const auto& info) {
                           return std::string(test::solverName(info.param));
                         });

TEST(JointFrictionDefinition, RefusedWithTheFieldNamed) {
  World world;
  const BodyId b = world.createBody(test::boxBody("b", 1.0, Vec3(0.1, 0.1, 0.1), Vec3::Zero()));
  const JointId j = world.createJoint(
      "hinge", JointDef{.name = "h", .body1 = b, .anchor = Vec3::Zero(), .axis = Vec3::UnitZ()});
  try {
    world.joint(j).setFriction(-1.0);
    FAIL() << "negative friction accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_STREQ(e.what(), "friction: must be >= 0, got -1");
  }
  EXPECT_THROW(world.joint(j).setFriction(1.0, 1), std::invalid_argument);  // one coordinate
  EXPECT_THROW(world.createJoint("fixed", JointDef{.name = "f",
                                                   .body1 = b,
                                                   .coordinates = {CoordinateDef{.friction = 1}}}),
               std::invalid_argument);
}

}  // namespace
}  // namespace linx
