// Universal (Cardan) joint: two shafts 30 degrees apart, the driving one turned at a constant rate
// by a motor: the driven shaft's rate swings between cos(30 deg) and 1 / cos(30 deg) times the
// driver's, following omega2 / omega1 = cos b / (1 - sin^2 b cos^2 theta1) (the Cardan ratio).
#include "support.hpp"

#include <gtest/gtest.h>

#include "random_state.hpp"

#include <fmt/format.h>

#include <cmath>
#include <cstdio>
#include <numbers>
#include <random>

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
  c.world.createJoint(
      "hinge",
      JointDef{.name = "bearing1",
               .body1 = c.driver,
               .anchor = Vec3(-0.5, 0, 0),
               .axis = Vec3::UnitX(),
               .coordinates = {CoordinateDef{.motor = JointMotor{.target_velocity = omega}}}});
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
  EXPECT_EQ(w.jointCoordinates(j).size(), 2);
}

TEST(UniversalJoint, CoordinatesAreTheTurnsAboutEachArm) {
  // Body 1 turned by alpha about its arm a1, then (cross and all) by beta about body 2's arm a2,
  // then both bodies by a common rotation G that the joint cannot see: the coordinates read
  // (alpha, beta).
  std::mt19937 rng(5);
  const auto randomQuat = [&] { return test::randomState(rng).pose.orientation; };
  int checked = 0;
  for (int trial = 0; trial < 50; ++trial) {
    const BodyState c1{Pose{Vec3(0.1, 0.2, 0.3), randomQuat()}, Vec3::Zero(), Vec3::Zero()};
    const BodyState c2{Pose{Vec3(-0.4, 0.0, 0.1), randomQuat()}, Vec3::Zero(), Vec3::Zero()};
    const Vec3 a1 = randomQuat() * Vec3::UnitX();
    const Vec3 a2 = a1.unitOrthogonal();
    std::unique_ptr<Joint> j =
        makeJoint("universal",
                  JointDef{.name = "u", .anchor = Vec3::Zero(), .axis = a1, .axis2 = a2}, c1, c2);
    EXPECT_LT(j->coordinates(c1, c2).norm(), 1e-15);
    std::uniform_real_distribution<double> angle(-3.0, 3.0);
    const double alpha = angle(rng), beta = angle(rng);
    const Quat g = randomQuat();
    const Quat turn = Quat(Eigen::AngleAxisd(beta, a2)) * Quat(Eigen::AngleAxisd(alpha, a1));
    const BodyState b1{Pose{c1.pose.position, g * turn * c1.pose.orientation}, {}, {}};
    const BodyState b2{Pose{c2.pose.position, g * c2.pose.orientation}, {}, {}};
    const JointCoordinates q = j->coordinates(b1, b2);
    ASSERT_EQ(q.size(), 2);
    EXPECT_NEAR(q[0], alpha, 1e-12);
    EXPECT_NEAR(q[1], beta, 1e-12);
    ++checked;
  }
  EXPECT_EQ(checked, 50);
}

// A box centred on the joint, held by a universal joint to the world: arm 1 along x turns with the
// box, arm 2 along y is the world's. Started turning about one arm, it turns about that arm alone
// (a principal axis through its centre), under what acts on that coordinate.
struct Gimbal {
  World world;
  BodyId box;
  JointId joint;
  double inertia[2];  // about x and y
};

Gimbal makeGimbal(int coordinate, const CoordinateDef& on_it, double rate) {
  WorldSettings s;
  s.gravity.setZero();
  s.timestep = 1e-3;
  s.sleep.enabled = false;
  Gimbal g{World(s), {}, {}, {}};
  const double m = 2.0;
  const Vec3 size(0.2, 0.4, 0.6);
  BodyDef d = test::boxBody("box", m, size, Vec3::Zero());
  d.angular_velocity = rate * Vec3::Unit(coordinate);
  g.box = g.world.createBody(d);
  JointDef def{.name = "u",
               .body1 = g.box,
               .anchor = Vec3::Zero(),
               .axis = Vec3::UnitX(),
               .axis2 = Vec3::UnitY()};
  def.coordinates[static_cast<std::size_t>(coordinate)] = on_it;
  g.joint = g.world.createJoint("universal", def);
  g.inertia[0] = m * (size.y() * size.y() + size.z() * size.z()) / 12.0;
  g.inertia[1] = m * (size.x() * size.x() + size.z() * size.z()) / 12.0;
  return g;
}

class GimbalCoordinate : public testing::TestWithParam<int> {};

TEST_P(GimbalCoordinate, SpringOscillatesWithItsPeriodAndKeepsItsAmplitude) {
  // x'' = -(k / I) x from x = 0, x' = w0: x = (w0 / omega) sin(omega t), 100 steps a period.
  const int i = GetParam();
  const double w0 = 0.5, period = 0.1;
  Gimbal probe = makeGimbal(i, {}, 0.0);
  const double inertia = probe.inertia[i];
  const double omega = 2.0 * M_PI / period, k = inertia * omega * omega;
  Gimbal g = makeGimbal(i, CoordinateDef{.spring = JointSpring{.stiffness = k}}, w0);
  double highest = 0.0, last = 0.0, crossing = -1.0, first_crossing = -1.0;
  int crossings = 0;
  while (g.world.time() < 10.0 * period - 1e-9) {
    g.world.step();
    const JointCoordinates q = g.world.jointCoordinates(g.joint);
    const double x = q[i];
    EXPECT_LT(std::abs(q[1 - i]), 1e-9);  // the other arm stays still
    highest = std::max(highest, std::abs(x));
    if (last > 0.0 && x <= 0.0) {  // a downward zero crossing, interpolated
      crossing = g.world.time() - g.world.settings().timestep * x / (x - last);
      if (first_crossing < 0.0) first_crossing = crossing;
      ++crossings;
    }
    last = x;
  }
  const double measured = (crossing - first_crossing) / (crossings - 1);
  std::printf("angle%d: amplitude %.6f rad (closed form %.6f), period %.6f s (closed form %.6f)\n",
              i + 1, highest, w0 / omega, measured, period);
  EXPECT_NEAR(highest / (w0 / omega), 1.0, 5e-3);
  EXPECT_NEAR(measured / period, 1.0, 5e-3);
  EXPECT_LT(g.world.maxJointError(), 1e-9);
}

TEST_P(GimbalCoordinate, LimitStopsTheArmAndMotorDrivesIt) {
  const int i = GetParam();
  Gimbal stop = makeGimbal(i, CoordinateDef{.limits = JointLimits{-0.3, 0.3}}, 1.0);
  double highest = 0.0;
  for (int n = 0; n < 1000; ++n) {
    stop.world.step();
    highest = std::max(highest, stop.world.jointCoordinates(stop.joint)[i]);
  }
  EXPECT_NEAR(highest, 0.3, 1e-9);
  EXPECT_NEAR(stop.world.jointCoordinates(stop.joint)[i], 0.3, 1e-6);  // resting on it

  Gimbal motor = makeGimbal(i, CoordinateDef{.motor = JointMotor{.target_velocity = -2.0}}, 0.0);
  for (int n = 0; n < 500; ++n) motor.world.step();
  EXPECT_NEAR(motor.world.jointCoordinates(motor.joint)[i], -2.0 * 0.5, 1e-9);
}

INSTANTIATE_TEST_SUITE_P(Arms, GimbalCoordinate, testing::Values(0, 1),
                         [](const auto& info) { return fmt::format("angle{}", info.param + 1); });

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
    EXPECT_STREQ(e.what(), "axis2: must be perpendicular to axis1 (they are 45 deg apart)");
  }
}

}  // namespace
}  // namespace linx
