// A coordinate's reference (its value where the model is built) and initial value (where it
// starts): a double pendulum built hanging straight and started bent lands on the forward
// kinematics of its two angles; a hinge whose reference is 0.3 rad reads 0.3 where it was built and
// stops at its limit counted from the same zero; a closed loop cannot be bent one joint at a time.
#include "support.hpp"

#include <linx/scene.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <stdexcept>

namespace linx {
namespace {

// A 1 m, 1 kg link hanging from `top` along -z.
BodyId link(World& world, const std::string& name, const Vec3& top) {
  return world.createBody(test::boxBody(name, 1.0, Vec3(0.05, 0.05, 1.0), top - Vec3(0, 0, 0.5)));
}

Vec3 turnedY(double angle, const Vec3& v) {
  return Eigen::AngleAxisd(angle, Vec3::UnitY()) * v;
}

TEST(InitialCoordinates, DoublePendulumBuiltStraightStartsBent) {
  World world;
  const BodyId upper = link(world, "upper", Vec3::Zero());
  const BodyId lower = link(world, "lower", Vec3(0, 0, -1));
  const JointId shoulder = world.createJoint(
      "hinge",
      JointDef{.name = "shoulder", .body1 = upper, .anchor = Vec3::Zero(), .axis = Vec3::UnitY()});
  const JointId elbow = world.createJoint("hinge", JointDef{.name = "elbow",
                                                            .body1 = lower,
                                                            .body2 = upper,
                                                            .anchor = Vec3(0, 0, -1),
                                                            .axis = Vec3::UnitY()});
  world.setJointCoordinate(shoulder, 0, 0.5);
  world.setJointCoordinate(elbow, 0, -1.2);
  // Forward kinematics: the upper link turned by 0.5 about y, the lower by 0.5 - 1.2.
  const Vec3 knee = turnedY(0.5, Vec3(0, 0, -1));
  const Vec3 upper_centre = turnedY(0.5, Vec3(0, 0, -0.5));
  const Vec3 lower_centre = knee + turnedY(0.5 - 1.2, Vec3(0, 0, -0.5));
  std::printf(
      "upper %.2e m, lower %.2e m from the forward kinematics; angles %.15f, %.15f; "
      "joints %.2e m\n",
      (world.body(upper).position() - upper_centre).norm(),
      (world.body(lower).position() - lower_centre).norm(), world.jointCoordinates(shoulder)[0],
      world.jointCoordinates(elbow)[0], world.maxJointError());
  EXPECT_LT((world.body(upper).position() - upper_centre).norm(), 1e-12);
  EXPECT_LT((world.body(lower).position() - lower_centre).norm(), 1e-12);
  EXPECT_NEAR(world.jointCoordinates(shoulder)[0], 0.5, 1e-12);
  EXPECT_NEAR(world.jointCoordinates(elbow)[0], -1.2, 1e-12);
  EXPECT_LT(world.maxJointError(), 1e-12);
  // Past half a turn, counted.
  world.setJointCoordinate(shoulder, 0, 4.0);
  EXPECT_NEAR(world.jointCoordinates(shoulder)[0], 4.0, 1e-12);
  EXPECT_NEAR(world.jointCoordinates(elbow)[0], -1.2, 1e-12);
}

TEST(InitialCoordinates, UniversalJointKeepsItsOtherAngle) {
  World world;
  const BodyId shaft =
      world.createBody(test::boxBody("shaft", 1.0, Vec3(1, 0.1, 0.1), Vec3(0.5, 0, 0)));
  const JointId cross = world.createJoint("universal", JointDef{.name = "cross",
                                                                .body1 = shaft,
                                                                .anchor = Vec3::Zero(),
                                                                .axis = Vec3::UnitX(),
                                                                .axis2 = Vec3::UnitZ()});
  world.setJointCoordinate(cross, 1, 0.7);
  world.setJointCoordinate(cross, 0, -0.4);
  const JointCoordinates q = world.jointCoordinates(cross);
  std::printf("angles %.15f %.15f, joint %.2e\n", q[0], q[1], world.maxJointError());
  EXPECT_NEAR(q[0], -0.4, 1e-12);
  EXPECT_NEAR(q[1], 0.7, 1e-12);
  EXPECT_LT(world.maxJointError(), 1e-12);
}

TEST(InitialCoordinates, ReferenceCountsLimitsFromTheSameZero) {
  // Built at 0.3 rad (its reference), limited to [-1, 0.5]: it falls from 0.3 towards +0.5.
  WorldSettings s;
  s.sleep.enabled = false;
  World world(s);
  const BodyId arm =
      world.createBody(test::boxBody("arm", 1.0, Vec3(1, 0.05, 0.05), Vec3(0.5, 0, 0)));
  const JointId hinge = world.createJoint(
      "hinge",
      JointDef{.name = "h",
               .body1 = arm,
               .anchor = Vec3::Zero(),
               .axis = Vec3::UnitY(),
               .coordinates = {CoordinateDef{.limits = JointLimits{-1.0, 0.5}, .reference = 0.3}}});
  EXPECT_NEAR(world.jointCoordinates(hinge)[0], 0.3, 1e-15);
  for (int n = 0; n < 2000; ++n) world.step();
  // About +y, gravity turns the horizontal arm's far end down: its angle grows.
  std::printf("rests at %.9f rad (limit 0.5): turned %.9f rad from where it was built\n",
              world.jointCoordinates(hinge)[0], world.jointCoordinates(hinge)[0] - 0.3);
  EXPECT_NEAR(world.jointCoordinates(hinge)[0], 0.5, 1e-6);
  world.setJointCoordinate(hinge, 0, -0.2);  // with the reference too
  EXPECT_NEAR(world.jointCoordinates(hinge)[0], -0.2, 1e-12);
  EXPECT_NEAR(world.body(arm).position().z(), 0.5 * std::sin(0.5),
              1e-12);  // 0.5 rad up from where it was built
}

TEST(InitialCoordinates, ClosedLoopIsRefused) {
  World world;
  const BodyId a = link(world, "a", Vec3::Zero());
  const JointId top = world.createJoint(
      "hinge", JointDef{.name = "top", .body1 = a, .anchor = Vec3::Zero(), .axis = Vec3::UnitY()});
  world.createJoint("slider", JointDef{.name = "rail", .body1 = a, .axis = Vec3::UnitZ()});
  try {
    world.setJointCoordinate(top, 0, 0.3);
    ADD_FAILURE() << "bent a loop";
  } catch (const std::invalid_argument& e) {
    EXPECT_STREQ(e.what(),
                 "initial: body1's side is also held by joint 'rail' (a closed loop, or fixed to "
                 "the world): it cannot move alone");
  }
}

TEST(InitialCoordinates, FromAScene) {
  const Scene scene = parseScene(R"({
    "bodies": [{"name": "a", "mass": 1, "inertia": [1, 1, 1], "position": [0, 0, -1]}],
    "joints": [{"name": "h", "type": "hinge", "body1": "a", "anchor": [0, 0, 0],
                "axis": [0, 1, 0], "reference": 0.1, "initial": 0.6}]
  })",
                                 "bent.json");
  EXPECT_EQ(scene.joints[0].def.coordinates[0].reference, 0.1);
  const World world = buildWorld(scene);
  EXPECT_NEAR(world.jointCoordinates(JointId{0})[0], 0.6, 1e-12);
  EXPECT_NEAR(world.body(BodyId{0}).position().x(), -std::sin(0.5), 1e-12);  // turned 0.5 about y
  try {
    parseScene(R"({"bodies": [{"name": "a", "mass": 1, "inertia": [1, 1, 1]}],
      "joints": [{"name": "h", "type": "hinge", "body1": "a", "anchor": [0, 0, 1],
                  "axis": [0, 1, 0], "locked": true, "initial": 1}]})",
               "bad.json");
    ADD_FAILURE() << "accepted";
  } catch (const SceneError& e) {
    EXPECT_STREQ(e.what(),
                 "bad.json: joints[0].initial: a locked coordinate stays where it was made");
  }
}

}  // namespace
}  // namespace linx
