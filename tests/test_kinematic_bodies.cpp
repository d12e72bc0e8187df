// Kinematic bodies: infinite mass, moving at their own velocity, pushing and carrying dynamic
// bodies. Closed forms: a box set down on a belt moving at v slides against friction mu g until it
// moves with the belt, after v / (mu g), having fallen behind it by v^2 / (2 mu g); a lift rising
// at a constant speed carries a box at its speed; a pendulum hung from a pivot moving at a constant
// velocity (and moving with it) hangs still (Galilean invariance); nothing changes the kinematic
// bodies' own motion.
#include "support.hpp"

#include <linx/scene.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <stdexcept>

namespace linx {
namespace {

constexpr double kG = 9.81;

ShapeDef box(const Vec3& size, double friction) {
  ShapeDef s;
  s.type = ShapeType::Box;
  s.size = size;
  s.friction = friction;
  return s;
}

class KinematicBody : public testing::TestWithParam<SolverType> {};

TEST_P(KinematicBody, BeltCarriesABoxAfterItSlidesToItsSpeed) {
  constexpr double v = 0.5, mu = 0.5, h = 1e-3;
  WorldSettings s;
  s.timestep = h;
  s.solver.type = GetParam();
  World world(s);
  BodyDef belt;
  belt.name = "belt";
  belt.kinematic = true;
  belt.linear_velocity = Vec3(v, 0, 0);
  belt.shapes.push_back(box(Vec3(20, 1, 0.1), mu));
  const BodyId b = world.createBody(belt);
  BodyDef load = test::boxBody("load", 2.0, Vec3(0.2, 0.2, 0.2), Vec3(0, 0, 0.15));
  load.shapes.push_back(box(Vec3(0.2, 0.2, 0.2), mu));
  const BodyId l = world.createBody(load);
  for (int n = 0; n < 1000; ++n) world.step();
  // Slipping for v / (mu g), then carried: behind the belt by v^2 / (2 mu g).
  const double lag = v * v / (2 * mu * kG);
  const double behind = world.body(b).position().x() - world.body(l).position().x();
  std::printf(
      "%s: belt at %.9f m (v t = %.9f), box %.9f m/s, behind by %.6f m (v^2 / (2 mu g) = "
      "%.6f), box z %.6f\n",
      test::solverName(GetParam()), world.body(b).position().x(), v * world.time(),
      world.body(l).linearVelocity().x(), behind, lag, world.body(l).position().z());
  EXPECT_NEAR(world.body(b).position().x(), v * world.time(), 1e-12);  // unmoved by the box
  EXPECT_EQ(world.body(b).linearVelocity(), Vec3(v, 0, 0));
  EXPECT_NEAR(world.body(l).linearVelocity().x(), v, 1e-6);
  EXPECT_NEAR(behind, lag, 0.02 * lag);
  EXPECT_NEAR(world.body(l).position().z(), 0.15, 2e-3);
  EXPECT_FALSE(world.isAsleep(l));  // carried along, never left behind asleep
}

TEST_P(KinematicBody, LiftRaisesABoxAtItsSpeed) {
  constexpr double v = 0.3;
  WorldSettings s;
  s.solver.type = GetParam();
  World world(s);
  BodyDef lift;
  lift.name = "lift";
  lift.kinematic = true;
  lift.shapes.push_back(box(Vec3(1, 1, 0.1), 0.5));
  const BodyId b = world.createBody(lift);
  BodyDef load = test::boxBody("load", 5.0, Vec3(0.2, 0.2, 0.2), Vec3(0, 0, 0.15));
  load.shapes.push_back(box(Vec3(0.2, 0.2, 0.2), 0.5));
  const BodyId l = world.createBody(load);
  for (int n = 0; n < 500; ++n) world.step();  // settles on the lift at rest
  world.body(b).setLinearVelocity(Vec3(0, 0, v));
  for (int n = 0; n < 1000; ++n) world.step();
  const double gap = world.body(l).position().z() - world.body(b).position().z();
  std::printf("%s: lift at %.9f m, box %.6f m above it, rising at %.9f m/s\n",
              test::solverName(GetParam()), world.body(b).position().z(), gap,
              world.body(l).linearVelocity().z());
  EXPECT_NEAR(world.body(b).position().z(), v * 1.0, 1e-12);
  EXPECT_NEAR(gap, 0.15, 2e-3);
  EXPECT_NEAR(world.body(l).linearVelocity().z(), v, 1e-6);
}

TEST_P(KinematicBody, PendulumOnAMovingPivotHangsStill) {
  const Vec3 v(0.7, -0.2, 0.1);
  WorldSettings s;
  s.solver.type = GetParam();
  s.sleep.enabled = false;
  World world(s);
  BodyDef carriage;
  carriage.name = "carriage";
  carriage.kinematic = true;
  carriage.position = Vec3(0, 0, 2);
  carriage.linear_velocity = v;
  const BodyId c = world.createBody(carriage);
  BodyDef bob = test::boxBody("bob", 1.0, Vec3(0.1, 0.1, 0.1), Vec3(0, 0, 1));
  bob.linear_velocity = v;
  const BodyId p = world.createBody(bob);
  const JointId pivot = world.createJoint(
      "hinge",
      JointDef{
          .name = "pivot", .body1 = p, .body2 = c, .anchor = Vec3(0, 0, 2), .axis = Vec3::UnitY()});
  for (int n = 0; n < 2000; ++n) world.step();
  std::printf("%s: angle %.2e rad, bob off the pivot's line %.2e m, joint error %.2e m\n",
              test::solverName(GetParam()), world.jointCoordinates(pivot)[0],
              (world.body(p).position() - world.body(c).position() - Vec3(0, 0, -1)).norm(),
              world.maxJointError());
  EXPECT_LT(std::abs(world.jointCoordinates(pivot)[0]), 1e-9);
  EXPECT_LT((world.body(p).position() - world.body(c).position() - Vec3(0, 0, -1)).norm(), 1e-9);
  EXPECT_NEAR((world.body(c).position() - Vec3(0, 0, 2) - v * world.time()).norm(), 0.0, 1e-12);
}

TEST_P(KinematicBody, FollowsItsPathAndPushesABoxAlong) {
  // A pusher on a table path: out along x at 0.5 m/s for a second, held for one, back; it meets a
  // box 0.3 m ahead and pushes it (the box then slides on the ground and stops).
  WorldSettings s;
  s.solver.type = GetParam();
  World world(s);
  world.createBody(test::groundPlane());
  BodyDef pusher;
  pusher.name = "pusher";
  pusher.kinematic = true;
  pusher.position = Vec3(0, 0, 0.1);
  pusher.path = VectorSignal({Signal({0.0, 1.0, 2.0, 3.0}, {0.0, 0.5, 0.5, 0.0}), 0.0, 0.1});
  pusher.shapes.push_back(box(Vec3(0.1, 0.4, 0.2), 0.5));
  const BodyId p = world.createBody(pusher);
  BodyDef load = test::boxBody("load", 1.0, Vec3(0.2, 0.2, 0.2), Vec3(0.35, 0, 0.1));
  load.shapes.push_back(box(Vec3(0.2, 0.2, 0.2), 0.3));
  const BodyId l = world.createBody(load);
  double worst = 0.0;
  for (int n = 1; n <= 3000; ++n) {
    world.step();
    const double t = world.time();
    const double x = t <= 1.0 ? 0.5 * t : t <= 2.0 ? 0.5 : 0.5 * (3.0 - t);
    worst = std::max(worst, (world.body(p).position() - Vec3(x, 0, 0.1)).norm());
  }
  std::printf("%s: pusher off its path by %.2e m at most; box pushed to x = %.4f m\n",
              test::solverName(GetParam()), worst, world.body(l).position().x());
  EXPECT_LT(worst, 1e-12);
  EXPECT_GT(world.body(l).position().x(), 0.5 + 0.15 - 1e-3);  // ahead of the pusher's reach
  BodyDef astray;                                              // a path on a dynamic body
  astray.name = "astray";
  astray.mass = 1.0;
  astray.inertia = Mat3::Identity();
  astray.path = VectorSignal(Vec3::Zero());
  EXPECT_THROW(world.createBody(astray), std::invalid_argument);
}

INSTANTIATE_TEST_SUITE_P(Solvers, KinematicBody,
                         testing::Values(SolverType::Auto, SolverType::Exact, SolverType::Pgs,
                                         SolverType::Soft),
                         [](const auto& info) {
                           return std::string(test::solverName(info.param));
                         });

TEST(KinematicBodyDefinition, RefusedWithTheFieldNamed) {
  World world;
  BodyDef both;
  both.name = "both";
  both.kinematic = true;
  both.is_static = true;
  EXPECT_THROW(world.createBody(both), std::invalid_argument);
  BodyDef heavy;
  heavy.name = "heavy";
  heavy.kinematic = true;
  heavy.mass = 2.0;
  EXPECT_THROW(world.createBody(heavy), std::invalid_argument);

  const auto error = [](const std::string& body) -> std::string {
    try {
      parseScene(R"({"bodies": [)" + body + "]}", "k.json");
    } catch (const SceneError& e) {
      return e.what();
    }
    return "accepted";
  };
  EXPECT_EQ(error(R"({"name": "k", "kinematic": true, "mass": 1})"),
            "k.json: bodies[0].mass: a kinematic body has infinite mass and moves at its given "
            "velocity");
  EXPECT_EQ(error(R"({"name": "k", "kinematic": true, "static": true})"),
            "k.json: bodies[0].kinematic: a body is static or kinematic, not both");
  EXPECT_EQ(error(R"({"name": "k", "kinematic": true,
                      "shapes": [{"type": "box", "size": [1, 1, 1], "density": 3}]})"),
            "k.json: bodies[0].shapes[0].density: a kinematic body has no mass (infinite)");
  EXPECT_EQ(error(R"({"name": "k", "kinematic": true, "linear_velocity": [1, 0, 0],
                      "shapes": [{"type": "box", "size": [1, 1, 1]}]})"),
            "accepted");
}

}  // namespace
}  // namespace linx
