// Bodies and joints added to a world between steps take part from the next step on: a box
// dropped onto a sleeping box wakes it and comes to rest on top of it (its centre one box height
// above the other's), and a pendulum added mid-run hangs from its hinge and swings with the
// physical pendulum's period. Removed between steps, they leave no trace: a box whose support is
// removed wakes and falls freely (z0 - g t^2 / 2), a bob whose joint is removed flies on a
// parabola, a world that had a body removed steps to the bit as one that never had it, and ids
// kept past a removal refer to nothing, even once their slot holds a new body.
#include "support.hpp"

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace linx {
namespace {

BodyDef cube(const std::string& name, const Vec3& position) {
  BodyDef b;
  b.name = name;
  b.position = position;
  ShapeDef box;
  box.type = ShapeType::Box;
  box.size = Vec3(0.2, 0.2, 0.2);
  box.density = 500;
  b.shapes.push_back(box);
  return b;
}

TEST(WorldChanges, BodiesAndJointsAddedBetweenStepsTakePart) {
  World world;
  world.createBody(test::groundPlane());
  const BodyId a = world.createBody(cube("a", Vec3(0, 0, 0.5)));
  for (int n = 0; n < 1000; ++n) world.step();
  ASSERT_TRUE(world.isAsleep(a));

  const BodyId b = world.createBody(cube("b", Vec3(0.05, 0, 0.8)));
  // A 1 m pendulum released at 0.2 rad: a 1 kg point-like bob (inertia 1e-6 about its centre).
  BodyDef bob;
  bob.name = "bob";
  bob.mass = 1.0;
  bob.inertia = 1e-6 * Mat3::Identity();
  bob.position = Vec3(3 + std::sin(0.2), 0, 2 - std::cos(0.2));
  const BodyId p = world.createBody(bob);
  const JointId hinge = world.createJoint(
      "hinge",
      JointDef{.name = "pivot", .body1 = p, .anchor = Vec3(3, 0, 2), .axis = Vec3::UnitY()});
  bool woke = false;
  std::vector<double> times, angles;
  for (int n = 0; n < 3000; ++n) {
    world.step();
    woke = woke || !world.isAsleep(a);
    times.push_back(world.time());
    angles.push_back(world.jointCoordinates(hinge)[0]);
  }
  // The angle counts from the release: the swing is about its midpoint.
  const auto [low, high] = std::minmax_element(angles.begin(), angles.end());
  const double middle = 0.5 * (*low + *high);
  for (double& angle : angles) angle -= middle;
  const std::vector<double> up = test::upwardCrossings(times, angles);
  ASSERT_GE(up.size(), 2u);
  const double period = (up.back() - up.front()) / static_cast<double>(up.size() - 1);
  const double expected = test::pendulumPeriod(1.0 + 1e-6, 1.0, 9.81, 1.0, 0.2);
  std::printf(
      "b rests at z = %.6f m (on a: 0.3), pendulum period %.6f s (closed form %.6f), "
      "joint error %.2e m\n",
      world.body(b).position().z(), period, expected, world.maxJointError());
  EXPECT_TRUE(woke);
  EXPECT_NEAR(world.body(b).position().z(), 0.3, 2e-3);
  EXPECT_NEAR(world.body(a).position().z(), 0.1, 2e-3);
  EXPECT_NEAR(period, expected, 2e-3 * expected);
  EXPECT_LT(world.maxJointError(), 1e-9);
}

TEST(WorldChanges, RemovingASupportLetsWhatRestedOnItFallFreely) {
  World world;
  world.createBody(test::groundPlane());
  const BodyId low = world.createBody(cube("low", Vec3(0, 0, 0.1)));
  const BodyId high = world.createBody(cube("high", Vec3(0, 0, 0.3)));
  world.addLoad(LoadDef{.body = low, .force = {Vec3(0, 0, -1)}});
  for (int n = 0; n < 1500; ++n) world.step();
  ASSERT_TRUE(world.isAsleep(high));
  const double z0 = world.body(high).position().z();

  world.removeBody(low);
  EXPECT_FALSE(world.isAsleep(high));  // it touched the removed body
  EXPECT_FALSE(world.contains(low));
  EXPECT_EQ(world.loadCount(), 0);  // the load went with its body
  // It falls 0.2 m to the ground: sqrt(2 * 0.2 / g) = 0.202 s. Watch 0.15 s of free fall.
  const double g = 9.81;
  double worst = 0.0;
  for (int n = 1; n <= 150; ++n) {
    world.step();
    // Symplectic Euler: z_n = z0 - g h^2 n (n + 1) / 2.
    const double h = world.settings().timestep;
    worst = std::max(
        worst, std::abs(world.body(high).position().z() - (z0 - 0.5 * g * h * h * n * (n + 1))));
  }
  const double fallen = z0 - world.body(high).position().z();
  std::printf("after its support went: fell %.6f m in 0.15 s (closed form %.6f), worst %.2e m\n",
              fallen, 0.5 * g * 0.15 * 0.15, worst);
  EXPECT_LT(worst, 1e-12);
  EXPECT_NEAR(fallen, 0.5 * g * 0.15 * 0.15, 2e-3);  // z0 - g t^2 / 2, up to the step's O(h)
  for (int n = 0; n < 1000; ++n) world.step();
  EXPECT_NEAR(world.body(high).position().z(), 0.1, 2e-3);  // now on the ground
}

TEST(WorldChanges, ABobWhoseJointIsRemovedFliesOnAParabola) {
  World world;
  BodyDef bob;
  bob.name = "bob";
  bob.mass = 1.0;
  bob.inertia = 1e-3 * Mat3::Identity();
  bob.position = Vec3(1, 0, 2);
  const BodyId p = world.createBody(bob);
  const JointId hinge = world.createJoint(
      "hinge",
      JointDef{.name = "pivot", .body1 = p, .anchor = Vec3(0, 0, 2), .axis = Vec3::UnitY()});
  for (int n = 0; n < 300; ++n) world.step();
  world.removeJoint(hinge);
  EXPECT_FALSE(world.contains(hinge));
  EXPECT_FALSE(world.findJoint("pivot"));
  EXPECT_THROW(world.jointCoordinates(hinge), std::out_of_range);
  const Vec3 x0 = world.body(p).position(), v0 = world.body(p).linearVelocity();
  const Vec3 w0 = world.body(p).angularVelocity();
  const double h = world.settings().timestep;
  double worst = 0.0;
  for (int n = 1; n <= 500; ++n) {
    world.step();
    // Symplectic Euler under gravity: x_n = x0 + n h v0 + g h^2 n (n + 1) / 2.
    const Vec3 truth = x0 + n * h * v0 + 0.5 * h * h * n * (n + 1) * world.settings().gravity;
    worst = std::max(worst, (world.body(p).position() - truth).norm());
  }
  std::printf("freed bob: %.2e m from its parabola over 0.5 s, spin change %.2e rad/s\n", worst,
              (world.body(p).angularVelocity() - w0).norm());
  EXPECT_LT(worst, 1e-12);
  EXPECT_LT((world.body(p).angularVelocity() - w0).norm(), 1e-12);  // a sphere-like free spin
}

/// Positions of the named bodies after `steps` steps.
std::vector<Vec3> positionsAfter(World& world, const std::vector<std::string>& names, int steps) {
  for (int n = 0; n < steps; ++n) world.step();
  std::vector<Vec3> out;
  for (const std::string& name : names) out.push_back(world.body(*world.findBody(name)).position());
  return out;
}

TEST(WorldChanges, ARemovedBodyLeavesNoTrace) {
  // Three boxes dropped onto the ground, in a world of their own and in one that also had a box
  // "extra" with a joint to one of them and a load, removed before the first step: the same
  // motion to the bit. Removed after 200 steps instead, its slot goes to a new body, which falls
  // freely far away.
  const auto build = [](World& world, bool extra) {
    world.createBody(test::groundPlane());
    for (int k = 0; k < 3; ++k)
      world.createBody(cube(fmt::format("box{}", k), Vec3(0.3 * k, 0, 0.15 + 0.25 * k)));
    if (extra) {
      const BodyId e = world.createBody(cube("extra", Vec3(0.9, 0, 0.1)));
      world.createJoint("ball", JointDef{.name = "tie",
                                         .body1 = e,
                                         .body2 = *world.findBody("box2"),
                                         .anchor = Vec3(0.75, 0, 0.3)});
      world.addLoad(LoadDef{.body = e, .torque = {Vec3(0, 0, 0.1)}});
    }
  };
  const std::vector<std::string> names{"box0", "box1", "box2"};
  World plain, edited;
  build(plain, false);
  build(edited, true);
  for (int n = 0; n < 200; ++n) edited.step();
  World early;
  build(early, true);
  early.removeBody(*early.findBody("extra"));
  EXPECT_EQ(early.jointIds().size(), 0u);  // its joint went with it
  const std::vector<Vec3> a = positionsAfter(plain, names, 600);
  const std::vector<Vec3> b = positionsAfter(early, names, 600);
  for (std::size_t k = 0; k < a.size(); ++k) EXPECT_EQ(a[k], b[k]) << names[k];

  // Removed mid-run: the slot's new body (a free-falling sphere-like box far away) falls as in
  // free fall, the others keep resting.
  edited.removeBody(*edited.findBody("extra"));
  const BodyId fresh = edited.createBody(cube("fresh", Vec3(10, 0, 5)));
  EXPECT_EQ(fresh.index, 4);  // the freed slot
  EXPECT_EQ(fresh.generation, 1u);
  const std::vector<Vec3> c = positionsAfter(edited, names, 300);
  const double h = edited.settings().timestep;
  EXPECT_NEAR(edited.body(fresh).position().z(), 5 - 0.5 * 9.81 * h * h * 300 * 301, 1e-12);
  for (std::size_t k = 0; k < c.size(); ++k) EXPECT_LT(c[k].z(), 0.35 + 0.25 * k) << names[k];
}

class JointSlot : public ::testing::TestWithParam<SolverType> {};

TEST_P(JointSlot, AJointInARemovedJointsSlotStartsAfresh) {
  // A spinning bar hangs on a hinge for 0.2 s in two identical worlds. In one the hinge is
  // removed and a ball joint at the same point takes its slot; in the other the hinge is only
  // switched off and the ball joint takes a new slot. They move on to the bit alike: nothing of
  // the hinge (its impulses' warm start, its reaction) carries over to its slot's new joint.
  const Vec3 pivot(0, 0, 2);
  WorldSettings settings;
  settings.solver.type = GetParam();
  World removed(settings), switched_off(settings);
  JointId hinge, ball1, ball2;
  for (World* world : {&removed, &switched_off}) {
    BodyDef bar = test::boxBody("bar", 2.0, Vec3(1.0, 0.1, 0.1), Vec3(0.5, 0, 2));
    bar.angular_velocity = Vec3(0, 0, 3.0);
    const BodyId b = world->createBody(bar);
    hinge = world->createJoint(
        "hinge", JointDef{.name = "hinge", .body1 = b, .anchor = pivot, .axis = Vec3::UnitY()});
    for (int n = 0; n < 200; ++n) world->step();
    EXPECT_GT(world->jointReaction(hinge).force.norm(), 1.0);
  }
  removed.removeJoint(hinge);
  switched_off.joint(hinge).setEnabled(false);
  const BodyId bar{0};
  ball1 = removed.createJoint("ball", JointDef{.name = "ball", .body1 = bar, .anchor = pivot});
  ball2 = switched_off.createJoint("ball", JointDef{.name = "ball", .body1 = bar, .anchor = pivot});
  EXPECT_EQ(ball1.index, hinge.index);
  EXPECT_NE(ball2.index, hinge.index);
  EXPECT_EQ(removed.jointReaction(ball1).force, Vec3::Zero());
  for (int n = 0; n < 300; ++n) {
    removed.step();
    switched_off.step();
  }
  EXPECT_EQ(removed.body(bar).position(), switched_off.body(bar).position());
  EXPECT_EQ(removed.body(bar).angularVelocity(), switched_off.body(bar).angularVelocity());
  EXPECT_EQ(removed.jointReaction(ball1).force, switched_off.jointReaction(ball2).force);
}
INSTANTIATE_TEST_SUITE_P(Solvers, JointSlot,
                         ::testing::Values(SolverType::Exact, SolverType::Pgs, SolverType::Soft),
                         [](const auto& info) { return test::solverName(info.param); });

TEST(WorldChanges, IdsKeptPastARemovalReferToNothing) {
  World world;
  const BodyId a = world.createBody(cube("a", Vec3(0, 0, 1)));
  const BodyId b = world.createBody(cube("b", Vec3(0, 0, 2)));
  const JointId j = world.createJoint(
      "ball", JointDef{.name = "j", .body1 = a, .body2 = b, .anchor = Vec3(0, 0, 1.5)});
  world.step();
  world.removeBody(a);
  EXPECT_FALSE(world.contains(a));
  EXPECT_FALSE(world.contains(j));  // its joint went with it
  EXPECT_TRUE(world.contains(b));
  EXPECT_THROW(world.body(a), std::out_of_range);
  EXPECT_THROW(world.joint(j), std::out_of_range);
  EXPECT_THROW(world.removeBody(a), std::out_of_range);
  EXPECT_THROW(world.removeJoint(j), std::out_of_range);
  EXPECT_THROW(world.createJoint("ball", JointDef{.name = "k", .body1 = a}), std::invalid_argument);
  EXPECT_THROW(world.addLoad(LoadDef{.body = a}), std::invalid_argument);
  EXPECT_FALSE(world.findBody("a"));

  // The name and the slot are free again; the old ids still refer to nothing.
  const BodyId again = world.createBody(cube("a", Vec3(0, 0, 3)));
  EXPECT_EQ(again.index, a.index);
  EXPECT_NE(again, a);
  EXPECT_FALSE(world.contains(a));
  EXPECT_EQ(world.body(again).id(), again);
  EXPECT_EQ(*world.findBody("a"), again);
  const JointId k = world.createJoint(
      "ball", JointDef{.name = "k", .body1 = again, .body2 = b, .anchor = Vec3(0, 0, 2.5)});
  EXPECT_EQ(k.index, j.index);
  EXPECT_FALSE(world.contains(j));
  EXPECT_EQ(world.bodyIds(), (std::vector<BodyId>{again, b}));
  EXPECT_EQ(world.jointIds(), (std::vector<JointId>{k}));
  world.step();
  EXPECT_LT(world.maxJointError(), 1e-9);
}

TEST(WorldChanges, BodiesComingAndGoingThroughFewSlots) {
  // A box rests on the ground (awake: sleeping is off) while balls rain beside it, one every 10
  // steps, each removed as it reaches the ground: 400 bodies come and go through a few slots, and
  // their removed shapes are packed away from time to time. Each falls freely to the ground.
  WorldSettings settings;
  settings.sleep.enabled = false;
  World world(settings);
  world.createBody(test::groundPlane());
  const BodyId box = world.createBody(cube("box", Vec3(0, 0, 0.1)));
  for (int n = 0; n < 500; ++n) world.step();
  const Vec3 rest = world.body(box).position();
  struct Falling {
    BodyId id;
    int born;
  };
  std::vector<Falling> balls;
  std::vector<int> fall_steps;
  const double z0 = 0.3, radius = 0.05, below = 0.06;
  for (int n = 0; n < 4400; ++n) {
    if (n % 10 == 0 && n < 4000) {
      BodyDef ball;
      const int k = static_cast<int>(fall_steps.size() + balls.size());
      ball.name = fmt::format("ball{}", k);
      ball.position = Vec3(1.0 + 0.12 * (k % 30), 0, z0);  // a place reused every 300 steps
      ball.shapes.push_back(ShapeDef{.type = ShapeType::Sphere, .radius = radius, .density = 1000});
      balls.push_back({world.createBody(ball), n});
    }
    world.step();
    std::erase_if(balls, [&](const Falling& ball) {
      if (world.body(ball.id).position().z() > below) return false;
      fall_steps.push_back(n + 1 - ball.born);
      world.removeBody(ball.id);
      return true;
    });
  }
  // Symplectic Euler: it passes `below` at the first n with g h^2 n (n + 1) / 2 >= z0 - below.
  const double h = world.settings().timestep, g = 9.81;
  int expected = 1;
  while (0.5 * g * h * h * expected * (expected + 1) < z0 - below) ++expected;
  const auto [fewest, most] = std::minmax_element(fall_steps.begin(), fall_steps.end());
  std::printf(
      "%zu balls came and went through %d slots, each falling in %d..%d steps (closed "
      "form %d); the box moved %.2e m\n",
      fall_steps.size(), world.bodyCount(), *fewest, *most, expected,
      (world.body(box).position() - rest).norm());
  EXPECT_EQ(fall_steps.size(), 400u);
  EXPECT_EQ(*fewest, expected);
  EXPECT_EQ(*most, expected);
  EXPECT_LE(world.bodyCount(), 2 + expected / 10 + 2);  // the ground, the box, the balls in the air
  EXPECT_LT((world.body(box).position() - rest).norm(), 1e-6);
}

}  // namespace
}  // namespace linx
