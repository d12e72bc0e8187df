// MJCF import against independent truths: a pendulum placed by euler angles and quaternions, with
// its inertial offset and turned, on an oblique hinge, swings with the physical pendulum's exact
// period; a body's mass from its geoms is the solids' closed form; default classes, childclass,
// <include> and degrees are read as MuJoCo reads them; an equality connect pins a body like a
// hinge; what linx does not use is named; bad files are refused with the element and its line.
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
constexpr double kPi = std::numbers::pi;

class MjcfImport : public ::testing::Test {
 protected:
  fs::path write(const std::string& name, const std::string& text) const {
    return folder_.write(name, text);
  }

  test::TempFolder folder_{
      "linx_mjcf_" + std::string(::testing::UnitTest::GetInstance()->current_test_info()->name())};
  const fs::path& dir_ = folder_.path();
};

Mat3 turn(const Vec3& axis, double degrees) {
  return Eigen::AngleAxisd(degrees * kPi / 180.0, axis.normalized()).toRotationMatrix();
}

// Euler angles in degrees about the axes that turn with the frame, x then y then z (MuJoCo's
// default eulerseq "xyz").
Mat3 euler(double x, double y, double z) {
  return turn(Vec3::UnitX(), x) * turn(Vec3::UnitY(), y) * turn(Vec3::UnitZ(), z);
}

const char* kPendulum = R"(<mujoco model="pendulum">
  <option timestep="0.001" gravity="0 0 -9.81"/>
  <worldbody>
    <geom name="floor" type="plane" size="5 5 0.1" pos="0 0 -3"/>
    <body name="bob" pos="0.1 0.2 1" euler="20 -10 30">
      <joint name="swing" type="hinge" pos="0.02 0 0.03" axis="0.6 0.8 0"/>
      <inertial pos="0.05 -0.3 0.1" quat="0.9 0.1 0.2 -0.3" mass="2" diaginertia="0.02 0.03 0.04"/>
      <geom type="sphere" size="0.05" pos="0.05 -0.3 0.1"/>
    </body>
  </worldbody>
</mujoco>)";

TEST_F(MjcfImport, TurnedPendulumSwingsWithThePhysicalPendulumsPeriod) {
  const Scene scene = importMjcf(write("pendulum.xml", kPendulum));
  ASSERT_EQ(scene.bodies.size(), 2u);  // the floor's static body, the bob
  ASSERT_EQ(scene.joints.size(), 1u);
  EXPECT_EQ(scene.settings.timestep, 0.001);

  const Mat3 frame = euler(20, -10, 30);
  const Vec3 origin(0.1, 0.2, 1.0);
  const Vec3 pivot = origin + frame * Vec3(0.02, 0, 0.03);
  const Vec3 axis = (frame * Vec3(0.6, 0.8, 0)).normalized();
  const Vec3 com = origin + frame * Vec3(0.05, -0.3, 0.1);
  const Mat3 principal = frame * Quat(0.9, 0.1, 0.2, -0.3).normalized().toRotationMatrix();
  const Mat3 inertia_world =
      principal * Vec3(0.02, 0.03, 0.04).asDiagonal() * principal.transpose();
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

TEST_F(MjcfImport, MassFromGeomsIsTheSolidsClosedForm) {
  const char* text = R"(<mujoco>
    <worldbody>
      <body name="dumbbell" pos="0 0 1">
        <freejoint/>
        <geom type="capsule" fromto="-0.2 0 0 0.2 0 0" size="0.05" density="500"/>
        <geom type="box" size="0.05 0.1 0.15" pos="0.3 0 0" mass="2"/>
        <geom type="cylinder" size="0.04 0.1" pos="-0.3 0 0" quat="0.7071068 0 0.7071068 0"/>
      </body>
    </worldbody>
  </mujoco>)";
  const Scene scene = importMjcf(write("dumbbell.xml", text));
  ASSERT_EQ(scene.bodies.size(), 1u);
  EXPECT_TRUE(scene.joints.empty());  // free
  const double capsule = 500.0 * (kPi * 0.05 * 0.05 * 0.4 + 4.0 / 3.0 * kPi * std::pow(0.05, 3));
  const double box = 2.0;
  const double cylinder = 1000.0 * kPi * 0.04 * 0.04 * 0.2;  // MuJoCo's default density
  const double mass = capsule + box + cylinder;
  const double x = (box * 0.3 - cylinder * 0.3) / mass;
  World world = buildWorld(scene);
  const Body& b = world.body(BodyId{0});
  EXPECT_NEAR(b.mass() / mass - 1.0, 0.0, 1e-12);
  EXPECT_NEAR(b.position().x(), x, 1e-12);
  EXPECT_NEAR(b.position().z(), 1.0, 1e-12);
  // The cylinder's axis was turned to x: its moment about x is m r^2 / 2.
  const Mat3 inertia = b.inertiaWorld();
  const double r2 = 0.05 * 0.05;  // the capsule about its axis: its cylinder and its two caps
  const double ixx = 500.0 * kPi * r2 * 0.4 * r2 / 2.0 +
                     0.4 * 500.0 * 4.0 / 3.0 * kPi * 0.05 * r2 * r2 +
                     box / 12.0 * (0.2 * 0.2 + 0.3 * 0.3) + cylinder * 0.04 * 0.04 / 2.0;
  EXPECT_NEAR(inertia(0, 0) / ixx - 1.0, 0.0, 1e-9);
}

// A cube of side 2 as OBJ quads, to be scaled.
const char* kCubeObj = R"(v -1 -1 -1
v 1 -1 -1
v 1 1 -1
v -1 1 -1
v -1 -1 1
v 1 -1 1
v 1 1 1
v -1 1 1
f 1 4 3 2
f 5 6 7 8
f 1 2 6 5
f 2 3 7 6
f 3 4 8 7
f 4 1 5 8
)";

// A mesh geom weighs as the box it is (scaled by powers of two, exact in single precision) and
// collides as its hull: dropped flat on the floor, it comes to rest on its face. A visual copy of
// it (contype and conaffinity 0) weighs too, as in MuJoCo, and is no shape.
TEST_F(MjcfImport, MeshGeomsWeighAsTheirSolidAndCollideAsTheirHull) {
  write("assets/cube.obj", kCubeObj);
  const fs::path file = write("brick.xml", R"(<mujoco>
    <compiler meshdir="assets"/>
    <asset><mesh file="cube.obj" scale="0.125 0.25 0.0625"/></asset>
    <worldbody>
      <geom type="plane" size="1 1 0.1"/>
      <body name="brick" pos="0.2 0.1 0.2">
        <freejoint/>
        <geom type="mesh" mesh="cube"/>
        <geom type="mesh" mesh="cube" contype="0" conaffinity="0" pos="0 0 0.125"/>
      </body>
    </worldbody>
  </mujoco>)");
  const Scene scene = importMjcf(file);
  ASSERT_EQ(scene.bodies.size(), 2u);
  const BodyDef& def = scene.bodies[1];
  ASSERT_EQ(def.shapes.size(), 1u);
  EXPECT_EQ(def.shapes[0].type, ShapeType::Convex);
  ASSERT_EQ(scene.warnings.size(), 1u);
  EXPECT_NE(scene.warnings[0].find("visual mesh geoms"), std::string::npos) << scene.warnings[0];
  World world = buildWorld(scene);
  const Body& brick = world.body(*world.findBody("brick"));
  const double m = 1000.0 * 0.25 * 0.5 * 0.125;  // each copy, at MuJoCo's default density
  EXPECT_NEAR(brick.mass(), 2.0 * m, 1e-12);
  EXPECT_NEAR(brick.position().z(), 0.2 + 0.0625, 1e-12);  // midway between the two copies
  // Each copy: m/12 (b^2 + c^2) about x; the two apart by 0.125 add 2 m (0.0625)^2.
  const Mat3 inertia = brick.inertiaWorld();
  EXPECT_NEAR(inertia(0, 0), 2.0 * m / 12.0 * (0.25 + 0.015625) + 2.0 * m * 0.0625 * 0.0625, 1e-12);
  EXPECT_NEAR(inertia(2, 2), 2.0 * m / 12.0 * (0.0625 + 0.25), 1e-12);
  EXPECT_NEAR(inertia(0, 1), 0.0, 1e-12);
  for (int i = 0; i < 1000; ++i) world.step();  // 2 s at MuJoCo's 2 ms
  // Resting on its collision copy's face: that copy's centre 0.0625 m up, the body's 0.0625 above.
  EXPECT_NEAR(brick.position().z(), 0.125, 2e-3);
  EXPECT_LT(brick.linearVelocity().norm(), 1e-3);
  EXPECT_NEAR(brick.position().x(), 0.2, 1e-6);
}

TEST_F(MjcfImport, DefaultClassesChildclassIncludeAndDegrees) {
  write("arm_defaults.xml", R"(<mujoco>
    <default>
      <joint damping="1" stiffness="3"/>
      <default class="soft">
        <joint damping="0.5" frictionloss="0.1"/>
        <default class="stiff"><joint stiffness="30" springref="10"/></default>
      </default>
    </default>
  </mujoco>)");
  const char* text = R"(<mujoco>
    <include file="arm_defaults.xml"/>
    <worldbody>
      <body name="upper" pos="0 0 2">
        <joint name="shoulder" class="stiff" axis="0 1 0" range="-90 90" ref="5"/>
        <geom type="capsule" fromto="0 0 0 0 0 -1" size="0.05"/>
        <body name="lower" pos="0 0 -1" childclass="soft">
          <joint name="elbow" axis="0 1 0" range="-45 90"/>
          <geom type="capsule" fromto="0 0 0 0 0 -1" size="0.05"/>
        </body>
      </body>
    </worldbody>
  </mujoco>)";
  const Scene scene = importMjcf(write("arm.xml", text));
  ASSERT_EQ(scene.joints.size(), 2u);
  const CoordinateDef& shoulder = scene.joints[0].def.coordinates[0];
  ASSERT_TRUE(shoulder.spring && shoulder.limits);
  EXPECT_EQ(shoulder.spring->stiffness, 30.0);  // "stiff"
  EXPECT_EQ(shoulder.spring->damping, 0.5);     // inherited from "soft"
  EXPECT_DOUBLE_EQ(shoulder.spring->rest, 10.0 * kPi / 180.0);
  EXPECT_DOUBLE_EQ(shoulder.reference, 5.0 * kPi / 180.0);
  EXPECT_DOUBLE_EQ(shoulder.limits->lower, -kPi / 2);
  EXPECT_EQ(shoulder.friction, 0.1);
  const CoordinateDef& elbow = scene.joints[1].def.coordinates[0];  // childclass "soft"
  ASSERT_TRUE(elbow.spring && elbow.limits);
  EXPECT_EQ(elbow.spring->stiffness, 3.0);  // from main
  EXPECT_EQ(elbow.spring->damping, 0.5);
  EXPECT_DOUBLE_EQ(elbow.limits->upper, kPi / 2);
  EXPECT_EQ(scene.joints[1].def.body2, BodyId{0});
  EXPECT_TRUE(scene.joints[1].def.anchor->isApprox(Vec3(0, 0, 1)));
  EXPECT_NO_THROW(buildWorld(scene));
}

TEST_F(MjcfImport, ConnectEqualityPinsABodyLikeAHinge) {
  // A free 1 m rod pinned to the world at its end by a connect (a ball joint), released level:
  // nothing pushes it out of its vertical plane, so it swings as a physical pendulum of amplitude
  // 90 degrees about its end.
  const char* text = R"(<mujoco>
    <option timestep="0.001"/>
    <worldbody>
      <body name="rod" pos="0 0 0">
        <freejoint/>
        <inertial pos="0.5 0 0" mass="1" diaginertia="0.0001 0.083333333333333 0.083333333333333"/>
      </body>
    </worldbody>
    <equality><connect body1="rod" anchor="0 0 0"/></equality>
  </mujoco>)";
  const Scene scene = importMjcf(write("pin.xml", text));
  ASSERT_EQ(scene.joints.size(), 1u);
  EXPECT_EQ(scene.joints[0].type, "ball");
  World world = buildWorld(scene);
  std::vector<double> t, z;
  for (int i = 0; i < 5000; ++i) {
    world.step();
    t.push_back(world.time());
    z.push_back(world.body(BodyId{0}).position().x());
  }
  const std::vector<double> up = test::upwardCrossings(t, z);
  ASSERT_GE(up.size(), 2u);
  const double measured = (up.back() - up.front()) / static_cast<double>(up.size() - 1);
  const double period = test::pendulumPeriod(0.083333333333333 + 0.25, 1.0, 9.81, 0.5, kPi / 2);
  std::printf("connect: period %.9f s (closed form %.9f s)\n", measured, period);
  EXPECT_NEAR(measured / period - 1.0, 0.0, 1e-3);
}

TEST_F(MjcfImport, ABallJointsRangeBoundsItsRotation) {
  // An arm on a ball joint with range 0 to 23 degrees, built level: gravity swings it down onto
  // its bound, where it rests at 23 degrees below the horizontal.
  const char* text = R"(<mujoco>
    <worldbody>
      <body name="arm" pos="0 0 1">
        <joint name="shoulder" type="ball" range="0 23"/>
        <geom type="sphere" pos="1 0 0" size="0.05" mass="1"/>
      </body>
    </worldbody>
  </mujoco>)";
  const Scene scene = importMjcf(write("ball.xml", text));
  ASSERT_EQ(scene.joints.size(), 1u);
  ASSERT_TRUE(scene.joints[0].def.coordinates[0].limits);
  const double bound = 23 * kPi / 180;
  EXPECT_DOUBLE_EQ(scene.joints[0].def.coordinates[0].limits->upper, bound);
  EXPECT_TRUE(scene.warnings.empty()) << scene.warnings.front();
  World world = buildWorld(scene);
  for (int i = 0; i < 3000; ++i) world.step();
  const Vec3 rest = Vec3(0, 0, 1) + Vec3(std::cos(bound), 0, -std::sin(bound));
  const Vec3 at = world.body(BodyId{0}).position();
  std::printf("ball range 23 deg: the arm rests %.2e m from its closed-form pose\n",
              (at - rest).norm());
  EXPECT_LT((at - rest).norm(), 1e-5);
}

TEST_F(MjcfImport, WhatLinxDoesNotUseIsNamedInOneWarning) {
  const char* text = R"(<mujoco>
    <compiler angle="radian" coordinate="local"/>
    <asset><texture name="t" builtin="flat"/></asset>
    <worldbody>
      <light pos="0 0 3"/>
      <body name="a" pos="0 0 1">
        <joint name="j" axis="0 1 0" armature="0.1"/>
        <geom type="sphere" size="0.1"/>
        <site name="s"/>
      </body>
    </worldbody>
    <actuator><motor joint="j" gear="10"/><general joint="j" dyntype="filter"/></actuator>
    <sensor><jointpos joint="j"/></sensor>
  </mujoco>)";
  const Scene scene = importMjcf(write("extras.xml", text));
  ASSERT_EQ(scene.warnings.size(), 1u);
  const std::string& w = scene.warnings[0];
  for (const char* named : {"<actuator><general> with activation (dyntype)", "<sensor>", "<light>",
                            "<site>", "<compiler coordinate>", "<asset><texture>"})
    EXPECT_NE(w.find(named), std::string::npos) << named << " not in: " << w;
  EXPECT_EQ(w.find("armature"), std::string::npos) << w;  // read: the coordinate's armature
  EXPECT_EQ(scene.joints[0].def.coordinates[0].armature, 0.1);
  ASSERT_TRUE(scene.joints[0].def.coordinates[0].force);  // the motor, at zero control
  EXPECT_EQ(scene.joints[0].def.coordinates[0].force->at(0.0), 0.0);
}

TEST_F(MjcfImport, PositionAndVelocityActuatorsAtZeroControlAreSpringsAndDampers) {
  // A flywheel (I = 0.1 about its hinge) built at ref = 30 degrees with a position actuator kp = 2,
  // gear 3: at zero control MuJoCo's force kp (0 - g q) on a length g q is a spring of stiffness
  // kp g^2 towards 0: it swings with amplitude pi / 6 and period 2 pi sqrt(I / (kp g^2)). A
  // velocity actuator kv = 0.5, gear 2 is a damper kv g^2, forcerange bounds it times the gear.
  const char* text = R"(<mujoco>
    <option gravity="0 0 0" timestep="0.001"/>
    <worldbody>
      <body name="wheel">
        <joint name="turn" axis="0 0 1" ref="30" limited="false"/>
        <inertial pos="0 0 0" mass="1" diaginertia="0.1 0.1 0.1"/>
      </body>
      <body name="other" pos="1 0 0">
        <joint name="spin" axis="0 0 1"/>
        <inertial pos="0 0 0" mass="1" diaginertia="0.1 0.1 0.1"/>
      </body>
    </worldbody>
    <actuator>
      <position joint="turn" kp="2" gear="3"/>
      <velocity joint="spin" kv="0.5" gear="2" forcerange="-4 4"/>
    </actuator>
  </mujoco>)";
  const Scene scene = importMjcf(write("actuators.xml", text));
  EXPECT_TRUE(scene.warnings.empty()) << scene.warnings[0];
  const JointMotor& damper = *scene.joints[1].def.coordinates[0].motor;
  EXPECT_EQ(damper.damping, 0.5 * 4);
  EXPECT_EQ(damper.max_force, 8.0);
  World world = buildWorld(scene);
  const test::Oscillation o = test::jointOscillation(world, JointId{0}, 3000);
  const double period = 2.0 * kPi * std::sqrt(0.1 / (2.0 * 9.0));
  std::printf("position actuator: amplitude %.6f rad (pi / 6), period %.6f s (closed form %.6f)\n",
              o.amplitude, o.period, period);
  EXPECT_NEAR(o.amplitude, kPi / 6.0, 1e-3);
  EXPECT_NEAR(o.period / period, 1.0, 1e-3);
}

// An include inside an included file splices in too (its elements were dropped: tinyxml2 inserts
// no node of another document), and the body it holds has its geom's mass: a 0.1 m sphere of
// density 1000, 4/3 pi r^3 rho.
TEST_F(MjcfImport, NestedIncludesSpliceTheirElements) {
  write("parts/arm.xml",
        "<mujoco><worldbody><body name='arm'><freejoint/><geom size='0.1'/></body></worldbody>"
        "</mujoco>");
  write("parts/outer.xml", "<mujoco><include file='arm.xml'/></mujoco>");
  const Scene scene =
      importMjcf(write("robot.xml", "<mujoco><include file='parts/outer.xml'/></mujoco>"));
  ASSERT_EQ(scene.bodies.size(), 1u);
  EXPECT_EQ(scene.bodies[0].name, "arm");
  ASSERT_TRUE(scene.bodies[0].mass);
  EXPECT_NEAR(*scene.bodies[0].mass, 4.0 / 3.0 * kPi * 1e-3 * 1000.0, 1e-12);
}

// A joint whose ref lies outside its range (Menagerie's A1, Gym's ant) is loaded, as MuJoCo loads
// it: it starts at its nearest bound, the bodies placed there at rest, so the first step makes no
// energy; one warning names every such joint; a scene file written from it starts the same.
TEST_F(MjcfImport, JointStartingOutsideItsRangeStartsAtItsNearestBound) {
  const Scene scene = importMjcf(write("arm.xml", R"(<mujoco>
  <worldbody>
    <body name="upper" pos="0 0 2">
      <joint name="shoulder" type="hinge" axis="0 1 0" range="-30 30"/>
      <geom type="capsule" fromto="0 0 0 0.5 0 0" size="0.05" mass="1"/>
      <body name="lower" pos="0.5 0 0">
        <joint name="elbow" type="hinge" axis="0 1 0" range="30 90"/>
        <geom type="capsule" fromto="0 0 0 0.5 0 0" size="0.05" mass="1"/>
        <body name="hand" pos="0.5 0 0">
          <joint name="wrist" type="slide" axis="1 0 0" range="0.1 0.2" ref="0.3"/>
          <geom type="sphere" size="0.05" mass="0.5"/>
        </body>
      </body>
    </body>
  </worldbody>
</mujoco>)"));
  ASSERT_EQ(scene.warnings.size(), 1u);
  EXPECT_EQ(scene.warnings[0],
            (dir_ / "arm.xml").string() +
                ": 2 joints start outside their range, moved to the nearest bound (the bodies "
                "placed there at rest, as MuJoCo and PyBullet load it): 'elbow' at 0 rad, range "
                "[0.523599, 1.5708]; 'wrist' at 0.3 m, range [0.1, 0.2]");
  World world = buildWorld(scene);
  const JointId elbow{1}, wrist{2};
  EXPECT_NEAR(world.jointCoordinates(elbow)[0], kPi / 6, 1e-12);
  EXPECT_NEAR(world.jointCoordinates(wrist)[0], 0.2, 1e-12);  // counted with its ref
  EXPECT_LT(world.jointError(elbow), 1e-12);
  for (int b = 0; b < world.bodyCount(); ++b)
    EXPECT_EQ(world.body(BodyId{b}).linearVelocity().norm(), 0.0);
  // Undriven and undamped: the swing keeps its energy (no kick from the limits), and the elbow
  // never leaves its range.
  const double start = world.energy().total();
  double lowest_elbow = kPi;
  for (int i = 0; i < 1000; ++i) {
    world.step();
    lowest_elbow = std::min(lowest_elbow, world.jointCoordinates(elbow)[0]);
    EXPECT_LT(world.energy().total(), start + 1e-6) << "step " << i;
  }
  EXPECT_GT(lowest_elbow, kPi / 6 - 1e-6);
  // Written as a scene file, it starts where the import does (the joints' `initial`).
  const Scene written = parseScene(writeSceneJson(scene), "arm.json");
  EXPECT_NEAR(buildWorld(written).jointCoordinates(elbow)[0], kPi / 6, 1e-12);
}

TEST_F(MjcfImport, BadFilesAreRefusedWithTheElementAndItsLine) {
  const auto refused = [&](const std::string& text, const std::string& expected) {
    const fs::path file = write("bad.xml", text);
    try {
      importMjcf(file);
      ADD_FAILURE() << "accepted; expected: " << expected;
    } catch (const SceneError& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find(file.string()), std::string::npos) << what;
      EXPECT_NE(what.find(expected), std::string::npos) << what;
    }
  };
  refused("<mujoco><worldbody>", "not well-formed XML");
  refused("<robot/>", "needs a <mujoco> element");
  refused(
      "<mujoco><worldbody>\n<body name='b'><joint/><joint type='ball'/><geom size='1'/></body>"
      "</worldbody></mujoco>",
      "joint (line 2): type: a ball joint with other joints in one body (linx takes hinges and "
      "slides there)");
  refused(
      "<mujoco><worldbody><body><freejoint/><geom type='hfield' size='1 2 3'/></body>"
      "</worldbody></mujoco>",
      "type: 'hfield' is not a geom type linx reads");
  refused(
      "<mujoco><worldbody><body><freejoint/><geom type='ellipsoid' size='1 2'/></body>"
      "</worldbody></mujoco>",
      "size: an ellipsoid needs 3 numbers");
  refused("<mujoco><worldbody><body><freejoint/><geom size='1 x'/></body></worldbody></mujoco>",
          "size: 'x' is not a finite number");
  refused("<mujoco><worldbody><body name='b'><joint/></body></worldbody></mujoco>",
          "body 'b' (line 1): a moving body needs an <inertial> or geoms");
  write("bad.xml", "<mujoco><include file='nowhere.xml'/></mujoco>");
  try {
    importMjcf(dir_ / "bad.xml");
    ADD_FAILURE() << "a missing include was accepted";
  } catch (const SceneError& e) {  // the including file and element, then the included file
    EXPECT_EQ(e.file(), (dir_ / "bad.xml").string());
    EXPECT_EQ(e.field(), "include (line 1)");
    EXPECT_EQ(e.problem(), "file 'nowhere.xml': cannot open: No such file or directory");
  }
  refused(
      "<mujoco><worldbody><body><joint range='1 -1'/><geom size='1'/></body></worldbody>"
      "</mujoco>",
      "range: the lower end is above the upper");
  refused(
      "<mujoco><worldbody><body childclass='nope'><freejoint/><geom size='1'/></body>"
      "</worldbody></mujoco>",
      "no default class 'nope'");
  refused(
      "<mujoco><worldbody><body name='b'><freejoint/>"
      "<inertial mass='1' diaginertia='1 -1 1'/></body></worldbody></mujoco>",
      "body 'b': inertia: ");
  // Meshes: a file that is not there, a mesh not defined, a primitive fitted to a mesh, a flat
  // mesh (no volume: MuJoCo refuses it), a file outside the model's folder.
  write("flat.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nf 1 2 4 3\n");
  const auto meshGeom = [&](const std::string& asset, const std::string& geom) {
    return "<mujoco><asset>\n" + asset + "</asset><worldbody><body><freejoint/>\n<geom " + geom +
           "/></body></worldbody></mujoco>";
  };
  refused(meshGeom("<mesh file='gone.obj'/>", "type='mesh' mesh='gone'"),
          "mesh (line 2): mesh file " + (dir_ / "gone.obj").string() + ": cannot open");
  refused(meshGeom("<mesh file='flat.obj'/>", "type='mesh' mesh='nothing'"),
          "geom (line 3): mesh: no mesh 'nothing'");
  refused(meshGeom("<mesh file='flat.obj'/>", "mesh='flat'"),
          "geom (line 3): mesh: a sphere fitted to a mesh is not read");
  refused(meshGeom("<mesh file='flat.obj'/>", "type='mesh' mesh='flat'"),
          "mesh (line 2): file 'flat.obj': the mesh's volume is too small (MuJoCo refuses it too)");
  refused(meshGeom("<mesh name='out' file='../outside.obj'/>", "type='mesh' mesh='out'"),
          "mesh 'out' (line 2): ");
  // A fault in an element an include copied in: the element's own file and line (a copy has no
  // line of its own: it was named at "line 0"), through nested includes too.
  write("parts/arm.xml",
        "<mujoco>\n<worldbody>\n<body name='arm'>\n<geom name='g' size='abc'/>\n</body>\n"
        "</worldbody>\n</mujoco>");
  refused("<mujoco>\n<include file='parts/arm.xml'/>\n</mujoco>",
          "geom 'g' (parts/arm.xml, line 4): size: 'abc' is not a finite number");
  write("parts/outer.xml", "<mujoco>\n\n<include file='arm.xml'/></mujoco>");
  refused("<mujoco>\n<include file='parts/outer.xml'/>\n</mujoco>",
          "geom 'g' (parts/arm.xml, line 4): size: 'abc' is not a finite number");
}

// Hostile files (a bad-input hunt): each refused with the exact element, line and problem, never
// with tinyxml2's own text, nor by a later check that names what the file does not hold.
TEST_F(MjcfImport, HostileFilesAreRefusedInPlainWords) {
  // `file` refused, the fault in `in` (file, or a file it includes).
  const auto refusedIn = [&](const fs::path& file, const fs::path& in, const std::string& field,
                             const std::string& problem) {
    try {
      importMjcf(file);
      ADD_FAILURE() << "accepted; expected: " << field << ": " << problem;
    } catch (const SceneError& e) {
      EXPECT_EQ(e.file(), in.string());
      EXPECT_EQ(e.field(), field);
      EXPECT_EQ(e.problem(), problem);
    }
  };
  const auto refused = [&](const fs::path& file, const std::string& field,
                           const std::string& problem) { refusedIn(file, file, field, problem); };
  const auto bad = [&](const std::string& text) { return write("bad.xml", text); };
  refused(bad("hello"), "line 1", "not XML (text where an element should be)");
  refused(bad("hello <"), "line 1", "not XML (text where an element should be)");
  refused(bad(""), "", "the file is empty");
  refused(bad("<mujoco>\n<worldbody></mujoco>"), "line 2",
          "not well-formed XML (an end tag does not match its start tag)");

  // <option>: a step that is not > 0 (it was refused later, as a run's duration).
  const std::string body =
      "<worldbody><body><freejoint/><geom size='0.1'/></body></worldbody></mujoco>";
  refused(bad("<mujoco>\n<option timestep='0'/>" + body), "option (line 2)",
          "timestep: must be > 0, got 0");
  refused(bad("<mujoco>\n<option timestep='-1'/>" + body), "option (line 2)",
          "timestep: must be > 0, got -1");
  refused(bad("<mujoco>\n<option timestep='nan'/>" + body), "option (line 2)",
          "timestep: 'nan' is not a finite number");

  // Sizes a shape uses must be > 0 (a plane's are only drawn).
  const auto geom = [&](const std::string& attributes) {
    return bad("<mujoco><worldbody>\n<body><freejoint/><geom " + attributes +
               "/></body></worldbody></mujoco>");
  };
  refused(geom("size='-0.1'"), "geom (line 2)", "size: the radius must be > 0, got -0.1");
  refused(geom("type='capsule' size='0.1 0'"), "geom (line 2)",
          "size: the radius and half-length must be > 0, got 0.1 0");
  refused(geom("type='cylinder' size='0' fromto='0 0 0 0 0 1'"), "geom (line 2)",
          "size: the radius must be > 0, got 0");
  refused(geom("type='box' size='1 0 1'"), "geom (line 2)",
          "size: the 3 half-sizes must be > 0, got 1 0 1");

  // contype and conaffinity are 32 bits (a cast of -1 or 1e10 was undefined).
  refused(bad("<mujoco><worldbody>\n<geom type='plane' size='1 1 1' contype='-1'/>"
              "</worldbody></mujoco>"),
          "geom (line 2)", "contype: must be a whole number in [0, 4294967295], got -1");
  refused(bad("<mujoco><worldbody>\n<geom type='plane' size='1 1 1' conaffinity='0.5'/>"
              "</worldbody></mujoco>"),
          "geom (line 2)", "conaffinity: must be a whole number in [0, 4294967295], got 0.5");

  // An include: the including file and the <include>'s line; a fault inside it: that file.
  refused(bad("<mujoco>\n<include file='nothere.xml'/>" + body), "include (line 2)",
          "file 'nothere.xml': cannot open: No such file or directory");
  const fs::path inner =
      write("parts/inner.xml", "<mujoco>\n\n<include file='gone.xml'/></mujoco>");
  refusedIn(bad("<mujoco>\n<include file='parts/inner.xml'/>" + body), inner, "include (line 3)",
            "file 'gone.xml': cannot open: No such file or directory");
  const fs::path broken = write("broken.xml", "<mujoco>\n<worldbody>\n</mujoco>");
  refusedIn(bad("<mujoco>\n<include file='broken.xml'/>" + body), broken, "line 2",
            "not well-formed XML (an end tag does not match its start tag)");
  const fs::path empty = write("empty.xml", "");
  refusedIn(bad("<mujoco>\n<include file='empty.xml'/>" + body), empty, "", "the file is empty");
}

}  // namespace
}  // namespace linx
