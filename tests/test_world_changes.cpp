// Bodies and joints added to a world between steps take part from the next step on: a box
// dropped onto a sleeping box wakes it and comes to rest on top of it (its centre one box height
// above the other's), and a pendulum added mid-run hangs from its hinge and swings with the
// physical pendulum's period.
#include "support.hpp"

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

}  // namespace
}  // namespace linx
