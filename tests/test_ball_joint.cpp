// Ball-and-socket joint: a conical pendulum against its closed form, and the joint's readouts.
// Its limit (an upper bound on the angle of its relative rotation, MuJoCo's ball range): an arm
// that gravity swings down comes to rest on it, at the bound's closed-form pose; a bob pushed to
// twice the bound's swing stops at it without making energy; a spin about the arm is held too
// (the whole rotation is bounded, not only the swing).
#include "support.hpp"

#include <gtest/gtest.h>

#include <functional>
#include <numbers>

namespace linx {
namespace {

TEST(Ball, ConicalPendulumKeepsItsHeightAndRate) {
  // A small dense sphere (the lumped mass) on a 1 m massless link at theta = 30 degrees from the
  // downward vertical circles at constant height when w^2 = g / (L cos theta).
  const double L = 1.0, theta = std::numbers::pi / 6, g = 9.81;
  const double w = std::sqrt(g / (L * std::cos(theta)));
  WorldSettings s;
  s.timestep = 1e-3;
  World world(s);
  BodyDef bob;
  bob.name = "bob";
  bob.mass = 1.0;
  bob.inertia = Mat3::Identity() * (2.0 / 5.0 * 0.01 * 0.01);
  bob.position = Vec3(L * std::sin(theta), 0, -L * std::cos(theta));
  bob.linear_velocity = Vec3(0, w * L * std::sin(theta), 0);
  bob.angular_velocity = Vec3(0, 0, w);  // turning with the link
  const BodyId id = world.createBody(bob);
  const JointId j =
      world.createJoint("ball", JointDef{.name = "socket", .body1 = id, .anchor = Vec3::Zero()});
  EXPECT_NEAR(world.jointCoordinates(j)[0], 0.0, 1e-15);

  const double period = 2 * std::numbers::pi / w;
  double worst_height = 0.0, worst_err = 0.0;
  while (world.time() < period - 1e-9) {
    world.step();
    worst_height =
        std::max(worst_height, std::abs(world.body(id).position().z() + L * std::cos(theta)));
    worst_err = std::max(worst_err, world.jointError(j));
  }
  const Vec3 x = world.body(id).position();
  std::printf("one revolution: height %.2e m, back at start %.2e m, joint error %.2e m\n",
              worst_height, (x - bob.position).norm(), worst_err);
  // Semi-implicit Euler on a circular orbit: the radius and rate err by O(h w) ~ 3e-3 relative at
  // most over a revolution; the height, a second-order effect, much less.
  EXPECT_LT(worst_height, 1e-3);
  EXPECT_LT((x - bob.position).norm(), 1e-2);
  EXPECT_LT(worst_err, 1e-4);
  // After one revolution about z, the body has turned by 2 pi: a relative rotation of zero.
  EXPECT_LT(world.jointCoordinates(j)[0], 1e-2);
}

TEST(Ball, FreeChainConservesMomentumAndEnergy) {
  // Two bodies joined by a ball joint, no gravity, thrown: linear momentum exactly conserved
  // (internal forces), kinetic energy conserved. With error reduction alone (post-stabilization
  // off) a velocity-level step only dissipates; with the default post-stabilization the rows take
  // the constraint's curvature, and the energy stays within O(h^2) of its start both ways.
  for (const int post : {0, 2}) {
    WorldSettings s;
    s.gravity.setZero();
    s.solver.post_stabilization = post;
    World w(s);
    BodyDef a = test::boxBody("a", 1.0, Vec3(0.5, 0.1, 0.1), Vec3(0, 0, 0));
    BodyDef b = test::boxBody("b", 3.0, Vec3(0.5, 0.1, 0.1), Vec3(0.5, 0, 0));
    a.linear_velocity = Vec3(0, 1, 0);
    a.angular_velocity = Vec3(1, 0, 2);
    b.linear_velocity = Vec3(0, -0.5, 0.2);
    const BodyId ia = w.createBody(a), ib = w.createBody(b);
    const JointId j = w.createJoint(
        "ball", JointDef{.name = "j", .body1 = ib, .body2 = ia, .anchor = Vec3(0.25, 0, 0)});
    w.step();  // the first step removes the approaching velocity of the anchors
    const Vec3 p0 = w.body(ia).linearVelocity() * 1.0 + w.body(ib).linearVelocity() * 3.0;
    const double e0 = w.energy().kinetic;
    double lo = e0, hi = e0, err = 0.0;
    for (int i = 0; i < 2000; ++i) {
      w.step();
      lo = std::min(lo, w.energy().kinetic);
      hi = std::max(hi, w.energy().kinetic);
      err = std::max(err, w.jointError(j));
    }
    const Vec3 p1 = w.body(ia).linearVelocity() * 1.0 + w.body(ib).linearVelocity() * 3.0;
    std::printf("post-stabilization %d: energy %.6f J in [%+.2e, %+.2e] relative, joint %.2e m\n",
                post, e0, lo / e0 - 1, hi / e0 - 1, err);
    EXPECT_LT((p1 - p0).norm(), 1e-12);
    if (post == 0) {
      EXPECT_LE(hi, e0 * (1 + 1e-9));
      EXPECT_GT(lo, 0.9 * e0);
    } else {
      EXPECT_LT(hi, e0 * (1 + 1e-4));
      EXPECT_GT(lo, e0 * (1 - 1e-4));
      EXPECT_LT(err, 1e-12);
    }
  }
}

}  // namespace
}  // namespace linx

namespace linx {
namespace {

// Per-joint erp and cfm turn a joint into a spring-damper of stiffness k and damping c. For the
// impulse-level rows of linx the mapping is erp = h k / (h k + c), cfm = 1 / (h (h k + c)):
// at rest the row then holds lambda = -h k phi, the impulse of the spring force -k phi.
/// A 1 kg bob 1 m from the origin, where a ball joint limited to `bound` holds it.
BodyId limitedBob(World& world, const Vec3& position, const Vec3& v, const Vec3& w, double bound,
                  JointId& socket) {
  BodyDef bob;
  bob.name = "bob";
  bob.mass = 1.0;
  bob.inertia = Mat3::Identity() * 1e-3;
  bob.position = position;
  bob.linear_velocity = v;
  bob.angular_velocity = w;
  const BodyId id = world.createBody(bob);
  socket = world.createJoint(BallDef{.name = "socket",
                                     .body1 = id,
                                     .anchor = Vec3::Zero(),
                                     .angle = {.limits = JointLimits{0.0, bound}}});
  return id;
}

/// Steps the world `steps` times; the joint's largest angle on the way.
double largestAngle(
    World& world, JointId joint, int steps, const std::function<void()>& each = [] {}) {
  double most = 0.0;
  for (int n = 0; n < steps; ++n) {
    world.step();
    most = std::max(most, world.jointCoordinates(joint)[0]);
    each();
  }
  return most;
}

TEST(Ball, AnArmComesToRestOnItsLimit) {
  // Built horizontal, limited to 0.4 rad: gravity swings it down until the limit holds it, at
  // (cos 0.4, 0, -sin 0.4), still.
  WorldSettings s;
  s.sleep.enabled = false;
  World world(s);
  JointId j;
  const BodyId bob = limitedBob(world, Vec3(1, 0, 0), Vec3::Zero(), Vec3::Zero(), 0.4, j);
  const double most = largestAngle(world, j, 3000);
  const Vec3 rest(std::cos(0.4), 0, -std::sin(0.4));
  std::printf(
      "arm on its 0.4 rad limit: angle %.9f rad (most %.9f), %.2e m from the closed form, "
      "speed %.2e m/s\n",
      world.jointCoordinates(j)[0], most, (world.body(bob).position() - rest).norm(),
      world.body(bob).linearVelocity().norm());
  EXPECT_NEAR(world.jointCoordinates(j)[0], 0.4, 1e-6);
  EXPECT_LT(most, 0.4 + 1e-3);
  EXPECT_LT((world.body(bob).position() - rest).norm(), 1e-5);
  EXPECT_LT(world.body(bob).linearVelocity().norm(), 1e-4);
}

TEST(Ball, ABobPushedPastItsLimitStopsThereWithoutMakingEnergy) {
  // Hanging straight down, pushed sideways hard enough to swing to 0.6 rad free
  // (v^2 = 2 g L (1 - cos 0.6)); limited to 0.3 rad.
  WorldSettings s;
  s.sleep.enabled = false;
  World world(s);
  JointId j;
  limitedBob(world, Vec3(0, 0, -1), Vec3(std::sqrt(2 * 9.81 * (1 - std::cos(0.6))), 0, 0),
             Vec3::Zero(), 0.3, j);
  // Energy above the bottom: 1.7 J at the push. The limit stops the swing dead (an inelastic
  // bound), and from then on it swings between the limit's height and its mirror: what is left
  // is m g L (1 - cos 0.3), the energy of a swing from the bound.
  const auto swing = [&] { return world.energy().total() + 9.81; };
  const double e0 = swing();
  double highest = e0;
  const double most = largestAngle(world, j, 4000, [&] { highest = std::max(highest, swing()); });
  const double left = 9.81 * (1 - std::cos(0.3));
  std::printf(
      "bob pushed to 0.6 rad, limited to 0.3: most %.6f rad; energy %.4f J -> %.4f J "
      "(closed form %.4f), at most %.2e J above the start\n",
      most, e0, swing(), left, highest - e0);
  EXPECT_GT(most, 0.3 - 1e-3);
  EXPECT_LT(most, 0.3 + 1e-3);
  EXPECT_NEAR(swing(), left, 0.01 * left);  // the step's O(h) swing in the energy
  EXPECT_LT(highest - e0, 1e-3 * e0);
}

TEST(Ball, ASpinAboutTheArmIsBoundedToo) {
  // No gravity: the bob spins about its own arm at 2 rad/s with a 1 rad limit: it turns 1 rad
  // and stops there (the whole relative rotation is bounded, twist included).
  WorldSettings s;
  s.gravity = Vec3::Zero();
  s.sleep.enabled = false;
  World world(s);
  JointId j;
  const BodyId bob = limitedBob(world, Vec3(1, 0, 0), Vec3::Zero(), Vec3(2, 0, 0), 1.0, j);
  const double most = largestAngle(world, j, 1000);
  std::printf("spin about the arm, limited to 1 rad: %.9f rad (most %.9f), spin %.2e rad/s\n",
              world.jointCoordinates(j)[0], most, world.body(bob).angularVelocity().norm());
  EXPECT_NEAR(world.jointCoordinates(j)[0], 1.0, 1e-6);
  EXPECT_LT(most, 1.0 + 1e-6);
  EXPECT_LT(world.body(bob).angularVelocity().norm(), 1e-6);
  EXPECT_LT(world.body(bob).position().norm() - 1.0, 1e-9);  // still on its arm
}

TEST(Ball, ItsAngleTakesOnlyAnUpperLimit) {
  World world;
  JointId j;
  const BodyId bob = limitedBob(world, Vec3(1, 0, 0), Vec3::Zero(), Vec3::Zero(), 0.4, j);
  EXPECT_THROW(world.createJoint(BallDef{.name = "a",
                                         .body1 = bob,
                                         .anchor = Vec3::Zero(),
                                         .angle = {.limits = JointLimits{0.1, 0.5}}}),
               std::invalid_argument);
  EXPECT_THROW(world.createJoint(BallDef{
                   .name = "b", .body1 = bob, .anchor = Vec3::Zero(), .angle = {.friction = 1.0}}),
               std::invalid_argument);
  EXPECT_THROW(world.createJoint(BallDef{.name = "c",
                                         .body1 = bob,
                                         .anchor = Vec3::Zero(),
                                         .angle = {.limits = JointLimits{0.0, 4.0}}}),
               std::invalid_argument);
}

TEST(Ball, SoftJointFromErpAndCfmIsASpringDamper) {
  const double m = 2.0, k = 5000.0, c = 20.0, g = 9.81, h = 1e-3;
  WorldSettings s;
  s.timestep = h;
  World w(s);
  BodyDef d = test::boxBody("weight", m, Vec3(0.1, 0.1, 0.1), Vec3(0, 0, -0.5));
  const BodyId id = w.createBody(d);
  w.createJoint("ball", JointDef{.name = "spring",
                                 .body1 = id,
                                 .anchor = Vec3(0, 0, -0.5),
                                 .erp = h * k / (h * k + c),
                                 .cfm = 1.0 / (h * (h * k + c))});
  // Released at the unstretched length: it oscillates about the static sag m g / k at
  // sqrt(k / m) (damping ratio c / (2 sqrt(k m)) = 0.1) and settles there.
  std::vector<double> t, y;
  for (int i = 0; i < 3000; ++i) {
    w.step();
    t.push_back(w.time());
    y.push_back(w.body(id).position().z() + 0.5 + m * g / k);
  }
  const auto crossings = test::upwardCrossings(t, y);
  ASSERT_GE(crossings.size(), 3u);
  const double period = crossings[2] - crossings[1];
  const double wn = std::sqrt(k / m), zeta = c / (2 * std::sqrt(k * m));
  const double damped = 2 * std::numbers::pi / (wn * std::sqrt(1 - zeta * zeta));
  for (int i = 0; i < 5000; ++i) w.step();
  const double sag = -0.5 - w.body(id).position().z();
  std::printf("sag %.6e m (m g / k = %.6e), period %.5f s (damped closed form %.5f s)\n", sag,
              m * g / k, period, damped);
  EXPECT_NEAR(sag, m * g / k, 1e-9);           // exact at rest: lambda = -h k phi
  EXPECT_NEAR(period, damped, 0.01 * damped);  // implicit-in-time spring: O(h w) phase
  // Projection pulls drift out, not a spring's stretch: the soft joint keeps its sag.
  w.settings().solver.projection = true;
  for (int i = 0; i < 100; ++i) w.step();
  EXPECT_NEAR(-0.5 - w.body(id).position().z(), m * g / k, 1e-9);

  const SoftRow soft = springDamper(k, c, h);
  EXPECT_DOUBLE_EQ(soft.erp, h * k / (h * k + c));
  EXPECT_DOUBLE_EQ(soft.cfm, 1.0 / (h * (h * k + c)));
}

}  // namespace
}  // namespace linx
