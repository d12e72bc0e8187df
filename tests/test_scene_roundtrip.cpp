// Writing scenes back (writeSceneJson): every example scene and robot, written and read again,
// builds a world that moves to the bit as the original does, and writing the re-read scene gives
// the same text.
#include <linx/import.hpp>
#include <linx/scene.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace {

// The example scenes and robots, in a stable order.
std::vector<std::filesystem::path> exampleModels() {
  std::vector<std::filesystem::path> models;
  const std::filesystem::path dir = LINX_EXAMPLES_DIR;
  for (const auto& folder : {dir, dir / "robots"})
    for (const auto& entry : std::filesystem::directory_iterator(folder)) {
      const auto ext = entry.path().extension();
      if (ext == ".json" || ext == ".urdf" || ext == ".xml") models.push_back(entry.path());
    }
  std::sort(models.begin(), models.end());
  return models;
}

// Steps `world` up to `steps` times; the number of steps taken before a fault stopped it.
int stepWorld(linx::World& world, int steps) {
  for (int i = 0; i < steps; ++i) {
    try {
      world.step();
    } catch (const linx::StepFault&) {
      return i;
    }
  }
  return steps;
}

void expectSameBits(const linx::Vec3& a, const linx::Vec3& b, const char* what) {
  for (int k = 0; k < 3; ++k) EXPECT_EQ(a[k], b[k]) << what << "[" << k << "]";
}

// Builds both scenes, steps both, and compares every body's state to the bit.
void expectSameMotion(const linx::Scene& original, const linx::Scene& reread, int steps) {
  linx::World a = linx::buildWorld(original);
  linx::World b = linx::buildWorld(reread);
  ASSERT_EQ(a.bodyCount(), b.bodyCount());
  ASSERT_EQ(a.jointCount(), b.jointCount());
  EXPECT_EQ(stepWorld(a, steps), stepWorld(b, steps));
  for (int i = 0; i < a.bodyCount(); ++i) {
    SCOPED_TRACE(a.body(linx::BodyId{i}).name());
    const linx::Body& x = a.body(linx::BodyId{i});
    const linx::Body& y = b.body(linx::BodyId{i});
    expectSameBits(x.position(), y.position(), "position");
    EXPECT_EQ(x.orientation().w(), y.orientation().w());
    expectSameBits(x.orientation().vec(), y.orientation().vec(), "orientation");
    expectSameBits(x.linearVelocity(), y.linearVelocity(), "linear velocity");
    expectSameBits(x.angularVelocity(), y.angularVelocity(), "angular velocity");
  }
}

// Writes `scene`, reads it back, and checks the motion and that writing again changes nothing.
void expectRoundTrip(const linx::Scene& scene, int steps) {
  const std::string text = linx::writeSceneJson(scene);
  ASSERT_FALSE(text.empty());
  EXPECT_EQ(text.back(), '\n');
  const linx::Scene reread = linx::parseScene(text, scene.file + " (written)");
  expectSameMotion(scene, reread, steps);
  EXPECT_EQ(linx::writeSceneJson(reread), text) << "writing is not idempotent";
}

TEST(SceneRoundTrip, EveryExampleMovesTheSameToTheBit) {
  const auto models = exampleModels();
  ASSERT_GE(models.size(), 20u);
  for (const auto& path : models) {
    SCOPED_TRACE(path.filename().string());
    expectRoundTrip(linx::loadModel(path), 200);
  }
}

TEST(SceneRoundTrip, FloatingBaseRobot) {
  const auto path = std::filesystem::path(LINX_EXAMPLES_DIR) / "robots" / "three_link_arm.urdf";
  expectRoundTrip(linx::loadModel(path, linx::ImportOptions{.floating_base = true}), 200);
}

TEST(SceneRoundTrip, UrdfRobotReadsBackToTheSameBodiesAndJoints) {
  const auto path = std::filesystem::path(LINX_EXAMPLES_DIR) / "robots" / "three_link_arm.urdf";
  const linx::Scene robot = linx::importUrdf(path);
  const linx::Scene scene = linx::parseScene(linx::writeSceneJson(robot), "robot.json");
  ASSERT_EQ(scene.bodies.size(), robot.bodies.size());
  for (std::size_t i = 0; i < robot.bodies.size(); ++i) {
    const linx::BodyDef &a = robot.bodies[i], &b = scene.bodies[i];
    SCOPED_TRACE(a.name);
    EXPECT_EQ(b.name, a.name);
    EXPECT_EQ(b.is_static, a.is_static);
    EXPECT_EQ(b.mass, a.mass);
    expectSameBits(b.position, a.position, "position");
    EXPECT_EQ(b.orientation.coeffs(), a.orientation.coeffs());
    ASSERT_EQ(b.inertia.has_value(), a.inertia.has_value());
    if (a.inertia) {
      // Written symmetrized, as Body makes it.
      const linx::Mat3 symmetric = 0.5 * (*a.inertia + a.inertia->transpose());
      EXPECT_EQ(*b.inertia, symmetric);
    }
    ASSERT_EQ(b.shapes.size(), a.shapes.size());
    for (std::size_t k = 0; k < a.shapes.size(); ++k) {
      EXPECT_EQ(b.shapes[k].type, a.shapes[k].type);
      expectSameBits(b.shapes[k].position, a.shapes[k].position, "shape position");
      EXPECT_EQ(b.shapes[k].orientation.coeffs(), a.shapes[k].orientation.coeffs());
    }
  }
  ASSERT_EQ(scene.joints.size(), robot.joints.size());
  ASSERT_FALSE(robot.joints.empty());
  for (std::size_t i = 0; i < robot.joints.size(); ++i) {
    const linx::SceneJoint &a = robot.joints[i], &b = scene.joints[i];
    SCOPED_TRACE(a.def.name);
    EXPECT_EQ(b.type, a.type);
    EXPECT_EQ(b.def.name, a.def.name);
    EXPECT_EQ(b.def.body1, a.def.body1);
    EXPECT_EQ(b.def.body2, a.def.body2);
    EXPECT_EQ(b.def.anchor, a.def.anchor);
    if (a.type != "fixed") expectSameBits(b.def.axis, a.def.axis, "axis");
    const linx::CoordinateDef &x = a.def.coordinates[0], &y = b.def.coordinates[0];
    ASSERT_EQ(y.limits.has_value(), x.limits.has_value());
    if (x.limits) {
      EXPECT_EQ(y.limits->lower, x.limits->lower);
      EXPECT_EQ(y.limits->upper, x.limits->upper);
    }
    EXPECT_EQ(y.friction, x.friction);
    ASSERT_EQ(y.motor.has_value(), x.motor.has_value());
    ASSERT_EQ(y.spring.has_value(), x.spring.has_value());
  }
}

// Axes and frames turned by a model's nested body frames come out a few units in the last place
// off unit length: no vector normalizes to them exactly, so a unit vector is read as written
// (ANYmal C and UR5e from the MuJoCo Menagerie could not be converted).
TEST(SceneRoundTrip, AxesTurnedByNestedFramesReadBackToTheBit) {
  const auto dir = std::filesystem::temp_directory_path() / "linx_roundtrip_axes";
  std::filesystem::create_directories(dir);
  const auto path = dir / "nested.xml";
  {
    std::ofstream out(path);
    out << R"(<mujoco>
  <worldbody>
    <body name="a" pos="0 0 1" quat="1 0 0 1">
      <geom type="box" size="0.1 0.1 0.1" mass="1"/>
      <body name="b" pos="0.3 0 0" quat="1 0 0 1">
        <joint name="j1" type="hinge" axis="0.3 0.1 0.9"/>
        <geom type="capsule" size="0.05 0.1" mass="1"/>
        <body name="c" pos="0.3 0 0" quat="0.9 0.1 0.3 1">
          <joint name="j2" type="hinge" axis="1 2 3"/>
          <joint name="j3" type="slide" axis="0.2 0.7 0.1"/>
          <geom type="sphere" size="0.05" mass="1"/>
        </body>
      </body>
    </body>
  </worldbody>
</mujoco>
)";
  }
  const linx::Scene model = linx::importMjcf(path);
  expectRoundTrip(model, 100);
  std::filesystem::remove_all(dir);
}

// Fields the examples do not all use: every joint type and coordinate field, tables, a kinematic
// body on a path, a top-level spring, forces at points and torques, contact stiffness, the view.
TEST(SceneRoundTrip, EveryFieldOfTheFormat) {
  const linx::Scene scene = linx::parseScene(R"({
    "gravity": [0.1, -0.2, -9.7], "timestep": 0.002, "duration": 0.5, "threads": 2,
    "solver": {"type": "pgs", "iterations": 40, "tolerance": 1e-9, "erp": 0.3, "cfm": 1e-9,
               "warm_start": false, "sor": 1.2, "substeps": 2, "post_stabilization": 2,
               "projection": true, "projection_iterations": 4, "projection_tolerance": 1e-11,
               "geometric_stiffness": false},
    "contact": {"enabled": true, "margin": 0.02, "slop": 0.001, "stiffness": 1e5,
                "damping": 100, "restitution_threshold": 0.3, "max_push_out": 2, "hertz": 30,
                "damping_ratio": 5},
    "sleep": {"enabled": false, "linear_velocity": 0.01, "angular_velocity": 0.02, "time": 1},
    "faults": {"energy": false, "kinetic_fraction": 0.7, "height": 0.2, "speed": 4},
    "view": {"eye": [3, 3, 2], "target": [0, 0, 0.5], "up": [0, 0.1, 3], "fov": 50},
    "bodies": [
      {"name": "ground", "static": true, "shapes": [
        {"type": "plane", "normal": [0.1, 0, 1], "offset": -0.5, "friction": 0.8},
        {"type": "mesh", "points": [[-5, -5, -1], [5, -5, -1], [0, 5, -1]],
         "triangles": [[0, 1, 2]], "restitution": 0.2, "group": 2, "mask": 5}]},
      {"name": "cart", "kinematic": true, "position": [0, 0, 2],
       "path": [{"times": [0, 1], "values": [0, 0.5]}, 0, 2],
       "shapes": [{"type": "box", "size": [0.4, 0.2, 0.1]}]},
      {"name": "a", "mass": 2, "inertia": [[0.1, 0.01, 0], [0.01, 0.2, 0], [0, 0, 0.3]],
       "position": [1, 0, 1], "orientation": [1, 0.2, 0.1, 0.3], "linear_velocity": [0, 1, 0],
       "angular_velocity": [0.5, 0, 0], "linear_damping": 0.1, "angular_damping": 0.2,
       "shapes": [{"type": "capsule", "radius": 0.1, "length": 0.3, "position": [0, 0, 0.1],
                   "orientation": [0.9, 0, 0.3, 0]}]},
      {"name": "b", "position": [2, 0, 1], "orientation": [0.3, 0.4, 0.5, 0.6], "shapes": [
        {"type": "cylinder", "radius": 0.1, "length": 0.3, "density": 500,
         "position": [0.1, 0.2, 0], "orientation": [1, 1, 0, 0]},
        {"type": "convex", "points": [[0, 0, 0], [0.2, 0, 0], [0, 0.2, 0], [0, 0, 0.2]],
         "density": 800}]},
      {"name": "c", "mass": 1, "position": [3, 0, 1],
       "shapes": [{"type": "sphere", "radius": 0.1}]},
      {"name": "d", "mass": 1, "position": [4, 0, 1],
       "shapes": [{"type": "sphere", "radius": 0.1}]},
      {"name": "e", "mass": 1, "position": [5, 0, 1],
       "shapes": [{"type": "sphere", "radius": 0.1}]}
    ],
    "joints": [
      {"name": "slide", "type": "slider", "body1": "a", "axis": [1, 1, 0],
       "limits": {"lower": -0.5}, "friction": 0.1, "reference": 0.05,
       "erp": 0.5, "cfm": 1e-8, "collide": true, "break_force": 1000, "break_torque": 500},
      {"name": "u", "type": "universal", "body1": "b", "body2": "a", "anchor": [1.5, 0, 1],
       "axis1": [0, 0, 1], "axis2": [0, 1, 0],
       "angle1": {"motor": {"target_velocity": {"times": [0, 0.2], "values": [0, 1]},
                            "max_force": 5}},
       "angle2": {"motor": {"target_position": 0.3, "stiffness": 10, "damping": 1}}},
      {"name": "g", "type": "generic", "body1": "c", "body2": "b", "anchor": [2.5, 0, 1],
       "axis1": [1, 0, 0], "axis2": [0, 1, 0],
       "x": {"locked": true}, "y": {"spring": {"stiffness": 100, "damping": 1, "rest": 0.1}},
       "z": {"prescribed": {"times": [0, 1], "values": [0, 0.1]}},
       "rx": {"locked": true}, "ry": {"locked": true}, "rz": {"locked": true}},
      {"name": "cone", "type": "cone_twist", "body1": "d", "body2": "c", "anchor": [3.5, 0, 1],
       "axis1": [1, 0, 0], "axis2": [0, 1, 0], "cone": {"swing1": 0.5, "swing2": 0.3}},
      {"name": "rope", "type": "distance", "body1": "d", "anchor1": [4, 0, 1.1],
       "anchor2": [4, 0, 3], "length": 2, "rope": true},
      {"name": "h", "type": "hinge", "body1": "e", "anchor": [5, 0, 1.5], "axis": [0, 1, 0],
       "limits": {"lower": -1, "upper": 1}, "reference": 0.1, "initial": 0.2}
    ],
    "springs": [{"name": "s", "body1": "c", "anchor2": [3, 0, 3], "stiffness": 50,
                 "damping": 0.5}],
    "forces": [{"body": "a", "force": [1, {"times": [0, 0.1], "values": [0, 2]}, 0],
                "point": [1, 0, 1.1]},
               {"body": "b", "force": {"times": [0, 0.5], "values": [[0, 0, 1], [0, 0, 2]]}}],
    "torques": [{"body": "c", "torque": [0, 0, 0.1]}]
  })",
                                             "every_field.json");
  expectRoundTrip(scene, 200);
  const std::string text = linx::writeSceneJson(scene);
  for (const char* field : {"\"kinematic\"", "\"path\"", "\"stiffness\"", "\"view\"", "\"cone\"",
                            "\"rope\"", "\"prescribed\"", "\"springs\"", "\"torques\"",
                            "\"reference\"", "\"initial\"", "\"break_torque\"", "\"mask\""})
    EXPECT_NE(text.find(field), std::string::npos) << field;
}

TEST(SceneRoundTrip, RefusesWhatAFileCannotHold) {
  linx::Scene scene = linx::parseScene(R"({"bodies": [
      {"name": "a", "mass": 1, "shapes": [{"type": "sphere", "radius": 0.1}]}]})",
                                       "a.json");
  linx::LoadDef both;
  both.body = linx::BodyId{0};
  both.force = linx::Vec3(1, 0, 0);
  both.torque = linx::Vec3(0, 0, 1);
  scene.loads.push_back({"", both});
  EXPECT_THROW(linx::writeSceneJson(scene), std::runtime_error);

  scene.loads.clear();
  linx::SceneJoint motor{"hinge", {}};
  motor.def.name = "h";
  motor.def.body1 = linx::BodyId{0};
  motor.def.anchor = linx::Vec3::Zero();
  motor.def.coordinates[0].motor = linx::JointMotor{};  // a velocity motor without a bound
  scene.joints.push_back(motor);
  try {
    linx::writeSceneJson(scene);
    ADD_FAILURE() << "an unbounded velocity motor was written";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("joints[0].motor.max_force"), std::string::npos)
        << e.what();
  }
}

}  // namespace
