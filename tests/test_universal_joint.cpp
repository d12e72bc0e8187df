// Universal (Cardan) joint: two shafts 30 degrees apart, the driving one turned at a constant rate
// by a motor: the driven shaft's rate swings between cos(30 deg) and 1 / cos(30 deg) times the
// driver's, following omega2 / omega1 = cos b / (1 - sin^2 b cos^2 theta1) (the Cardan ratio).
#include "support.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>

namespace linx {
namespace {

constexpr double kPi = std::numbers::pi;

struct Cardan {
  World world;
  BodyId driver, driven;
  JointId cross;
  Vec3 axis2;  // the driven shaft's axis
};

// The driver along x ends at the origin, its yoke's arm along z (in the shafts' plane, x-z); the
// driven shaft leaves the origin along (cos b, 0, sin b), its arm along -y (perpendicular to both
// that shaft and the first arm). Both shafts turn in hinges to the world about their own axes.
Cardan makeCardan(double beta, double omega, SolverType type) {
  WorldSettings s;
  s.gravity.setZero();
  s.timestep = 1e-3;
  s.solver.type = type;
  Cardan c{World(s), {}, {}, {}, Vec3(std::cos(beta), 0, std::sin(beta))};
  c.driver =
      c.world.createBody(test::boxBody("driver", 1.0, Vec3(1.0, 0.05, 0.05), Vec3(-0.5, 0, 0)));
  BodyDef d = test::boxBody("driven", 1.0, Vec3(1.0, 0.05, 0.05), 0.5 * c.axis2);
  d.orientation = Quat(Eigen::AngleAxisd(-beta, Vec3::UnitY()));  // its length along axis2
  c.driven = c.world.createBody(d);
  c.world.createJoint("hinge", JointDef{.name = "bearing1",
                                        .body1 = c.driver,
                                        .anchor = Vec3(-0.5, 0, 0),
                                        .axis = Vec3::UnitX(),
                                        .motor = JointMotor{.target_velocity = omega}});
  c.world.createJoint(
      "hinge",
      JointDef{.name = "bearing2", .body1 = c.driven, .anchor = 0.5 * c.axis2, .axis = c.axis2});
  c.cross = c.world.createJoint("universal", JointDef{.name = "cross",
                                                      .body1 = c.driver,
                                                      .body2 = c.driven,
                                                      .anchor = Vec3::Zero(),
                                                      .axis = Vec3::UnitZ(),
                                                      .axis2 = -Vec3::UnitY()});
  return c;
}

class CardanRatio : public testing::TestWithParam<SolverType> {};

TEST_P(CardanRatio, DrivenShaftFollowsTheCardanRatio) {
  const double beta = kPi / 6.0, omega = 2.0 * kPi;
  Cardan c = makeCardan(beta, omega, GetParam());
  double lowest = kInfinity, highest = 0.0, worst = 0.0;
  for (int i = 0; i < 1000; ++i) {  // one turn of the driver
    c.world.step();
    const double w1 = c.world.body(c.driver).angularVelocity().dot(Vec3::UnitX());
    const double w2 = c.world.body(c.driven).angularVelocity().dot(c.axis2);
    // theta1 from where the driver's arm lies in the shafts' plane (z at the start).
    const double theta1 = omega * c.world.time();
    const double cb = std::cos(beta), sb = std::sin(beta), ct = std::cos(theta1);
    worst = std::max(worst, std::abs(w2 / w1 - cb / (1.0 - sb * sb * ct * ct)));
    lowest = std::min(lowest, w2 / w1);
    highest = std::max(highest, w2 / w1);
  }
  std::printf(
      "ratio from %.6f to %.6f (cos b %.6f, 1 / cos b %.6f), worst against the closed form "
      "%.2e, joint error %.2e m\n",
      lowest, highest, std::cos(beta), 1.0 / std::cos(beta), worst, c.world.maxJointError());
  EXPECT_NEAR(lowest, std::cos(beta), 1e-4);
  EXPECT_NEAR(highest, 1.0 / std::cos(beta), 1e-4);
  EXPECT_LT(worst, 2e-3);  // the rate at the step's end against theta1 at it: O(omega h)
  EXPECT_LT(c.world.maxJointError(), 1e-9);
}

INSTANTIATE_TEST_SUITE_P(Solvers, CardanRatio, testing::Values(SolverType::Auto, SolverType::Exact),
                         [](const auto& info) {
                           return std::string(info.param == SolverType::Auto ? "auto" : "exact");
                         });

TEST(UniversalJoint, HoldsItsPointAndItsCrossUnderATumble) {
  // Two bodies joined by a universal joint tumble without gravity. The anchor stays common and the
  // arms perpendicular; the joint's forces are internal (equal and opposite at the anchor, and a
  // couple), so the total linear momentum stays what it was to round-off, the angular momentum and
  // the energy up to the step's first-order error.
  WorldSettings s;
  s.gravity.setZero();
  World w(s);
  BodyDef a = test::boxBody("a", 2.0, Vec3(0.3, 0.2, 0.1), Vec3(0, 0, 0));
  a.angular_velocity = Vec3(1.0, -2.0, 0.5);
  BodyDef b = test::boxBody("b", 1.0, Vec3(0.1, 0.4, 0.2), Vec3(0, 0, -0.4));
  b.linear_velocity = Vec3(0.3, 0, 0);
  const BodyId ia = w.createBody(a), ib = w.createBody(b);
  const JointId j = w.createJoint("universal", JointDef{.name = "u",
                                                        .body1 = ia,
                                                        .body2 = ib,
                                                        .anchor = Vec3(0, 0, -0.2),
                                                        .axis = Vec3(1, 1, 0),
                                                        .axis2 = Vec3(1, -1, 0.5)});
  const auto momentum = [&] {
    Vec3 p = Vec3::Zero(), l = Vec3::Zero();
    for (const BodyId id : {ia, ib}) {
      const Body& body = w.body(id);
      p += body.mass() * body.linearVelocity();
      l += body.position().cross(body.mass() * body.linearVelocity()) + body.angularMomentum();
    }
    return std::pair{p, l};
  };
  const auto energy = [&] { return w.body(ia).kineticEnergy() + w.body(ib).kineticEnergy(); };
  const auto [p0, l0] = momentum();
  // The bodies start with velocities that open the joint: the first step takes them back onto
  // it, as an inelastic collision does (momentum kept, 3 % of the energy lost). From then on the
  // energy is conserved.
  w.step();
  const double e1 = energy();
  const double l1 = (momentum().second - l0).norm() / l0.norm();
  double worst = 0.0, dp = 0.0, dl = 0.0, de = 0.0;
  for (int i = 0; i < 2000; ++i) {
    w.step();
    worst = std::max(worst, w.jointError(j));
    const auto [p, l] = momentum();
    dp = std::max(dp, (p - p0).norm());
    dl = std::max(dl, (l - l0).norm() / l0.norm());
    de = std::max(de, std::abs(energy() - e1) / e1);
  }
  std::printf(
      "largest joint error %.2e, momentum change %.2e kg m/s, angular momentum %.2e "
      "(%.2e in the first step), energy %.2e (relative)\n",
      worst, dp, dl, l1, de);
  EXPECT_LT(worst, 1e-9);
  EXPECT_LT(dp, 1e-12);
  // First order in h: impulses at the step's start poses, positions projected after the step.
  EXPECT_LT(dl, 5e-4);
  EXPECT_LT(de, 5e-4);
  EXPECT_FALSE(w.jointCoordinate(j).has_value());
}

TEST(UniversalJoint, ArmsMustBePerpendicular) {
  World w;
  const BodyId a = w.createBody(test::boxBody("a", 1.0, Vec3(1, 1, 1), Vec3::Zero()));
  try {
    w.createJoint("universal", JointDef{.name = "u",
                                        .body1 = a,
                                        .anchor = Vec3::Zero(),
                                        .axis = Vec3::UnitX(),
                                        .axis2 = Vec3(1, 1, 0)});
    ADD_FAILURE() << "accepted arms 45 degrees apart";
  } catch (const std::invalid_argument& e) {
    EXPECT_STREQ(e.what(), "axis2: must be perpendicular to axis1 (the cross's two arms)");
  }
}

}  // namespace
}  // namespace linx
