// Joints given in their bodies' own frames (JointDef::local, a scene's "frame": "local"): the
// anchor and axis in body 1's frame, anchor2 and axis2 in body 2's. A tilted bar on a hinge
// written in its own frame swings with the physical pendulum's closed-form period about the axis
// that frame puts in the world; a universal joint whose second axis is given in a turned body 2's
// frame moves as the same joint written in the world frame; a scene in local frames, with a body
// whose centre of mass is not its stated position, moves as the scene written in the world frame.
#include "support.hpp"

#include <linx/scene.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>
#include <string>

namespace linx {
namespace {

TEST(LocalFrames, AHingeInTheBarsOwnFrameSwingsAsTheClosedFormSays) {
  // A 1 m bar turned 30 deg about z and tilted 20 deg about its own x; its hinge is at its end,
  // about its own (0, 1, 0.3) direction: nowhere near a world axis.
  const Quat q = Quat(Eigen::AngleAxisd(0.5236, Vec3::UnitZ())) *
                 Quat(Eigen::AngleAxisd(0.349, Vec3::UnitX()));
  BodyDef bar = test::boxBody("bar", 2.0, Vec3(1.0, 0.1, 0.1), Vec3(0.2, -0.1, 1.5));
  bar.orientation = q;
  const Vec3 local_anchor(-0.5, 0, 0), local_axis = Vec3(0, 1, 0.3).normalized();
  World world;
  const BodyId b = world.createBody(bar);
  const JointId hinge = world.createJoint(
      "hinge",
      JointDef{
          .name = "hinge", .body1 = b, .local = true, .anchor = local_anchor, .axis = local_axis});
  // The joint is made in the world frame: its definition says where the local frame put it.
  const JointDef& made = world.joint(hinge).def();
  EXPECT_FALSE(made.local);
  EXPECT_LT((*made.anchor - (bar.position + q * local_anchor)).norm(), 1e-15);
  EXPECT_LT((made.axis - q * local_axis).norm(), 1e-15);

  const Vec3 pivot = bar.position + q * local_anchor, axis = q * local_axis;
  const Mat3 inertia = q.toRotationMatrix() * *bar.inertia * q.toRotationMatrix().transpose();
  const test::PendulumOnAxis truth =
      test::pendulumOnAxis(pivot, axis, bar.position, inertia, 2.0, world.settings().gravity);
  const test::Oscillation swing = test::swingAgainst(world, hinge, 6000, truth);
  EXPECT_NEAR(swing.period, truth.period, 1e-4 * truth.period);
  EXPECT_NEAR(swing.amplitude, truth.amplitude, 1e-3);
  EXPECT_LT(world.maxJointError(), 1e-9);
}

TEST(LocalFrames, AUniversalJointInTwoBodiesFramesIsTheWorldFramesJoint) {
  // Two shafts, body 2 turned 90 deg about x, the cross's axis2 given in body 2's own frame:
  // written that way and in the world frame, the two worlds move alike.
  const Quat q2(Eigen::AngleAxisd(M_PI / 2, Vec3::UnitX()));
  const auto build = [&](World& world, bool local) {
    BodyDef a = test::boxBody("a", 1.0, Vec3(1.0, 0.1, 0.1), Vec3(0.5, 0, 0));
    a.angular_velocity = Vec3(5, 1, 0);
    BodyDef c = test::boxBody("c", 1.0, Vec3(1.0, 0.1, 0.1), Vec3(-0.5, 0, 0));
    c.orientation = q2;
    c.angular_velocity = Vec3(-2, 0, 1);
    const BodyId ia = world.createBody(a), ic = world.createBody(c);
    JointDef d{.name = "cross", .body1 = ia, .body2 = ic, .local = local};
    if (local) {
      d.anchor = Vec3(-0.5, 0, 0);               // body a's end
      d.axis = Vec3::UnitZ();                    // a's z
      d.axis2 = q2.conjugate() * Vec3::UnitY();  // the world's y, in c's frame
    } else {
      d.anchor = Vec3::Zero();
      d.axis = Vec3::UnitZ();
      d.axis2 = Vec3::UnitY();
    }
    world.settings().gravity = Vec3::Zero();
    return world.createJoint("universal", d);
  };
  World local, global;
  const JointId jl = build(local, true), jg = build(global, false);
  double worst = 0.0;
  for (int n = 0; n < 2000; ++n) {
    local.step();
    global.step();
    worst = std::max(worst,
                     (local.body(BodyId{0}).position() - global.body(BodyId{0}).position()).norm());
  }
  const JointCoordinates ql = local.jointCoordinates(jl), qg = global.jointCoordinates(jg);
  std::printf("universal joint in local frames vs world frame: %.2e m, angles %.2e rad\n", worst,
              (ql - qg).norm());
  EXPECT_LT(worst, 1e-12);
  EXPECT_LT((ql - qg).norm(), 1e-12);
  EXPECT_LT(local.maxJointError(), 1e-9);
}

TEST(LocalFrames, ALocalSceneMovesAsTheWorldFrameScene) {
  // A rod given by its shape's density with the shape off its stated position (its centre of mass
  // moves there), turned 90 deg about y: the hinge and the distance joint's points are in the
  // frame the scene states, where the shapes are.
  const std::string bodies = R"(
    "gravity": [0, 0, -9.81],
    "bodies": [
      {"name": "rod", "position": [1, 0, 2], "orientation": [0.7071067811865476, 0, 0.7071067811865476, 0],
       "shapes": [{"type": "box", "size": [0.1, 0.1, 1], "position": [0.2, 0, 0.5], "density": 500}]},
      {"name": "bob", "position": [1.7, 0, 1.5], "mass": 1, "inertia": [0.01, 0.01, 0.01]}
    ],)";
  const Scene local = parseScene("{" + bodies + R"(
    "joints": [
      {"name": "pin", "type": "hinge", "body1": "rod", "frame": "local",
       "anchor": [0, 0, 0], "axis": [0, 1, 0]},
      {"name": "rod2bob", "type": "distance", "body1": "bob", "body2": "rod", "frame": "local",
       "anchor1": [0, 0, 0], "anchor2": [0.2, 0, 1]}
    ]})",
                                 "local.json");
  // The same in the world frame: rod frame (1, 0, 2) turned 90 deg about y maps (x, y, z) to
  // (1 + z, y, 2 - x).
  const Scene world_frame = parseScene("{" + bodies + R"(
    "joints": [
      {"name": "pin", "type": "hinge", "body1": "rod", "anchor": [1, 0, 2], "axis": [0, 1, 0]},
      {"name": "rod2bob", "type": "distance", "body1": "bob", "body2": "rod",
       "anchor1": [1.7, 0, 1.5], "anchor2": [2, 0, 1.8]}
    ]})",
                                       "world.json");
  World a = buildWorld(local), b = buildWorld(world_frame);
  EXPECT_LT((*a.joint(JointId{1}).def().anchor2 - Vec3(2, 0, 1.8)).norm(), 1e-15);
  for (int n = 0; n < 2000; ++n) {
    a.step();
    b.step();
  }
  const Vec3 pa = a.body(BodyId{1}).position(), pb = b.body(BodyId{1}).position();
  std::printf("local scene vs world-frame scene: bob %.2e m apart after 2 s\n", (pa - pb).norm());
  EXPECT_LT((pa - pb).norm(), 1e-9);
  EXPECT_GT((pa - Vec3(1.7, 0, 1.5)).norm(), 0.1);  // it did swing
  // Written back (the rod with its mass, at its centre), the scene keeps its local frames and
  // moves as it did.
  const Scene again = parseScene(writeSceneJson(local), "again.json");
  EXPECT_TRUE(again.joints[0].def.local);
  World c = buildWorld(again);
  for (int n = 0; n < 2000; ++n) c.step();
  EXPECT_LT((c.body(BodyId{1}).position() - pa).norm(), 1e-12);
}

TEST(LocalFrames, BadFramesAreRefused) {
  const std::string head = R"({"bodies": [
      {"name": "a", "mass": 1, "inertia": [1, 1, 1], "orientation": [0.7071067811865476, 0.7071067811865476, 0, 0]},
      {"name": "b", "mass": 1, "inertia": [1, 1, 1], "position": [1, 0, 0]}],
    "joints": [)";
  const auto message = [&](const std::string& joint) {
    try {
      buildWorld(parseScene(head + joint + "]}", "bad.json"));
    } catch (const std::exception& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  EXPECT_NE(message(R"({"name": "j", "type": "hinge", "body1": "a", "frame": "body",
                        "anchor": [0, 0, 0], "axis": [0, 0, 1]})")
                .find("joints[0].frame: unknown frame 'body'"),
            std::string::npos);
  // a's z is the world's -y, so axis1 (0, 0, 1) in a's frame is along b's (0, 1, 0) in b's:
  // parallel, not perpendicular, once both are in the world.
  const std::string parallel = message(
      R"({"name": "u", "type": "universal", "body1": "a", "body2": "b", "frame": "local",
          "anchor": [0, 0, 0], "axis1": [0, 0, 1], "axis2": [0, 1, 0]})");
  std::printf("%s\n", parallel.c_str());
  EXPECT_NE(parallel.find("joints[0].axis2: must be perpendicular to axis1"), std::string::npos);
  EXPECT_NE(message(R"({"name": "d", "type": "distance", "body1": "a", "body2": "b",
                        "frame": "local", "anchor1": [1, 0, 0], "anchor2": [0, 0, 0]})")
                .find("joints[0].anchor2: must be apart"),
            std::string::npos);
}

}  // namespace
}  // namespace linx
