// Reading a run back (src/viz/run.*), the scene's `view`, and the camera (src/viz/camera.*).
// A run is recorded from a world stepped here, so the truth is the world's own state at each
// recorded step; hull geometry is checked against the closed-form volume of a cube, and the
// camera against plain projective geometry.
#include <linx/linx.hpp>

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <csignal>
#include <cstdio>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <string>
#include <vector>

#include "viz/camera.hpp"
#include "viz/run.hpp"

namespace fs = std::filesystem;
using linx::Vec3;

namespace {

class VizRun : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    root_ = fs::temp_directory_path() /
            (std::string("linx_viz_run_") + info->name() + "_" + std::to_string(::getpid()));
    fs::remove_all(root_);
    fs::create_directories(root_);
  }
  void TearDown() override { fs::remove_all(root_); }

  fs::path root_;
};

// A pendulum bob on a hinge (with a name that needs CSV quoting), a cube given as a hull of its
// corners and inner points falling onto a ground plane, and a ball joint between two boxes.
constexpr const char* kScene = R"({
  "timestep": 0.002,
  "view": { "eye": [2, -6, 3], "target": [0, 0, 0.5], "fov": 35 },
  "bodies": [
    { "name": "ground", "static": true, "shapes": [{ "type": "plane" }] },
    { "name": "bob, \"the\" weight", "mass": 1, "position": [1, 0, 2],
      "shapes": [{ "type": "sphere", "radius": 0.1 }] },
    { "name": "cube", "mass": 2, "position": [3, 0, 0.8], "orientation": [0.9, 0.1, 0.2, 0.3],
      "shapes": [{ "type": "convex", "points": [[-0.5,-0.5,-0.5],[0.5,-0.5,-0.5],[0.5,0.5,-0.5],
        [-0.5,0.5,-0.5],[-0.5,-0.5,0.5],[0.5,-0.5,0.5],[0.5,0.5,0.5],[-0.5,0.5,0.5],
        [0.1,0.2,0.3],[0,0,0]] }] },
    { "name": "a", "mass": 1, "position": [-2, 0, 2], "angular_velocity": [0, 0, 3],
      "shapes": [{ "type": "box", "size": [0.2, 0.2, 0.2] }] },
    { "name": "b", "mass": 1, "position": [-2, 0, 1.6],
      "shapes": [{ "type": "box", "size": [0.2, 0.2, 0.2] }] }
  ],
  "joints": [
    { "name": "pivot", "type": "hinge", "body1": "bob, \"the\" weight", "anchor": [0, 0, 2],
      "axis": [0, 1, 0] },
    { "name": "ball", "type": "ball", "body1": "b", "body2": "a", "anchor": [-2, 0, 1.8] },
    { "name": "hold", "type": "fixed", "body1": "a", "anchor": [-2, 0, 2] }
  ]
})";

struct Recorded {
  std::vector<double> times;
  std::vector<std::vector<linx::Pose>> poses;
};

// Runs kScene for `steps` steps, recording every `every`-th, and keeps the world's own poses.
Recorded record(const fs::path& dir, int steps, int every) {
  const linx::Scene scene = linx::parseScene(kScene, "scene.json");
  linx::World world = linx::buildWorld(scene);
  linx::Recorder recorder(dir, linx::RecorderOptions{.contacts = true});
  recorder.writeFile("scene.json", linx::runSceneJson(scene, world, every));
  Recorded truth;
  const auto keep = [&] {
    recorder.record(world);
    truth.times.push_back(world.time());
    std::vector<linx::Pose> poses;
    for (int i = 0; i < world.bodyCount(); ++i) poses.push_back(world.body(linx::BodyId{i}).pose());
    truth.poses.push_back(poses);
  };
  keep();
  for (int s = 1; s <= steps; ++s) {
    world.step();
    if (s % every == 0) keep();
  }
  recorder.finish();
  return truth;
}

TEST_F(VizRun, ReadsBackEveryRecordedPoseAndTheSceneGeometry) {
  const Recorded truth = record(root_, 300, 10);
  const linx::viz::Run run = linx::viz::readRun(root_);

  ASSERT_EQ(run.frames.size(), truth.times.size());
  ASSERT_EQ(run.bodies.size(), 5u);
  EXPECT_EQ(run.bodies[1].name, "bob, \"the\" weight");
  EXPECT_TRUE(run.bodies[0].is_static);
  EXPECT_EQ(run.every, 10);
  EXPECT_TRUE(run.has_contacts);
  for (std::size_t f = 0; f < run.frames.size(); ++f) {
    EXPECT_EQ(run.frames[f].time, truth.times[f]);
    for (std::size_t b = 0; b < run.bodies.size(); ++b) {
      // Written at full precision: read back to the bit (the orientation up to normalization).
      EXPECT_EQ(run.frames[f].poses[b].position, truth.poses[f][b].position);
      EXPECT_NEAR(run.frames[f].poses[b].orientation.angularDistance(truth.poses[f][b].orientation),
                  0.0, 1e-15);
    }
  }

  // The cube landed on the plane: the last frames have ground-cube contacts.
  bool cube_contact = false;
  for (const linx::viz::RunContact& c : run.frames.back().contacts)
    cube_contact |= (c.body1 == 2 && c.body2 == 0) || (c.body1 == 0 && c.body2 == 2);
  EXPECT_TRUE(cube_contact);

  // The hull: the 8 corners, and outward triangles enclosing the unit cube's volume (divergence
  // theorem: V = 1/6 sum a . (b x c)).
  const linx::ShapeDef& hull = run.bodies[2].shapes.at(0);
  ASSERT_EQ(hull.type, linx::ShapeType::Convex);
  EXPECT_EQ(hull.points.size(), 8u);
  double volume = 0;
  for (const auto& t : hull.triangles)
    volume += hull.points[t[0]].dot(hull.points[t[1]].cross(hull.points[t[2]])) / 6;
  EXPECT_NEAR(volume, 1.0, 1e-12);
  // The hull is in the body frame: centred on the centre of mass, the cube's centre.
  Vec3 centroid = Vec3::Zero();
  for (const Vec3& p : hull.points) centroid += p / 8;
  EXPECT_LT((centroid + hull.position).norm(), 1e-12);

  // Joint anchors given in each body's frame meet at every frame, to the joint's drift.
  ASSERT_EQ(run.joints.size(), 3u);
  EXPECT_EQ(run.joints[0].body2, -1);
  ASSERT_TRUE(run.joints[0].axis1.has_value());
  EXPECT_FALSE(run.joints[1].axis1.has_value());
  for (const linx::viz::Frame& frame : run.frames) {
    for (std::size_t j = 0; j < run.joints.size(); ++j) {
      const linx::viz::RunJoint& joint = run.joints[j];
      const Vec3 p1 = linx::viz::worldPoint(frame, joint.body1, joint.anchor1);
      const Vec3 p2 = linx::viz::worldPoint(frame, joint.body2, joint.anchor2);
      EXPECT_LT((p1 - p2).norm(), 1e-3) << joint.name << " at t = " << frame.time;
    }
    // The pendulum's anchor is the pivot, 1 m from the bob's centre.
    EXPECT_NEAR((frame.poses[1].position - Vec3(0, 0, 2)).norm(), 1.0, 1e-3);
  }

  // The view as the scene gave it, with up filled in against gravity.
  ASSERT_TRUE(run.view.has_value());
  EXPECT_EQ(*run.view->eye, Vec3(2, -6, 3));
  EXPECT_EQ(*run.view->up, Vec3(0, 0, 1));
  EXPECT_EQ(run.view->fov, 35);
}

TEST_F(VizRun, BadFoldersAreNamedWithTheFileAndTheProblem) {
  const auto message = [&](const fs::path& dir) -> std::string {
    try {
      linx::viz::readRun(dir);
    } catch (const linx::viz::RunError& e) {
      return e.what();
    }
    return "no error";
  };
  EXPECT_NE(message(root_ / "missing").find("not a directory"), std::string::npos);
  record(root_ / "run", 20, 10);

  fs::copy(root_ / "run", root_ / "no_scene");
  fs::remove(root_ / "no_scene" / "scene.json");
  const std::string no_scene = message(root_ / "no_scene");
  EXPECT_NE(no_scene.find("scene.json: file: cannot be read"), std::string::npos) << no_scene;
  EXPECT_NE(no_scene.find("rerun"), std::string::npos) << no_scene;

  // A run killed part-way through a frame: the whole frames are read, the rest left out.
  fs::copy(root_ / "run", root_ / "short");
  const auto cutTo = [&](const char* file, int lines, const char* tail) {
    std::ifstream in(root_ / "run" / file);
    std::ofstream out(root_ / "short" / file, std::ios::trunc);
    std::string line;
    for (int i = 0; i < lines && std::getline(in, line); ++i) out << line << '\n';
    out << tail;
  };
  cutTo("bodies.csv", 1 + 5 * 2 + 3, "0.2,bo");  // 2 frames, 3 rows and half a row of the third
  const linx::viz::Run short_run = linx::viz::readRun(root_ / "short");
  EXPECT_EQ(short_run.frames.size(), 2u);
  EXPECT_TRUE(short_run.truncated);
  EXPECT_FALSE(linx::viz::readRun(root_ / "run").truncated);
  // Files further apart than a kill can leave them are damaged: an error.
  cutTo("bodies.csv", 1 + 5 * 1, "");
  const std::string damaged = message(root_ / "short");
  EXPECT_NE(damaged.find("joints.csv: rows: "), std::string::npos) << damaged;

  // A number that is not one, or not finite, reported with its line and field.
  for (const std::string bad : {"x", "inf", "nan"}) {
    const fs::path dir = root_ / ("bad_" + bad);
    fs::copy(root_ / "run", dir);
    std::ifstream in(root_ / "run" / "world.csv");
    std::ofstream out(dir / "world.csv", std::ios::trunc);
    std::string line;
    for (int i = 1; std::getline(in, line); ++i) {
      if (i == 3)
        line = line.substr(0, line.find(',')) + "," + bad +
               line.substr(line.find(',', line.find(',') + 1));
      out << line << '\n';
    }
    out.close();
    EXPECT_NE(message(dir).find("world.csv: line 3: field 2: '" + bad + "' is not a finite number"),
              std::string::npos)
        << message(dir);
  }

  // Values of the wrong type or out of range in scene.json: an error naming the file, never a
  // crash or a foreign exception.
  const std::string good = [&] {
    std::ifstream in(root_ / "run" / "scene.json");
    return std::string(std::istreambuf_iterator<char>(in), {});
  }();
  const auto withScene = [&](const std::string& from, const std::string& to) {
    const fs::path dir = root_ / "edited";
    fs::remove_all(dir);
    fs::copy(root_ / "run", dir);
    std::string text = good;
    const std::size_t at = text.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    if (at != std::string::npos) text.replace(at, from.size(), to);
    std::ofstream(dir / "scene.json", std::ios::trunc) << text;
    return message(dir);
  };
  EXPECT_NE(withScene("\"version\": 1", "\"version\": \"1\"").find("scene.json: version: "),
            std::string::npos);
  EXPECT_NE(withScene("\"every\": 10", "\"every\": 3000000000").find("scene.json: every: "),
            std::string::npos);
  EXPECT_NE(withScene("\"fov\": 35.0", "\"fov\": 0").find("scene.json: view.fov: must be in"),
            std::string::npos);
  EXPECT_NE(withScene("\"radius\": 0.1", "\"radius\": -0.1")
                .find("scene.json: bodies[1].shapes[0].radius: must be > 0"),
            std::string::npos);
  EXPECT_NE(withScene("\"name\": \"cube\"", "\"name\": [1]")
                .find("scene.json: bodies[2].name: expected a string"),
            std::string::npos);

  fs::copy(root_ / "run", root_ / "json");
  std::ofstream(root_ / "json" / "scene.json", std::ios::trunc) << "{\"format\": \"other\"}";
  EXPECT_NE(message(root_ / "json").find("scene.json: format: not a linx run"), std::string::npos);
}

TEST(SceneView, IsValidatedWithTheFieldPath) {
  const auto error = [](const std::string& view) -> std::string {
    try {
      linx::parseScene(
          R"({"bodies": [{"name": "b", "mass": 1, "inertia": [1, 1, 1]}], "view": )" + view + "}",
          "s.json");
    } catch (const linx::SceneError& e) {
      return e.what();
    }
    return "no error";
  };
  EXPECT_EQ(error(R"({"fov": 200})"),
            "s.json: view.fov: must be strictly between 0 and 180, got 200");
  EXPECT_EQ(error(R"({"eye": [1, 2, 3], "target": [1, 2, 3]})"),
            "s.json: view.target: must differ from eye");
  EXPECT_EQ(error(R"({"eye": [0, 0, 5], "target": [0, 0, 0], "up": [0, 0, 2]})"),
            "s.json: view.up: must not be parallel to target - eye");
  EXPECT_EQ(error(R"({"up": [0, 0, 0]})"), "s.json: view.up: must not be zero");
  EXPECT_EQ(error(R"({"look": [0, 0, 0]})").substr(0, 32), "s.json: view.look: unknown field");
  EXPECT_EQ(error(R"({"fov": 60, "eye": [1, 0, 0]})"), "no error");
}

// A camera looking down -y from (0, -10, 0) with a 90 degree field of view maps a point at
// depth d and height h to the row H/2 - (H/2) h / d.
TEST(Camera, ProjectsLikeAPinhole) {
  linx::viz::Camera cam;
  cam.eye = Vec3(0, -10, 0);
  cam.target = Vec3(0, 0, 0);
  cam.up = Vec3::UnitZ();
  cam.fov = 90;
  const auto p = linx::viz::project(cam, Vec3(0, 0, 0), 200, 100);
  ASSERT_TRUE(p.has_value());
  EXPECT_NEAR((*p - Eigen::Vector2d(100, 50)).norm(), 0, 1e-12);
  const auto q = linx::viz::project(cam, Vec3(5, 0, 5), 200, 100);  // right and up
  ASSERT_TRUE(q.has_value());
  EXPECT_NEAR(q->x(), 100 + 50 * 5.0 / 10, 1e-9);
  EXPECT_NEAR(q->y(), 50 - 50 * 5.0 / 10, 1e-9);
  EXPECT_FALSE(linx::viz::project(cam, Vec3(0, -20, 0), 200, 100).has_value());  // behind
}

// The automatic camera keeps every corner of the run's bounds inside the picture.
TEST_F(VizRun, AutomaticCameraFramesTheWholeRun) {
  record(root_, 300, 10);
  linx::viz::Run run = linx::viz::readRun(root_);
  run.view.reset();
  const linx::viz::Bounds bounds = linx::viz::runBounds(run);
  // The bounds hold the pendulum's whole swing and the falling cube.
  EXPECT_LE(bounds.min.x(), -2.1);
  EXPECT_GE(bounds.max.x(), 3.5);
  for (const double aspect : {4.0 / 3.0, 0.5}) {
    const int w = static_cast<int>(600 * aspect), h = 600;
    const linx::viz::Camera cam = linx::viz::chooseCamera(run, aspect);
    EXPECT_NEAR(cam.up.dot(cam.target - cam.eye), 0, 1e-9);
    EXPECT_GT((cam.eye - cam.target).dot(Vec3::UnitZ()), 0) << "the camera looks from above";
    for (int corner = 0; corner < 8; ++corner) {
      const Vec3 c((corner & 1) ? bounds.max.x() : bounds.min.x(),
                   (corner & 2) ? bounds.max.y() : bounds.min.y(),
                   (corner & 4) ? bounds.max.z() : bounds.min.z());
      const auto p = linx::viz::project(cam, c, w, h);
      ASSERT_TRUE(p.has_value());
      EXPECT_GE(p->x(), 0);
      EXPECT_LE(p->x(), w);
      EXPECT_GE(p->y(), 0);
      EXPECT_LE(p->y(), h);
    }
  }
}

}  // namespace

namespace {

// Starts `linx run SCENE --out DIR ARGS...` and returns its process id.
pid_t startRun(const std::string& scene, const fs::path& dir, std::vector<std::string> args) {
  std::vector<std::string> argv{LINX_CLI, "run", scene, "--out", dir.string()};
  argv.insert(argv.end(), args.begin(), args.end());
  const pid_t pid = fork();
  if (pid == 0) {
    std::vector<char*> c_argv;
    for (std::string& a : argv) c_argv.push_back(a.data());
    c_argv.push_back(nullptr);
    freopen("/dev/null", "w", stdout);
    freopen("/dev/null", "w", stderr);
    execv(LINX_CLI, c_argv.data());
    _exit(127);
  }
  return pid;
}

}  // namespace

// SIGKILL at any moment leaves a folder that reads back, and what it reads is exactly the start
// of the uninterrupted run, frame for frame and bit for bit: never another run's files, never a
// damaged frame. The moments are spread over the run, some inside the writing of a frame.
TEST_F(VizRun, AKilledRunKeepsExactlyTheFramesItWrote) {
  const std::string scene = std::string(LINX_EXAMPLES_DIR) + "/hinge_chain.json";
  const fs::path full_dir = root_ / "full";
  int status = 0;
  waitpid(startRun(scene, full_dir, {"--duration", "10"}), &status, 0);
  ASSERT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0);
  const linx::viz::Run full = linx::viz::readRun(full_dir);
  ASSERT_EQ(full.frames.size(), 10001u);

  const fs::path dir = root_ / "killed";
  int read_back = 0, truncated = 0;
  std::size_t longest = 0;
  for (int k = 0; k < 12; ++k) {
    // An earlier run in the folder, which the killed one replaces.
    const std::string earlier = std::string(LINX_EXAMPLES_DIR) + "/pendulum.json";
    waitpid(startRun(earlier, dir, {"--duration", "0.1"}), &status, 0);
    const pid_t pid = startRun(scene, dir, {"--duration", "10"});
    usleep(static_cast<useconds_t>(20'000 + 90'000 * k));
    kill(pid, SIGKILL);
    waitpid(pid, &status, 0);
    if (!fs::exists(dir / "scene.json")) continue;  // killed before it wrote its first frame
    const linx::viz::Run run = linx::viz::readRun(dir);
    if (run.source == earlier) {  // killed before it started: the earlier run, whole
      EXPECT_EQ(run.frames.size(), 101u);
      EXPECT_FALSE(run.truncated);
      continue;
    }
    ++read_back;
    truncated += run.truncated;
    longest = std::max(longest, run.frames.size());
    ASSERT_EQ(run.source, scene);
    ASSERT_EQ(run.bodies.size(), full.bodies.size());
    ASSERT_LE(run.frames.size(), full.frames.size());
    for (std::size_t f = 0; f < run.frames.size(); ++f) {
      ASSERT_EQ(run.frames[f].time, full.frames[f].time) << "kill " << k << ", frame " << f;
      for (std::size_t b = 0; b < run.bodies.size(); ++b) {
        ASSERT_EQ(run.frames[f].poses[b].position, full.frames[f].poses[b].position);
        ASSERT_EQ(run.frames[f].poses[b].orientation.coeffs(),
                  full.frames[f].poses[b].orientation.coeffs());
      }
      ASSERT_EQ(run.frames[f].joint_error, full.frames[f].joint_error);
      ASSERT_EQ(run.frames[f].kinetic_energy, full.frames[f].kinetic_energy);
    }
  }
  EXPECT_GE(read_back, 6);
  EXPECT_GT(longest, 1u);
  std::printf(
      "killed runs read back: %d of 12 (%d ended part-way through a frame), up to %zu of "
      "%zu frames\n",
      read_back, truncated, longest, full.frames.size());
}
