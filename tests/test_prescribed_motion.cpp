// Prescribed motion: a coordinate follows a table exactly, by whatever force it takes. Checked
// against the closed forms of that force: a block on a horizontal rail moved as x = A sin(w t)
// needs m x'' = -m A w^2 sin(w t); a pendulum turned at a constant rate needs the torque that
// balances gravity's, m g l sin(theta), and nothing about the axis beyond it.
#include "support.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <stdexcept>

namespace linx {
namespace {

constexpr double kG = 9.81;

class PrescribedMotion : public testing::TestWithParam<SolverType> {};

TEST_P(PrescribedMotion, BlockOnARailFollowsASineWithMassTimesAcceleration) {
  constexpr double m = 2.0, amplitude = 0.1, w = 2.0 * M_PI, h = 1e-3;
  // The sine sampled at every step: the table is exact where the steps end.
  std::vector<double> times, values;
  for (int k = 0; k <= 1000; ++k) {
    times.push_back(k * h);
    values.push_back(amplitude * std::sin(w * k * h));
  }
  World world(test::solverSettings(GetParam()));
  const BodyId block =
      world.createBody(test::boxBody("block", m, Vec3(0.1, 0.1, 0.1), Vec3(0, 0, 1)));
  const JointId rail = world.createJoint(
      "slider", JointDef{.name = "rail",
                         .body1 = block,
                         .axis = Vec3::UnitX(),
                         .coordinates = {CoordinateDef{.prescribed = Signal(times, values)}}});
  double worst_x = 0.0, worst_f = 0.0;
  for (int k = 1; k <= 1000; ++k) {
    world.step();
    const double t = k * h;
    worst_x = std::max(worst_x, std::abs(world.jointCoordinates(rail)[0] - values[k]));
    // The step's impulse turned the last step's rate into this one's: the force at the step's
    // start, the discrete second derivative there (exact to O(h^2) of the closed form).
    if (k >= 2) {
      const double force = world.jointReaction(rail).force.x();
      worst_f = std::max(worst_f, std::abs(force + m * amplitude * w * w * std::sin(w * (t - h))));
    }
  }
  std::printf("%s: worst position %.2e m, worst force %.2e N (amplitude %.4f N)\n",
              test::solverName(GetParam()), worst_x, worst_f, m * amplitude * w * w);
  EXPECT_LT(worst_x, 1e-9);
  EXPECT_LT(worst_f, 1e-3 * m * amplitude * w * w);
}

TEST_P(PrescribedMotion, PendulumTurnedAtAConstantRateNeedsGravitysTorque) {
  // A 1 kg point-like bob on a light rod of 0.5 m about a horizontal hinge (y), driven from
  // hanging at 3 rad/s for a whole turn and more.
  constexpr double m = 1.0, l = 0.5, rate = 3.0;
  World world(test::solverSettings(GetParam()));
  BodyDef def;
  def.name = "bob";
  def.mass = m;
  def.inertia = 1e-4 * Mat3::Identity();
  def.position = Vec3(0, 0, -l);
  const BodyId bob = world.createBody(def);
  const JointId hinge = world.createJoint(
      "hinge", JointDef{.name = "pivot",
                        .body1 = bob,
                        .anchor = Vec3::Zero(),
                        .axis = Vec3::UnitY(),
                        .coordinates = {
                            CoordinateDef{.prescribed = Signal({0.0, 10.0}, {0.0, 10.0 * rate})}}});
  double worst_angle = 0.0, worst_torque = 0.0;
  for (int k = 1; k <= 3000; ++k) {
    world.step();
    const double theta = rate * world.time();
    worst_angle = std::max(worst_angle, std::abs(world.jointCoordinates(hinge)[0] - theta));
    if (k >= 2) {
      // About +y, theta from hanging: gravity's torque about the pivot is -m g l sin(theta). The
      // reaction is taken at the step's start, where the bob was one step back.
      const double torque = world.jointReaction(hinge).torque.y();
      worst_torque =
          std::max(worst_torque, std::abs(torque - m * kG * l * std::sin(theta - rate * 1e-3)));
    }
  }
  std::printf(
      "%s: angle after 3 s %.12f rad (3 rad/s: %.12f), worst %.2e rad, worst torque "
      "%.2e N m (m g l = %.4f)\n",
      test::solverName(GetParam()), world.jointCoordinates(hinge)[0], 9.0, worst_angle,
      worst_torque, m * kG * l);
  EXPECT_LT(worst_angle, 1e-9);
  EXPECT_LT(worst_torque, 2e-3 * m * kG * l);
}

INSTANTIATE_TEST_SUITE_P(Solvers, PrescribedMotion,
                         testing::Values(SolverType::Auto, SolverType::Exact, SolverType::Pgs,
                                         SolverType::Soft),
                         [](const auto& info) {
                           return std::string(test::solverName(info.param));
                         });

TEST(PrescribedMotionDefinition, RefusedWithTheFieldNamed) {
  World world;
  const BodyId b = world.createBody(test::boxBody("b", 1.0, Vec3(0.1, 0.1, 0.1), Vec3::Zero()));
  const auto message = [&](const CoordinateDef& c) -> std::string {
    try {
      world.createJoint("universal", JointDef{.name = "u",
                                              .body1 = b,
                                              .anchor = Vec3::Zero(),
                                              .axis = Vec3::UnitZ(),
                                              .axis2 = Vec3::UnitY(),
                                              .coordinates = {CoordinateDef{}, c}});
    } catch (const std::invalid_argument& e) {
      return e.what();
    }
    return "accepted";
  };
  EXPECT_EQ(message(CoordinateDef{.limits = JointLimits{-1, 1}, .prescribed = Signal(0.5)}),
            "angle2.prescribed: a prescribed coordinate takes no limits, motor, spring, friction, "
            "armature, force or lock");
  EXPECT_EQ(message(CoordinateDef{.prescribed = Signal({0.0, 0.0}, {1.0, 2.0})}),
            "angle2.prescribed: times[1]: must be after times[0] (0 <= 0)");
  EXPECT_EQ(message(CoordinateDef{.prescribed = Signal(0.25)}), "accepted");
}

}  // namespace
}  // namespace linx
