// Frictional contact against closed forms: the sticking and sliding thresholds of a block on an
// incline, rolling without slipping (5/7 g sin(theta) for a solid sphere, 2/3 for a cylinder), the
// rebound height of a ball with restitution e (e^2 of the drop), and momentum in a frictionless
// head-on collision. Each test states its tolerance and why.
#include "support.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <numbers>

namespace linx {
namespace {

constexpr double kG = 9.81;

/// A static plane through the origin with the given unit normal; friction and restitution of its
/// material.
BodyDef ground(const Vec3& normal, double friction, double restitution = 0.0) {
  BodyDef g;
  g.name = "ground";
  g.is_static = true;
  g.shapes.push_back(ShapeDef{.type = ShapeType::Plane,
                              .normal = normal,
                              .friction = friction,
                              .restitution = restitution});
  return g;
}

/// An incline of angle theta about the y axis: normal n = (sin, 0, cos), downhill d = (cos, 0,
/// -sin); the rotation about y by theta takes a body's z axis to n.
struct Slope {
  double theta;
  Vec3 n() const { return Vec3(std::sin(theta), 0, std::cos(theta)); }
  Vec3 down() const { return Vec3(std::cos(theta), 0, -std::sin(theta)); }
  Quat tilt() const { return Quat(Eigen::AngleAxisd(theta, Vec3::UnitY())); }
};

World makeWorld(SolverType type, double h = 1e-3) {
  WorldSettings s;
  s.timestep = h;
  s.solver.type = type;
  if (type == SolverType::Soft) s.solver.substeps = 4;
  return World(s);
}

/// A 1 kg box of 0.4 x 0.3 x 0.2 m resting on the incline (its bottom face on the plane).
BodyId addBlock(World& world, const Slope& slope, double friction) {
  BodyDef d = test::boxBody("block", 1.0, Vec3(0.4, 0.3, 0.2), 0.1 * slope.n());
  d.orientation = slope.tilt();
  d.shapes[0].friction = friction;
  return world.createBody(d);
}

class Incline : public testing::TestWithParam<SolverType> {};
class InclineStick : public testing::TestWithParam<SolverType> {};

// mu = 0.5 against tan(theta) = 0.95 mu: the friction needed, m g sin(theta), is 95 % of the bound
// mu m g cos(theta), so the block must not move at all. The bound is 0.1 mm over 2 s: the only
// motion allowed is the settling of the contact within its slop.
TEST_P(InclineStick, BlockSticksBelowTheFrictionAngle) {
  const double mu = 0.5;
  const Slope slope{std::atan(0.95 * mu)};
  World world = makeWorld(GetParam());
  world.createBody(ground(slope.n(), mu));
  const BodyId block = addBlock(world, slope, mu);
  const Vec3 x0 = world.body(block).position();
  for (int i = 0; i < 2000; ++i) world.step();
  const double moved = (world.body(block).position() - x0).norm();
  std::printf("stick: tan(theta) = 0.95 mu, moved %.3e m in 2 s\n", moved);
  EXPECT_LT(moved, 1e-4);
}

// Beyond the friction angle the block slides with a = g (sin(theta) - mu cos(theta)). The discrete
// velocity after n steps is exactly a n h under a constant net force, so 1 % is loose: it covers
// the first steps in which the contact settles. The last case lies just beyond the threshold
// (tan(theta) = 1.05 mu): it must slide, however slowly; a bound held anywhere but at mu lambda_n
// would stop it.
TEST_P(Incline, BlockSlidesWithCoulombFriction) {
  constexpr double kDeg = std::numbers::pi / 180.0;
  for (const auto& [theta, mu] : {std::pair{30.0 * kDeg, 0.3}, std::pair{40.0 * kDeg, 0.5},
                                  std::pair{std::atan(0.525), 0.5}}) {
    const Slope slope{theta};
    World world = makeWorld(GetParam());
    world.createBody(ground(slope.n(), mu));
    const BodyId block = addBlock(world, slope, mu);
    for (int i = 0; i < 1000; ++i) world.step();
    const double a = world.body(block).linearVelocity().dot(slope.down()) / world.time();
    const double expected = kG * (std::sin(slope.theta) - mu * std::cos(slope.theta));
    std::printf("slide: theta %.2f deg, mu %.1f: a = %.5f, closed form %.5f (%.2e relative)\n",
                theta / kDeg, mu, a, expected, std::abs(a / expected - 1.0));
    EXPECT_NEAR(a, expected, 0.01 * expected);
    // It slides straight down: no sideways drift, no lift-off.
    EXPECT_LT(std::abs(world.body(block).linearVelocity().y()), 1e-6);
    EXPECT_LT(std::abs(world.body(block).position().dot(slope.n()) - 0.1), 1e-3);
  }
}

INSTANTIATE_TEST_SUITE_P(Solvers, Incline,
                         testing::Values(SolverType::Auto, SolverType::Exact, SolverType::Pgs),
                         [](const auto& info) { return std::string(solverTypeName(info.param)); });

// The soft step too. It is left out of the sliding test: one sweep a substep leaves the four
// corners' normal impulses unequal, and a sliding block drifts sideways (2 cm/s after 1 s on the
// 30 degree slope) and, just past the friction angle, slides 9 % too slowly (docs/solver.md).
INSTANTIATE_TEST_SUITE_P(Solvers, InclineStick,
                         testing::Values(SolverType::Auto, SolverType::Exact, SolverType::Pgs,
                                         SolverType::Soft),
                         [](const auto& info) { return std::string(solverTypeName(info.param)); });

class Rolling : public testing::TestWithParam<SolverType> {};

// A solid sphere rolling without slipping: a = g sin(theta) / (1 + I / (m r^2)) = 5/7 g sin(theta).
// Friction 0.8 is far above the 2/7 tan(theta) = 0.10 needed. 1 % as the issue asks; the discrete
// motion is exact up to the contact's settling.
TEST_P(Rolling, SolidSphereAndCylinderRollAtTheirClosedFormAcceleration) {
  const Slope slope{20.0 * std::numbers::pi / 180.0};
  const double r = 0.1, m = 2.0;
  for (const bool cylinder : {false, true}) {
    World world = makeWorld(GetParam());
    world.createBody(ground(slope.n(), 0.8));
    BodyDef d;
    d.name = cylinder ? "cylinder" : "sphere";
    d.mass = m;
    d.position = r * slope.n();
    if (cylinder) {
      // Axis along y (perpendicular to the slope's fall line): local z turned onto y.
      const double l = 0.3;
      d.orientation = Quat(Eigen::AngleAxisd(-std::numbers::pi / 2, Vec3::UnitX()));
      d.inertia = Vec3(m * (3 * r * r + l * l) / 12, m * (3 * r * r + l * l) / 12, 0.5 * m * r * r)
                      .asDiagonal();
      d.shapes.push_back(
          ShapeDef{.type = ShapeType::Cylinder, .radius = r, .length = l, .friction = 0.8});
    } else {
      d.inertia = Mat3::Identity() * 0.4 * m * r * r;
      d.shapes.push_back(ShapeDef{.type = ShapeType::Sphere, .radius = r, .friction = 0.8});
    }
    const BodyId body = world.createBody(d);
    for (int i = 0; i < 1000; ++i) world.step();
    const Body& b = world.body(body);
    const double a = b.linearVelocity().dot(slope.down()) / world.time();
    const double expected = (cylinder ? 2.0 / 3.0 : 5.0 / 7.0) * kG * std::sin(slope.theta);
    // Rolling: the contact point does not slip, v = w x (r n) ... i.e. |v| = |w| r.
    const double slip = (b.linearVelocity() + b.angularVelocity().cross(-r * slope.n())).norm();
    std::printf("%s: a = %.5f, closed form %.5f (%.2e relative), slip %.2e m/s\n", d.name.c_str(),
                a, expected, std::abs(a / expected - 1.0), slip);
    EXPECT_NEAR(a, expected, 0.01 * expected);
    EXPECT_LT(slip, 1e-3);
  }
}

INSTANTIATE_TEST_SUITE_P(Solvers, Rolling,
                         testing::Values(SolverType::Auto, SolverType::Exact, SolverType::Pgs,
                                         SolverType::Soft),
                         [](const auto& info) { return std::string(solverTypeName(info.param)); });

// A ball of restitution e dropped from rest at height H (its bottom) rebounds to e^2 H: the
// rebound speed is e times the impact speed sqrt(2 g H). 2 % as the issue asks; the step's own
// error is about h sqrt(2 g H) / H ~ 0.5 %.
TEST(Restitution, BallReboundsToESquaredOfItsDropHeight) {
  const double r = 0.05, H = 1.0;
  for (const auto& [type, e] :
       {std::pair{SolverType::Exact, 0.5}, std::pair{SolverType::Exact, 0.8},
        std::pair{SolverType::Soft, 0.5}, std::pair{SolverType::Soft, 0.8}}) {
    SCOPED_TRACE(std::string(solverTypeName(type)));
    World world = makeWorld(type);
    world.createBody(ground(Vec3::UnitZ(), 0.5, e));
    BodyDef d;
    d.name = "ball";
    d.mass = 0.1;
    d.inertia = Mat3::Identity() * 0.4 * 0.1 * r * r;
    d.position = Vec3(0, 0, r + H);
    d.shapes.push_back(ShapeDef{.type = ShapeType::Sphere, .radius = r, .restitution = e});
    const BodyId ball = world.createBody(d);
    double peak = 0.0;
    bool bounced = false;
    for (int i = 0; i < 2000; ++i) {
      world.step();
      const Body& b = world.body(ball);
      if (b.linearVelocity().z() > 0.0) bounced = true;
      if (bounced) {
        peak = std::max(peak, b.position().z() - r);
        if (b.linearVelocity().z() < 0.0) break;  // past the top of the first rebound
      }
    }
    std::printf("e = %.1f: rebound %.5f m, e^2 H = %.5f m (%.2e relative)\n", e, peak, e * e * H,
                std::abs(peak / (e * e * H) - 1.0));
    EXPECT_TRUE(bounced);
    EXPECT_NEAR(peak, e * e * H, 0.02 * e * e * H);
  }
}

// A perfectly elastic ball (e = 1) dropped from rest at height H keeps its energy: every rebound
// rises to H again. The bounce reverses the ball where it is when the gap would close, so it
// reflects the speed the ball had there, before the step's gravity; the semi-implicit Euler step
// is then symmetric in time about the bounce, and each apex returns to H to 3e-9. (Reflecting the
// speed after gravity gained m g v h a bounce: 0.85 % of the energy each time for H = 0.4 m at
// h = 1 ms, 5 % after six.) The soft step bounces after its substeps, from the ball's speed when
// its spring began to act, and loses 0.7 % of the height a bounce: it may lose, never gain.
TEST(Restitution, ElasticBallReturnsToItsDropHeightAtEveryBounce) {
  const double r = 0.1, H = 0.4;
  for (const SolverType type :
       {SolverType::Auto, SolverType::Pgs, SolverType::Exact, SolverType::Soft}) {
    SCOPED_TRACE(std::string(solverTypeName(type)));
    World world = makeWorld(type);
    world.createBody(ground(Vec3::UnitZ(), 0.5, 1.0));
    BodyDef d;
    d.name = "ball";
    d.mass = 1.0;
    d.inertia = Mat3::Identity() * 0.4 * r * r;
    d.position = Vec3(0, 0, r + H);
    d.shapes.push_back(ShapeDef{.type = ShapeType::Sphere, .radius = r, .restitution = 1.0});
    const BodyId ball = world.createBody(d);
    std::vector<double> apexes;
    double last_vz = 0.0, worst = 0.0;
    for (int i = 0; i < 4000; ++i) {  // 4 s: six bounces
      world.step();
      const Body& b = world.body(ball);
      const double vz = b.linearVelocity().z();
      if (last_vz > 0.0 && vz <= 0.0) apexes.push_back(b.position().z() - r);
      last_vz = vz;
    }
    for (const double apex : apexes) worst = std::max(worst, std::abs(apex / H - 1.0));
    std::printf("%s: %zu apexes, the last %.5f m, worst %.2e relative to H = %.1f m\n",
                std::string(solverTypeName(type)).c_str(), apexes.size(),
                apexes.empty() ? 0.0 : apexes.back(), worst, H);
    EXPECT_GE(apexes.size(), 5u);
    if (type == SolverType::Soft) {
      for (const double apex : apexes) EXPECT_LE(apex, H * (1.0 + 1e-9));
      EXPECT_LE(worst, 0.1);
    } else {
      EXPECT_LE(worst, 1e-7);
    }
  }
}

// Two free spheres meet head on without friction or gravity. Momentum is conserved to round-off
// whatever the restitution (the contact impulse is internal); with e = 1 the velocities after
// are the elastic closed form v1' = ((m1 - m2) v1 + 2 m2 v2) / (m1 + m2), and with e = 0 both
// move at the common velocity.
TEST(Collision, FrictionlessHeadOnCollisionConservesMomentum) {
  for (const SolverType type : {SolverType::Exact, SolverType::Pgs, SolverType::Soft}) {
    for (const double e : {0.0, 1.0}) {
      WorldSettings s;
      s.gravity = Vec3::Zero();
      s.timestep = 1e-3;
      s.solver.type = type;
      World world(s);
      const double m1 = 1.0, m2 = 3.0, v1 = 2.0, v2 = -1.0, r = 0.1;
      auto sphere = [&](const char* name, double m, double x, double v) {
        BodyDef d;
        d.name = name;
        d.mass = m;
        d.inertia = Mat3::Identity() * 0.4 * m * r * r;
        d.position = Vec3(x, 0, 0);
        d.linear_velocity = Vec3(v, 0, 0);
        d.shapes.push_back(
            ShapeDef{.type = ShapeType::Sphere, .radius = r, .friction = 0.0, .restitution = e});
        return world.createBody(d);
      };
      const BodyId a = sphere("a", m1, -0.5, v1), b = sphere("b", m2, 0.5, v2);
      const Vec3 p0 = m1 * world.body(a).linearVelocity() + m2 * world.body(b).linearVelocity();
      double worst = 0.0;
      for (int i = 0; i < 600; ++i) {
        world.step();
        const Vec3 p = m1 * world.body(a).linearVelocity() + m2 * world.body(b).linearVelocity();
        worst = std::max(worst, (p - p0).norm());
      }
      const double va = world.body(a).linearVelocity().x(), vb = world.body(b).linearVelocity().x();
      const double common = (m1 * v1 + m2 * v2) / (m1 + m2);
      const double ea = e == 1.0 ? ((m1 - m2) * v1 + 2 * m2 * v2) / (m1 + m2) : common;
      const double eb = e == 1.0 ? ((m2 - m1) * v2 + 2 * m1 * v1) / (m1 + m2) : common;
      std::printf("%s e = %.0f: momentum error %.2e, v = (%.6f, %.6f), closed form (%.6f, %.6f)\n",
                  std::string(solverTypeName(type)).c_str(), e, worst, va, vb, ea, eb);
      EXPECT_LT(worst, 1e-12);
      EXPECT_NEAR(va, ea, 1e-6);
      EXPECT_NEAR(vb, eb, 1e-6);
      EXPECT_LT(world.body(a).linearVelocity().tail<2>().norm(), 1e-12);  // head on: stays on x
    }
  }
}

// Speculative contacts: rows for a gap the bodies can close within the step, and only those.
// A ball falling at 12 m/s with h = 1/60 s covers 0.2 m per step, four times its radius: it must
// stop at the plane (penetration within the 0.5 mm slop plus the erp's one-step lag, never
// through it), because its row exists while the gap is still open. Two balls falling side by side,
// 2 cm apart (beyond the 1 cm margin, well within the 0.4 m that their swept boxes reach), close
// nothing along their normal: no contact may be reported between them, and none may push them
// apart (their horizontal velocities stay exactly zero).
TEST(SpeculativeContact, FastBallStopsAtThePlaneAndSideBySideBallsGetNoRow) {
  const double r = 0.05, h = 1.0 / 60.0;
  WorldSettings s;
  s.timestep = h;
  World world(s);
  world.createBody(ground(Vec3::UnitZ(), 0.5));
  auto ball = [&](const char* name, const Vec3& x, const Vec3& v) {
    BodyDef d;
    d.name = name;
    d.mass = 0.1;
    d.inertia = Mat3::Identity() * 0.4 * 0.1 * r * r;
    d.position = x;
    d.linear_velocity = v;
    d.shapes.push_back(ShapeDef{.type = ShapeType::Sphere, .radius = r, .friction = 0.5});
    return world.createBody(d);
  };
  const BodyId fast = ball("fast", Vec3(-1, 0, r + 0.5), Vec3(0, 0, -12));
  const BodyId left = ball("left", Vec3(1, 0, 4.0), Vec3(0, 0, -12));
  const BodyId right = ball("right", Vec3(1 + 2 * r + 0.02, 0, 4.0), Vec3(0, 0, -12));
  double lowest = 1.0;
  bool side_contact = false;
  for (int i = 0; i < 12; ++i) {  // the pair falls 2.6 m from 4 m: still in the air
    world.step();
    lowest = std::min(lowest, world.body(fast).position().z());
    for (const Contact& c : world.contacts())
      if ((c.body1 == left && c.body2 == right) || (c.body1 == right && c.body2 == left))
        side_contact = true;
  }
  std::printf("fast ball: lowest centre %.6f m (radius %.2f); pair z = %.3f m\n", lowest, r,
              world.body(left).position().z());
  EXPECT_GT(lowest, r - 2e-3);
  EXPECT_LT(std::abs(world.body(fast).position().z() - r), 2e-3);  // resting on the plane
  EXPECT_GT(world.body(left).position().z(), r + 0.1);             // the pair has not landed yet
  EXPECT_FALSE(side_contact);
  EXPECT_EQ(world.body(left).linearVelocity().head<2>().norm(), 0.0);
  EXPECT_EQ(world.body(right).linearVelocity().head<2>().norm(), 0.0);
}

// A contact given a stiffness k and damping c instead of erp and cfm is a spring: a ball resting on
// it sinks by m g / k beyond the slop (the slop is never corrected), to 1e-9 m once the damped
// motion has died out (c is set near critical: 2 sqrt(k m)).
TEST(SoftContact, BallSinksByItsWeightOverTheStiffness) {
  WorldSettings s;
  s.sleep.enabled = false;  // settle to the equilibrium, not to the rest threshold
  s.contact.stiffness = 1e4;
  s.contact.damping = 200.0;
  World world(s);
  world.createBody(ground(Vec3::UnitZ(), 0.5));
  const double r = 0.1, m = 1.0;
  BodyDef d;
  d.name = "ball";
  d.mass = m;
  d.inertia = Mat3::Identity() * 0.4 * m * r * r;
  d.position = Vec3(0, 0, r);
  d.shapes.push_back(ShapeDef{.type = ShapeType::Sphere, .radius = r});
  const BodyId ball = world.createBody(d);
  for (int i = 0; i < 3000; ++i) world.step();
  const double sink = r - world.body(ball).position().z();
  const double expected = m * kG / *s.contact.stiffness + s.contact.slop;
  std::printf("soft contact: sink %.9f m, m g / k + slop = %.9f m\n", sink, expected);
  EXPECT_NEAR(sink, expected, 1e-9);
}

/// Two overlapping spheres, the second 0.15 m above the first (radii 0.1: 5 cm of overlap), in
/// zero gravity: whether they push apart tells whether their shapes collide.
bool pushApart(const std::function<void(World&, BodyId, BodyId, ShapeDef&, ShapeDef&)>& setup) {
  WorldSettings s;
  s.gravity = Vec3::Zero();
  World world(s);
  ShapeDef sa{.type = ShapeType::Sphere, .radius = 0.1}, sb = sa;
  BodyDef a, b;
  a.name = "a";
  b.name = "b";
  a.mass = b.mass = 1.0;
  a.inertia = b.inertia = Mat3::Identity();
  b.position = Vec3(0, 0, 0.15);
  // The filters must be set before the bodies exist; joints after.
  setup(world, kWorldBody, kWorldBody, sa, sb);
  a.shapes = {sa};
  b.shapes = {sb};
  const BodyId ia = world.createBody(a), ib = world.createBody(b);
  setup(world, ia, ib, sa, sb);
  for (int i = 0; i < 10; ++i) world.step();
  return world.body(ib).position().z() > 0.15 + 1e-4;
}

TEST(CollisionFilter, GroupsMasksAndJoints) {
  // By default they collide.
  EXPECT_TRUE(pushApart([](World&, BodyId, BodyId, ShapeDef&, ShapeDef&) {}));
  // a's mask excludes b's group: no contact either way round.
  EXPECT_FALSE(pushApart([](World&, BodyId, BodyId, ShapeDef& a, ShapeDef& b) {
    a.mask = ~0x2u;
    b.group = 0x2u;
  }));
  EXPECT_TRUE(pushApart([](World&, BodyId, BodyId, ShapeDef& a, ShapeDef& b) {
    a.mask = ~0x4u;
    b.group = 0x2u;
  }));
  // Joined by a slider along z (which lets them part): no contact, unless the joint sets collide.
  for (const bool collide : {false, true}) {
    EXPECT_EQ(
        pushApart([collide](World& w, BodyId a, BodyId b, ShapeDef&, ShapeDef&) {
          if (a.isWorld()) return;
          w.createJoint(
              "slider",
              JointDef{
                  .name = "j", .body1 = b, .body2 = a, .axis = Vec3::UnitZ(), .collide = collide});
        }),
        collide);
  }
}

// A body whose shapes cannot be prepared (a flat hull) is rejected and leaves nothing behind: the
// next body's shapes collide as its own.
TEST(CollisionFilter, RejectedBodyLeavesNoTrace) {
  World world;
  world.createBody(ground(Vec3::UnitZ(), 0.5));
  BodyDef flat;
  flat.name = "flat";
  flat.mass = 1.0;
  flat.inertia = Mat3::Identity();
  flat.shapes = {ShapeDef{.type = ShapeType::Box, .size = Vec3::Ones()},
                 ShapeDef{.type = ShapeType::Convex,
                          .points = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(1, 1, 0)}}};
  EXPECT_THROW(world.createBody(flat), std::invalid_argument);
  BodyDef ball;
  ball.name = "ball";
  ball.mass = 1.0;
  ball.inertia = Mat3::Identity();
  ball.position = Vec3(0, 0, 0.1);
  ball.shapes = {ShapeDef{.type = ShapeType::Sphere, .radius = 0.1}};
  const BodyId id = world.createBody(ball);
  for (int i = 0; i < 500; ++i) world.step();
  EXPECT_NEAR(world.body(id).position().z(), 0.1, 1e-3);  // resting on the ground, not through it
}

// Resting bodies keep the last step's contact points (the narrowphase is skipped for a pair of
// bodies that have not moved), so the points must follow whatever moves one of them between steps:
// the geometry is the truth. A 0.2 m cube falls asleep on the ground; its four points are the
// corners of its bottom face. Moved sideways with setPose while asleep (no wake), its points are
// under its new place; lifted 1 m, it has none; put back and the ground lowered 5 cm, none; the
// speculative margin widened past the gap, its points come back 5 cm below it.
TEST(SleepingContacts, PointsFollowBodiesMovedBetweenSteps) {
  for (const SolverType type : {SolverType::Auto, SolverType::Soft}) {
    World world = makeWorld(type, 1.0 / 60.0);
    const BodyId ground_id = world.createBody(ground(Vec3::UnitZ(), 0.5));
    const BodyId box =
        world.createBody(test::boxBody("box", 1.0, Vec3::Constant(0.2), Vec3(0.0, 0.0, 0.1)));
    for (int i = 0; i < 600 && !world.isAsleep(box); ++i) world.step();
    ASSERT_TRUE(world.isAsleep(box));
    const auto cornersUnder = [&](double x, double gap) {
      const auto contacts = world.contacts();
      ASSERT_EQ(contacts.size(), 4u);
      for (const Contact& c : contacts) {
        EXPECT_NEAR(std::abs(c.point.x() - x), 0.1, 1e-3);
        EXPECT_NEAR(std::abs(c.point.y()), 0.1, 1e-3);
        EXPECT_NEAR(-c.depth, gap, 1e-3);
      }
    };
    world.step();
    cornersUnder(0.0, 0.0);

    Pose pose = world.body(box).pose();
    pose.position.x() += 0.5;
    world.body(box).setPose(pose);
    world.step();
    cornersUnder(0.5, 0.0);

    pose.position.z() += 1.0;
    world.body(box).setPose(pose);
    world.step();
    EXPECT_TRUE(world.contacts().empty());

    pose.position.z() -= 1.0;
    world.body(box).setPose(pose);
    Pose plane = world.body(ground_id).pose();
    plane.position.z() -= 0.05;
    world.body(ground_id).setPose(plane);
    world.step();
    EXPECT_TRUE(world.contacts().empty());

    world.settings().contact.margin = 0.1;
    world.step();
    cornersUnder(0.5, 0.05);
  }
}

}  // namespace
}  // namespace linx
