// URDF import against independent truths: a pendulum whose inertial is offset and turned from its
// link frame, on a joint axis along no world axis, swings with the physical pendulum's exact
// period; a two-link arm falls exactly as the same model written by hand in the scene format; a
// floating base falls freely; massless links on fixed joints join their parent; what linx does not
// use is named; bad files are refused with the file and the element.
#include "support.hpp"

#include <linx/import.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <string>

namespace linx {
namespace {

namespace fs = std::filesystem;

class UrdfImport : public ::testing::Test {
 protected:
  fs::path write(const std::string& name, const std::string& text) const {
    return folder_.write(name, text);
  }

  test::TempFolder folder_{
      "linx_urdf_" + std::string(::testing::UnitTest::GetInstance()->current_test_info()->name())};
  const fs::path& dir_ = folder_.path();
};

// URDF's rpy: fixed-axis roll about x, then pitch about y, then yaw about z.
Mat3 rpy(double roll, double pitch, double yaw) {
  return (Eigen::AngleAxisd(yaw, Vec3::UnitZ()) * Eigen::AngleAxisd(pitch, Vec3::UnitY()) *
          Eigen::AngleAxisd(roll, Vec3::UnitX()))
      .toRotationMatrix();
}

const char* kPendulum = R"(<?xml version="1.0"?>
<robot name="pendulum">
  <link name="world"><collision><geometry><sphere radius="0.02"/></geometry></collision></link>
  <joint name="swing" type="continuous">
    <parent link="world"/><child link="bob"/>
    <origin xyz="0.1 0.2 1.0" rpy="0.3 -0.2 0.5"/>
    <axis xyz="0.6 0.8 0"/>
  </joint>
  <link name="bob">
    <inertial>
      <origin xyz="0.05 -0.3 0.1" rpy="0.4 0.1 -0.2"/>
      <mass value="2"/>
      <inertia ixx="0.02" ixy="0.001" ixz="0" iyy="0.03" iyz="-0.002" izz="0.04"/>
    </inertial>
    <collision><origin xyz="0.05 -0.3 0.1"/><geometry><sphere radius="0.05"/></geometry></collision>
  </link>
</robot>
)";

TEST_F(UrdfImport, TurnedPendulumSwingsWithThePhysicalPendulumsPeriod) {
  const Scene scene = importUrdf(write("pendulum.urdf", kPendulum));
  ASSERT_EQ(scene.bodies.size(), 2u);  // the bob, and the world link's sphere on a static body
  ASSERT_EQ(scene.joints.size(), 1u);
  EXPECT_EQ(scene.bodies[1].name, "world_shapes");
  EXPECT_TRUE(scene.bodies[1].is_static);

  // The closed form, from the file's numbers.
  const Mat3 joint_r = rpy(0.3, -0.2, 0.5);
  const Vec3 pivot(0.1, 0.2, 1.0);
  const Vec3 axis = (joint_r * Vec3(0.6, 0.8, 0.0)).normalized();
  const Vec3 com = pivot + joint_r * Vec3(0.05, -0.3, 0.1);
  Mat3 inertial;
  inertial << 0.02, 0.001, 0, 0.001, 0.03, -0.002, 0, -0.002, 0.04;
  const Mat3 to_world = joint_r * rpy(0.4, 0.1, -0.2);
  const Mat3 inertia_world = to_world * inertial * to_world.transpose();
  const test::PendulumOnAxis truth =
      test::pendulumOnAxis(pivot, axis, com, inertia_world, 2.0, Vec3(0, 0, -9.81));
  ASSERT_GT(truth.amplitude, 0.3);
  ASSERT_LT(truth.amplitude, 2.5);

  World world = buildWorld(scene);
  const test::Oscillation swing = test::swingAgainst(world, JointId{0}, 6000, truth);
  ASSERT_GE(swing.crossings, 3u);
  EXPECT_NEAR(swing.amplitude / truth.amplitude - 1.0, 0.0, 1e-3);  // released from rest
  EXPECT_NEAR(swing.period / truth.period - 1.0, 0.0, 1e-3);
}

// A two-link arm: in URDF, and by hand in the scene format with the world-frame numbers.
const char* kArmUrdf = R"(<?xml version="1.0"?>
<robot name="arm">
  <link name="world"/>
  <joint name="shoulder" type="revolute">
    <parent link="world"/><child link="upper"/>
    <origin xyz="0 0 1"/><axis xyz="0 1 0"/>
    <limit lower="-3" upper="3" effort="10" velocity="5"/>
  </joint>
  <link name="upper">
    <inertial><origin xyz="0.25 0 0" rpy="0 1.5707963267948966 0"/><mass value="1.5"/>
      <inertia ixx="0.04" ixy="0" ixz="0" iyy="0.04" iyz="0" izz="0.003"/></inertial>
  </link>
  <joint name="elbow" type="revolute">
    <parent link="upper"/><child link="lower"/>
    <origin xyz="0.5 0 0"/><axis xyz="0 1 0"/>
    <limit lower="-0.5" upper="0.5" effort="10" velocity="5"/>
    <dynamics damping="0.2"/>
  </joint>
  <link name="lower">
    <inertial><origin xyz="0.2 0 0"/><mass value="1"/>
      <inertia ixx="0.002" ixy="0" ixz="0" iyy="0.02" iyz="0" izz="0.02"/></inertial>
  </link>
</robot>
)";

const char* kArmScene = R"({
  "duration": 1,
  "bodies": [
    { "name": "upper", "mass": 1.5, "inertia": [0.003, 0.04, 0.04], "position": [0.25, 0, 1] },
    { "name": "lower", "mass": 1, "inertia": [0.002, 0.02, 0.02], "position": [0.7, 0, 1] }
  ],
  "joints": [
    { "name": "shoulder", "type": "hinge", "body1": "upper", "body2": "world",
      "anchor": [0, 0, 1], "axis": [0, 1, 0], "limits": {"lower": -3, "upper": 3} },
    { "name": "elbow", "type": "hinge", "body1": "lower", "body2": "upper",
      "anchor": [0.5, 0, 1], "axis": [0, 1, 0], "limits": {"lower": -0.5, "upper": 0.5},
      "spring": { "stiffness": 0, "damping": 0.2 } }
  ]
})";

TEST_F(UrdfImport, ArmFallsAsTheSameModelInTheSceneFormat) {
  World urdf = buildWorld(importUrdf(write("arm.urdf", kArmUrdf)));
  World json = buildWorld(loadScene(write("arm.json", kArmScene)));
  ASSERT_EQ(urdf.bodyCount(), json.bodyCount());
  double largest = 0.0, swing = 0.0;
  for (int i = 0; i < 1000; ++i) {
    urdf.step();
    json.step();
    for (int b = 0; b < urdf.bodyCount(); ++b) {
      largest = std::max(
          largest, (urdf.body(BodyId{b}).position() - json.body(BodyId{b}).position()).norm());
    }
    swing = std::max(swing, std::abs(urdf.jointCoordinates(JointId{0})[0]));
  }
  std::printf("arm: largest position difference URDF - scene format over 1 s: %.3g m\n", largest);
  EXPECT_GT(swing, 1.0);  // it fell
  EXPECT_LT(largest, 1e-9);
  // The elbow met its limit and stayed within it.
  EXPECT_LE(urdf.jointCoordinates(JointId{1})[0], 0.5 + 1e-3);
}

// A joint whose zero lies outside its <limit> (bullet3's NAO) is loaded as PyBullet loads it: it
// starts at its nearest bound, placed there at rest, with one warning naming it and its range.
TEST_F(UrdfImport, JointStartingOutsideItsLimitStartsAtItsNearestBound) {
  std::string text = kArmUrdf;
  const std::string limit = R"(<limit lower="-0.5" upper="0.5")";
  text.replace(text.find(limit), limit.size(), R"(<limit lower="0.25" upper="0.5")");
  const Scene scene = importUrdf(write("arm.urdf", text));
  ASSERT_FALSE(scene.warnings.empty());
  EXPECT_NE(scene.warnings.back().find("1 joint starts outside its range, moved to the nearest "
                                       "bound"),
            std::string::npos)
      << scene.warnings.back();
  EXPECT_NE(scene.warnings.back().find("'elbow' at 0 rad, range [0.25, 0.5]"), std::string::npos);
  World world = buildWorld(scene);
  EXPECT_NEAR(world.jointCoordinates(JointId{1})[0], 0.25, 1e-12);
  EXPECT_LT(world.jointError(JointId{1}), 1e-12);
}

TEST_F(UrdfImport, FloatingBaseFallsFreely) {
  const fs::path file = write("arm.urdf", kArmUrdf);
  ImportOptions floating;
  floating.floating_base = true;
  EXPECT_THROW(importUrdf(file, floating), SceneError);  // its root "world" has no mass

  const char* box = R"(<robot name="box">
    <link name="base"><inertial><mass value="3"/>
      <inertia ixx="0.1" ixy="0" ixz="0" iyy="0.1" iyz="0" izz="0.1"/></inertial>
      <collision><geometry><box size="0.2 0.2 0.2"/></geometry></collision></link>
  </robot>)";
  const fs::path box_file = write("box.urdf", box);
  EXPECT_TRUE(importUrdf(box_file).bodies[0].is_static);
  World world = buildWorld(importUrdf(box_file, floating));
  for (int i = 0; i < 500; ++i) world.step();
  EXPECT_NEAR(world.body(BodyId{0}).linearVelocity().z(), -9.81 * world.time(), 1e-9);
}

TEST_F(UrdfImport, MasslessLinkOnAFixedJointJoinsItsParent) {
  const char* text = R"(<robot name="r">
    <link name="base"/>
    <joint name="j" type="prismatic"><parent link="base"/><child link="carriage"/>
      <origin xyz="0 0 1" rpy="0 0 1.5707963267948966"/><axis xyz="1 0 0"/>
      <limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
    <link name="carriage"><inertial><origin xyz="0.1 0 0"/><mass value="2"/>
      <inertia ixx="0.1" ixy="0" ixz="0" iyy="0.1" iyz="0" izz="0.1"/></inertial></link>
    <joint name="mount" type="fixed"><parent link="carriage"/><child link="sensor"/>
      <origin xyz="0.3 0 0.05"/></joint>
    <link name="sensor"><collision><origin xyz="0 0 0.02"/>
      <geometry><sphere radius="0.03"/></geometry></collision></link>
  </robot>)";
  const Scene scene = importUrdf(write("r.urdf", text));
  ASSERT_EQ(scene.bodies.size(), 2u);  // base, carriage (with the sensor's sphere)
  ASSERT_EQ(scene.joints.size(), 1u);
  EXPECT_EQ(scene.joints[0].type, "slider");
  EXPECT_TRUE(scene.joints[0].def.axis.isApprox(Vec3::UnitY(), 1e-15));  // x turned 90 deg
  const BodyDef& carriage = scene.bodies[1];
  EXPECT_TRUE(carriage.position.isApprox(Vec3(0, 0.1, 1), 1e-15));
  ASSERT_EQ(carriage.shapes.size(), 1u);
  // The sphere is 0.3 - 0.1 along the link's x from the centre of mass, 0.07 up.
  EXPECT_TRUE(carriage.shapes[0].position.isApprox(Vec3(0.2, 0, 0.07), 1e-14))
      << carriage.shapes[0].position.transpose();
  World world = buildWorld(scene);
  for (int i = 0; i < 100; ++i) world.step();  // gravity is across the slider: it stays
  EXPECT_NEAR(world.jointCoordinates(JointId{0})[0], 0.0, 1e-12);
}

TEST_F(UrdfImport, MeshesFromPackagesAreScaledAndMovingOnesConvex) {
  write("ws/my_robot/meshes/cube.obj",
        "v -1 -1 -1\nv 1 -1 -1\nv 1 1 -1\nv -1 1 -1\nv -1 -1 1\nv 1 -1 1\nv 1 1 1\nv -1 1 1\n"
        "f 1 3 2\nf 1 4 3\nf 5 6 7\nf 5 7 8\nf 1 2 6\nf 1 6 5\nf 2 3 7\nf 2 7 6\nf 3 4 8\n"
        "f 3 8 7\nf 4 1 5\nf 4 5 8\n");
  const char* text = R"(<robot name="r">
    <link name="base"><collision><geometry>
      <mesh filename="package://my_robot/meshes/cube.obj" scale="2 2 2"/></geometry></collision></link>
    <joint name="j" type="continuous"><parent link="base"/><child link="wheel"/>
      <axis xyz="0 0 1"/></joint>
    <link name="wheel"><inertial><mass value="1"/>
      <inertia ixx="0.1" ixy="0" ixz="0" iyy="0.1" iyz="0" izz="0.1"/></inertial>
      <collision><geometry><mesh filename="package://my_robot/meshes/cube.obj" scale="0.1 0.2 0.3"/>
      </geometry></collision></link>
    <joint name="k" type="continuous"><parent link="wheel"/><child link="hub"/>
      <axis xyz="0 0 1"/></joint>
    <link name="hub"><inertial><mass value="1"/>
      <inertia ixx="0.1" ixy="0" ixz="0" iyy="0.1" iyz="0" izz="0.1"/></inertial>
      <collision><geometry><mesh filename="package://my_robot/meshes/cube.obj" scale="0.1 0.1 0.1"/>
      </geometry></collision></link>
  </robot>)";
  const Scene scene = importUrdf(write("ws/my_robot/urdf/r.urdf", text));
  ASSERT_EQ(scene.bodies.size(), 3u);
  EXPECT_EQ(scene.bodies[0].shapes[0].type, ShapeType::Mesh);  // static: the mesh itself
  EXPECT_EQ(scene.bodies[0].shapes[0].points[6], Vec3(2, 2, 2));
  const ShapeDef& wheel = scene.bodies[1].shapes[0];
  EXPECT_EQ(wheel.type, ShapeType::Convex);
  EXPECT_EQ(wheel.points[6], Vec3(0.1, 0.2, 0.3));
  EXPECT_EQ(scene.bodies[2].shapes[0].type, ShapeType::Convex);
  // One warning for all of them (bullet3's NAO had one a link, 39), naming each.
  ASSERT_EQ(scene.warnings.size(), 1u) << scene.warnings[0];
  EXPECT_NE(scene.warnings[0].find("2 meshes on moving links collide as their convex hulls"),
            std::string::npos)
      << scene.warnings[0];
  EXPECT_NE(scene.warnings[0].find("'wheel'"), std::string::npos) << scene.warnings[0];
  EXPECT_NE(scene.warnings[0].find("'hub'"), std::string::npos) << scene.warnings[0];
  EXPECT_NO_THROW(buildWorld(scene));
}

TEST_F(UrdfImport, WhatLinxDoesNotUseIsNamedInOneWarning) {
  const char* text = R"(<robot name="r">
    <link name="a"><inertial><mass value="1"/>
      <inertia ixx="1" ixy="0" ixz="0" iyy="1" iyz="0" izz="1"/></inertial>
      <visual><geometry><sphere radius="1"/></geometry></visual></link>
    <joint name="j1" type="continuous"><parent link="a"/><child link="b"/></joint>
    <link name="b"><inertial><mass value="1"/>
      <inertia ixx="1" ixy="0" ixz="0" iyy="1" iyz="0" izz="1"/></inertial></link>
    <joint name="j2" type="continuous"><parent link="a"/><child link="c"/>
      <mimic joint="j1" multiplier="2"/></joint>
    <link name="c"><inertial><mass value="1"/>
      <inertia ixx="1" ixy="0" ixz="0" iyy="1" iyz="0" izz="1"/></inertial></link>
    <transmission name="t1"/><transmission name="t2"/><gazebo/>
  </robot>)";
  const Scene scene = importUrdf(write("r.urdf", text));
  ASSERT_EQ(scene.warnings.size(), 1u);
  const std::string& w = scene.warnings[0];
  for (const char* named : {"<transmission> (x2)", "<gazebo>", "<visual>"})
    EXPECT_NE(w.find(named), std::string::npos) << named << " not in: " << w;
  // <mimic> is used: a mimic joint after the joints it ties.
  EXPECT_EQ(w.find("mimic"), std::string::npos) << w;
  ASSERT_EQ(scene.joints.size(), 3u);
  const SceneJoint& mimic = scene.joints[2];
  EXPECT_EQ(mimic.type, "mimic");
  EXPECT_EQ(mimic.def.leader, JointId{0});
  EXPECT_EQ(mimic.def.follower, JointId{1});
  EXPECT_EQ(mimic.def.ratio, 2.0);
  EXPECT_EQ(mimic.def.offset, 0.0);
}

// Each bad file: the message names the file and the element and says what is wrong.
TEST_F(UrdfImport, BadFilesAreRefusedWithTheFileAndTheElement) {
  const auto refused = [&](const std::string& text, const std::string& expected) {
    const fs::path file = write("bad.urdf", text);
    try {
      importUrdf(file);
      ADD_FAILURE() << "accepted; expected: " << expected;
    } catch (const SceneError& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find(file.string()), std::string::npos) << what;
      EXPECT_NE(what.find(expected), std::string::npos) << what;
    }
  };
  const std::string link_b =
      R"(<link name="b"><inertial><mass value="1"/>
         <inertia ixx="1" ixy="0" ixz="0" iyy="1" iyz="0" izz="1"/></inertial></link>)";
  refused("<robot name='r'><link name='a'>", "not well-formed XML (");
  refused("<model/>", "needs a <robot> element");
  refused(
      "<robot name='r'><link name='a'/><joint name='j' type='continuous'><parent link='a'/>"
      "<child link='nope'/></joint></robot>",
      "nope");
  refused(
      "<robot name='r'><link name='a'/><joint name='j' type='continuous'><parent link='a'/>"
      "<child link='b'/></joint><link name='b'/></robot>",
      "link 'b': has no <inertial> with a mass > 0, but joint 'j' moves it");
  refused(
      "<robot name='r'><link name='a'/><joint name='j' type='revolute'><parent link='a'/>"
      "<child link='b'/><limit lower='1' upper='-1' effort='1' velocity='1'/></joint>" +
          link_b + "</robot>",
      "joint 'j': <limit> lower 1 is above upper -1");
  refused(
      "<robot name='r'><link name='a'><collision><geometry><mesh filename='gone.stl'/>"
      "</geometry></collision></link></robot>",
      "gone.stl");
  refused(
      "<robot name='r'><link name='a'/><joint name='j' type='continuous'><parent link='a'/>"
      "<child link='b'/></joint><link name='b'><inertial><mass value='1'/>"
      "<inertia ixx='0' ixy='0' ixz='0' iyy='1' iyz='0' izz='1'/></inertial></link></robot>",
      "link 'b': inertia: must be finite, symmetric and positive definite");
  const std::string two_joints =
      "<robot name='r'><link name='a'/><joint name='j' type='continuous'><parent link='a'/>"
      "<child link='b'/></joint>" +
      link_b + "<joint name='k' type='fixed'><parent link='a'/><child link='c'/>";
  refused(two_joints + "<mimic joint='nope'/></joint><link name='c'/></robot>",
          "joint 'k' <mimic>: no joint 'nope' to follow");
  refused(two_joints + "<mimic joint='j'/></joint><link name='c'/></robot>",
          "joint 'k' <mimic>: joint 'k' is not a revolute, continuous or prismatic joint");
  EXPECT_THROW(importUrdf(dir_ / "missing.urdf"), SceneError);
}

std::string missingPackage(const fs::path& dir) {
  return "mesh file 'package://nopkg/m.stl': package 'nopkg' not found (linx looks for a folder "
         "named nopkg in " +
         fs::absolute(dir).string() + " and the folders above it)";
}

// Hostile files (a bad-input hunt): each refused with the exact element, line and problem, never
// with urdfdom's, tinyxml2's or the standard library's own text.
TEST_F(UrdfImport, HostileFilesAreRefusedInPlainWords) {
  const auto refused = [&](const std::string& text, const std::string& field,
                           const std::string& problem) {
    const fs::path file = write("bad.urdf", text);
    try {
      importUrdf(file);
      ADD_FAILURE() << "accepted; expected: " << field << ": " << problem;
    } catch (const SceneError& e) {
      EXPECT_EQ(e.file(), file.string());
      EXPECT_EQ(e.field(), field);
      EXPECT_EQ(e.problem(), problem);
    }
  };
  const std::string inertial =
      "<inertial><mass value='1'/><inertia ixx='1' ixy='0' ixz='0' iyy='1' iyz='0' izz='1'/>"
      "</inertial>";
  const auto link = [&](const std::string& name, const std::string& inside = "") {
    return "<link name='" + name + "'>" + inertial + inside + "</link>\n";
  };
  const auto joint = [](const std::string& name, const std::string& parent,
                        const std::string& child, const std::string& inside = "") {
    return "<joint name='" + name + "' type='continuous'><parent link='" + parent +
           "'/><child link='" + child + "'/>" + inside + "</joint>\n";
  };
  const auto collision = [&](const std::string& geometry) {
    return "<robot name='r'>\n" +
           link("a",
                "<collision><geometry><sphere radius='1'/></geometry></collision>\n"
                "<collision><geometry>" +
                    geometry + "</geometry></collision>") +
           "</robot>";
  };

  // A loop of joints: urdfdom finds the root "base" and reads the rest; a loop is not a tree.
  refused(
      "<robot name='r'>\n" + link("base") + joint("j1", "c", "a") + link("a") +
          joint("j2", "a", "b") + link("b") + joint("j3", "b", "c") + link("c") +
          joint("tool", "c", "d") + link("d") + "</robot>",
      "robot",
      "joints 'j1', 'j2', 'j3' form a loop (c -> a -> b -> c): a URDF's links must form a tree");

  // Collision sizes.
  refused(collision("<box size='0.3 -0.06 0.06'/>"), "link 'a' collision 1 <box> (line 3)",
          "size: must be 3 numbers > 0, got 0.3 -0.06 0.06");
  refused(collision("<box size='0.3 0.06'/>"), "link 'a' collision 1 <box> (line 3)",
          "size: must be 3 numbers > 0, got 0.3 0.06");
  refused(collision("<box/>"), "link 'a' collision 1 <box> (line 3)", "size: missing");
  refused(collision("<sphere radius='0'/>"), "link 'a' collision 1 <sphere> (line 3)",
          "radius: must be a number > 0, got 0");
  refused(collision("<cylinder radius='0.1' length='0'/>"),
          "link 'a' collision 1 <cylinder> (line 3)", "length: must be a number > 0, got 0");
  refused(collision("<cylinder radius='-1' length='1'/>"),
          "link 'a' collision 1 <cylinder> (line 3)", "radius: must be a number > 0, got -1");
  refused(collision("<mesh filename='m.stl' scale='1 1'/>"), "link 'a' collision 1 <mesh> (line 3)",
          "scale: needs 3 numbers, got 2");
  refused(collision("<mesh filename='m.stl' scale='0 1 1'/>"),
          "link 'a' collision 1 <mesh> (line 3)", "scale: must be 3 non-zero numbers, got 0 1 1");
  refused(collision("<mesh/>"), "link 'a' collision 1 <mesh> (line 3)", "filename: missing");
  // A collision urdfdom would drop silently: no shape, or one it does not know.
  refused(collision("<capsule radius='0.1' length='0.2'/>"),
          "link 'a' collision 1 <geometry> (line 3)",
          "<capsule> is not a URDF geometry (box, sphere, cylinder, mesh)");
  refused(collision(""), "link 'a' collision 1 <geometry> (line 3)",
          "needs a box, sphere, cylinder or mesh");
  refused("<robot name='r'>\n" + link("a", "\n<collision><origin xyz='0 0 1'/></collision>") +
              "</robot>",
          "link 'a' collision 0 <collision> (line 3)", "needs a <geometry>");
  // A visual is not used, but urdfdom reads its numbers.
  refused("<robot name='r'>\n" +
              link("a",
                   "<visual><origin xyz='0 0 1e999'/>"
                   "<geometry><sphere radius='0'/></geometry></visual>") +
              "</robot>",
          "link 'a' visual 0 <origin> (line 2)", "xyz: '1e999' is not a finite number");

  // Numbers urdfdom would refuse without naming the element.
  const std::string two = "<robot name='r'>\n" + link("a") + link("b");
  refused(two + joint("pitch2", "a", "b", "\n<origin xyz='nan 0 0'/>") + "</robot>",
          "joint 'pitch2' <origin> (line 5)", "xyz: 'nan' is not a finite number");
  refused(two + joint("pitch2", "a", "b", "\n<origin xyz='a b c'/>") + "</robot>",
          "joint 'pitch2' <origin> (line 5)", "xyz: 'a' is not a finite number");
  refused(two + joint("pitch2", "a", "b", "\n<origin rpy='0 0'/>") + "</robot>",
          "joint 'pitch2' <origin> (line 5)", "rpy: needs 3 numbers, got 2");
  refused(two + joint("j", "a", "b", "<axis xyz='0 0x1 0'/>") + "</robot>",
          "joint 'j' <axis> (line 4)", "xyz: '0x1' is not a finite number");
  refused(two + joint("j", "a", "b", "<dynamics damping='inf'/>") + "</robot>",
          "joint 'j' <dynamics> (line 4)", "damping: 'inf' is not a finite number");
  refused(two + joint("j", "a", "b", "<limit lower='-1' upper='1 2' effort='1' velocity='1'/>") +
              "</robot>",
          "joint 'j' <limit> (line 4)", "upper: needs 1 number, got 2");
  refused(two + joint("j", "a", "b", "<limit lower='-1' upper='1' velocity='1'/>") + "</robot>",
          "joint 'j' <limit> (line 4)", "effort: missing");
  refused(
      "<robot name='r'>\n<link name='a'><inertial><mass value='abc'/></inertial></link>"
      "</robot>",
      "link 'a' <mass> (line 2)", "value: 'abc' is not a finite number");
  refused(
      "<robot name='r'>\n<link name='a'><inertial><mass value='1'/>"
      "<inertia ixx='1' ixy='0' ixz='0' iyy='1' izz='1'/></inertial></link></robot>",
      "link 'a' <inertia> (line 2)", "iyz: missing");

  // A package that is not there: named, and where linx looked.
  refused(collision("<mesh filename='package://nopkg/m.stl'/>"), "link 'a' collision 1",
          missingPackage(dir_));

  // Not XML.
  refused("hello", "line 1", "not XML (text where an element should be)");
  refused("", "", "the file is empty");
  refused(" \n ", "", "the file holds only white space");
  refused("<robot name='r'>\n<link name='a'></robot>", "line 2",
          "not well-formed XML (an end tag does not match its start tag)");
}

TEST_F(UrdfImport, LoadModelTellsFormatsApartByExtension) {
  EXPECT_EQ(loadModel(write("a.URDF", kArmUrdf)).joints.size(), 2u);
  EXPECT_EQ(loadModel(write("a.json", kArmScene)).joints.size(), 2u);
}

}  // namespace
}  // namespace linx
