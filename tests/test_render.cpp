// `linx render`: POV-Ray frames of a run. A sphere falling freely from a known height is rendered
// with povray, and its pixels must be where a pinhole camera computed here by hand (and
// viz::project) puts the closed-form trajectory z = z0 - g t^2 / 2; flags are validated; frames
// are picked at the requested rate.
#include "viz/camera.hpp"
#include "viz/povray.hpp"
#include "viz/run.hpp"

#include <fcntl.h>
#include <gtest/gtest.h>
#include <png.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <set>
#include <sstream>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;

bool onPath(const std::string& program) {
  const char* path = std::getenv("PATH");
  std::stringstream dirs(path ? path : "");
  for (std::string dir; std::getline(dirs, dir, ':');)
    if (!dir.empty() && ::access((dir + "/" + program).c_str(), X_OK) == 0) return true;
  return false;
}

struct Result {
  int status = -1;
  std::string out, err;
};

std::string slurp(const fs::path& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// Runs the linx program with `args` (already quoted), capturing stdout and stderr.
Result linx(const fs::path& tmp, const std::string& args) {
  const fs::path out = tmp / "stdout.txt", err = tmp / "stderr.txt";
  const std::string command = std::string("'") + LINX_CLI + "' " + args + " >'" + out.string() +
                              "' 2>'" + err.string() + "'";
  const int raw = std::system(command.c_str());
  Result r;
  r.status = WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
  r.out = slurp(out);
  r.err = slurp(err);
  return r;
}

struct Image {
  int width = 0, height = 0;
  std::vector<unsigned char> rgb;  // row by row, top first
  const unsigned char* at(int x, int y) const {
    return &rgb[3 * (static_cast<std::size_t>(y) * width + x)];
  }
};

Image readPng(const fs::path& path) {
  png_image image{};
  image.version = PNG_IMAGE_VERSION;
  Image result;
  if (!png_image_begin_read_from_file(&image, path.c_str())) return result;
  image.format = PNG_FORMAT_RGB;
  result.rgb.resize(PNG_IMAGE_SIZE(image));
  if (!png_image_finish_read(&image, nullptr, result.rgb.data(), 0, nullptr)) {
    png_image_free(&image);
    return {};
  }
  result.width = static_cast<int>(image.width);
  result.height = static_cast<int>(image.height);
  return result;
}

// Centroid (pixel centres at +0.5) of the distinctly red pixels: the first dynamic body's colour,
// lit or in its own shade; the sky, the grey ground and shadows are not red.
struct Blob {
  double x = 0, y = 0;
  int count = 0;
};
Blob redBlob(const Image& image) {
  Blob b;
  for (int y = 0; y < image.height; ++y) {
    for (int x = 0; x < image.width; ++x) {
      const unsigned char* p = image.at(x, y);
      if (p[0] > 40 && p[0] > 1.6 * p[1] && p[0] > 1.6 * p[2]) {
        b.x += x + 0.5;
        b.y += y + 0.5;
        ++b.count;
      }
    }
  }
  if (b.count > 0) {
    b.x /= b.count;
    b.y /= b.count;
  }
  return b;
}

class RenderTest : public ::testing::Test {
 protected:
  void SetUp() override {
    tmp_ = fs::temp_directory_path() /
           ("linx_test_render_" + std::to_string(::getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(tmp_);
    fs::create_directories(tmp_);
  }
  void TearDown() override {
    if (!HasFailure()) fs::remove_all(tmp_);
  }
  // A run of one sphere (radius 0.2 m) falling from z0 = 1 m for 0.3 s, recorded every 10 steps,
  // seen from a known camera: eye (0, -4, 0.7) looking along +y, up +z, 40 degrees.
  fs::path fallingSphere() {
    const fs::path scene = tmp_ / "fall.json";
    std::ofstream(scene) << R"({
      "gravity": [0, 0, -9.81], "timestep": 0.001, "duration": 0.3,
      "view": { "eye": [0, -4, 0.7], "target": [0, 0, 0.7], "up": [0, 0, 1], "fov": 40 },
      "bodies": [ { "name": "ball", "position": [0.1, 0, 1],
                    "shapes": [ { "type": "sphere", "radius": 0.2, "density": 1000 } ] } ]
    })";
    const fs::path dir = tmp_ / "fall";
    const Result r =
        linx(tmp_, "run '" + scene.string() + "' --out '" + dir.string() + "' --every 10");
    EXPECT_EQ(r.status, 0) << r.err;
    return dir;
  }
  fs::path tmp_;
};

TEST_F(RenderTest, FallingSphereIsWhereTheTrajectoryAndCameraPutIt) {
  if (!onPath("povray")) GTEST_SKIP() << "povray is not installed (scripts/install-deps.sh)";
  const fs::path dir = fallingSphere();
  const linx::viz::Run run = linx::viz::readRun(dir);
  ASSERT_EQ(run.frames.size(), 31u);
  const int w = 160, h = 120;
  const linx::viz::Camera camera = linx::viz::chooseCamera(run, double(w) / h);

  // Hand-made pinhole of the scene's view: depth along +y from y = -4, focal length in pixels.
  const double f = (h / 2.0) / std::tan(20 * std::numbers::pi / 180);
  const auto pixel = [&](double x, double z) {
    return Eigen::Vector2d(w / 2.0 + f * x / 4.0, h / 2.0 - f * (z - 0.7) / 4.0);
  };

  std::vector<Eigen::Vector2d> seen, expected;
  for (const char* which : {"0", "last"}) {
    const Result r =
        linx(tmp_, "render '" + dir.string() + "' --frame " + which + " --width 160 --height 120");
    ASSERT_EQ(r.status, 0) << r.err;
    std::string png = r.out;
    while (!png.empty() && png.back() == '\n') png.pop_back();
    ASSERT_TRUE(fs::exists(png)) << png;
    EXPECT_EQ(fs::path(png).parent_path(), dir / "render");

    const Image image = readPng(png);
    ASSERT_EQ(image.width, w);
    ASSERT_EQ(image.height, h);
    std::set<int> colours;  // not an empty picture
    for (std::size_t i = 0; i + 2 < image.rgb.size(); i += 3)
      colours.insert(image.rgb[i] << 16 | image.rgb[i + 1] << 8 | image.rgb[i + 2]);
    EXPECT_GT(colours.size(), 50u);

    const linx::viz::Frame& frame =
        std::string(which) == "0" ? run.frames.front() : run.frames.back();
    const double t = frame.time;
    const linx::Vec3 p = frame.poses[0].position;
    // The recorded trajectory is free fall (symplectic Euler: within g h t / 2 + round-off).
    EXPECT_NEAR(p.z(), 1.0 - 9.81 * t * t / 2, 0.003) << "t = " << t;
    EXPECT_NEAR(p.x(), 0.1, 1e-12);
    // viz::project agrees with the hand-made camera.
    const auto projected = linx::viz::project(camera, p, w, h);
    ASSERT_TRUE(projected);
    EXPECT_NEAR((*projected - pixel(p.x(), p.z())).norm(), 0.0, 1e-9);

    const Blob blob = redBlob(image);
    // A disc of radius f * 0.2 / 4 = 8.2 pixels: about 212 pixels.
    EXPECT_GT(blob.count, 150) << png;
    EXPECT_LT(blob.count, 260) << png;
    const Eigen::Vector2d centre(blob.x, blob.y);
    EXPECT_LT((centre - *projected).norm(), 0.75)
        << png << ": sphere seen at " << centre.transpose() << ", projected at "
        << projected->transpose();
    seen.push_back(centre);
    expected.push_back(pixel(0.1, 1.0 - 9.81 * t * t / 2));
  }
  // Between the two frames it falls 0.44 m: about 18 pixels down, as projected.
  const Eigen::Vector2d moved = seen[1] - seen[0], should = expected[1] - expected[0];
  EXPECT_GT(should.y(), 17.0);
  EXPECT_NEAR(moved.x(), should.x(), 0.5);
  EXPECT_NEAR(moved.y(), should.y(), 0.75);
}

TEST_F(RenderTest, RendersPickedFramesAndAVideo) {
  if (!onPath("povray")) GTEST_SKIP() << "povray is not installed (scripts/install-deps.sh)";
  const fs::path dir = fallingSphere();
  const bool ffmpeg = onPath("ffmpeg");
  const Result r = linx(tmp_, "render '" + dir.string() + "' --fps 10 --width 48 --height 32 " +
                                  (ffmpeg ? "--video mp4" : "--video none") + " --jobs 2");
  ASSERT_EQ(r.status, 0) << r.err;
  // t = 0, 0.1, 0.2, 0.3 s.
  for (int k = 0; k < 4; ++k) {
    char name[32];
    std::snprintf(name, sizeof name, "frame_%06d.png", k);
    const Image image = readPng(dir / "render" / name);
    EXPECT_EQ(image.width, 48) << name;
    EXPECT_EQ(image.height, 32) << name;
  }
  EXPECT_FALSE(fs::exists(dir / "render" / "frame_000004.png"));
  EXPECT_TRUE(fs::exists(dir / "render" / "scene.inc"));
  EXPECT_NE(r.out.find("rendered 4 frames to " + (dir / "render").string() + " (48x32)"),
            std::string::npos)
      << r.out;
  if (ffmpeg) {
    EXPECT_GT(fs::file_size(dir / "render.mp4"), 0u);
    EXPECT_NE(r.out.find("video " + (dir / "render.mp4").string()), std::string::npos) << r.out;
  }
  for (const auto& entry : fs::directory_iterator(dir / "render"))
    EXPECT_EQ(entry.path().string().find(".part."), std::string::npos) << entry.path();
}

// A SIGTERM sent to linx alone (not to its process group) stops the render at once, and a povray
// that ignores SIGTERM is killed: none outlives linx. The povray here is a script that ignores
// SIGTERM and never ends.
TEST_F(RenderTest, SigtermToLinxAloneStopsEvenAPovrayThatIgnoresIt) {
  const fs::path dir = fallingSphere();
  const fs::path bin = tmp_ / "bin", pids = tmp_ / "povray_pids.txt";
  fs::create_directories(bin);
  std::ofstream(bin / "povray") << "#!/bin/sh\ntrap '' TERM\necho $$ >>'" << pids.string()
                                << "'\nwhile :; do sleep 0.1; done\n";
  fs::permissions(bin / "povray", fs::perms::owner_all);
  const char* path = std::getenv("PATH");
  const std::string env_path = "PATH=" + bin.string() + ":" + (path ? path : "/usr/bin:/bin");
  const std::string dir_arg = dir.string(), log = (tmp_ / "linx.txt").string();
  std::vector<std::string> args{"/usr/bin/env", env_path, LINX_CLI,  "render", dir_arg,
                                "--jobs",       "2",      "--video", "none"};
  std::vector<char*> argv;
  for (std::string& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  const pid_t linx_pid = ::fork();
  ASSERT_GE(linx_pid, 0);
  if (linx_pid == 0) {
    const int fd = ::open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    if (fd >= 0) {
      ::dup2(fd, 1);
      ::dup2(fd, 2);
    }
    ::setpgid(0, 0);  // its own process group, so that only linx gets the signal
    ::execv(argv[0], argv.data());
    ::_exit(127);
  }
  // Both povray processes have started.
  const auto started = [&] {
    std::ifstream in(pids);
    int count = 0;
    for (std::string line; std::getline(in, line);) count += !line.empty();
    return count;
  };
  for (int i = 0; i < 500 && started() < 2; ++i) ::usleep(10000);
  ASSERT_EQ(started(), 2) << slurp(log);

  const auto t0 = std::chrono::steady_clock::now();
  ::kill(linx_pid, SIGTERM);
  int status = 0;
  pid_t got = 0;
  for (int i = 0; i < 1000 && (got = ::waitpid(linx_pid, &status, WNOHANG)) == 0; ++i)
    ::usleep(10000);
  if (got == 0) {  // still running after 10 s: do not leave it behind
    ::kill(linx_pid, SIGKILL);
    ::waitpid(linx_pid, &status, 0);
    FAIL() << "linx did not stop on SIGTERM: " << slurp(log);
  }
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  ASSERT_TRUE(WIFEXITED(status)) << slurp(log);
  EXPECT_EQ(WEXITSTATUS(status), 130) << slurp(log);
  EXPECT_LT(seconds, 5.0);  // 2 s for povray to stop, then SIGKILL
  EXPECT_NE(slurp(log).find("interrupted; stopped povray"), std::string::npos) << slurp(log);
  std::ifstream in(pids);
  for (pid_t pid; in >> pid;) {
    EXPECT_NE(::kill(pid, 0), 0) << "povray " << pid << " outlived linx";
    if (::kill(pid, 0) == 0) ::kill(pid, SIGKILL);
  }
  for (const auto& entry : fs::directory_iterator(dir / "render"))
    EXPECT_EQ(entry.path().filename().string().find(".png"), std::string::npos) << entry.path();
}

TEST_F(RenderTest, RejectsBadFlags) {
  const fs::path dir = fallingSphere();
  const std::string d = "render '" + dir.string() + "' ";
  const struct {
    std::string args, message;
  } cases[] = {
      {"--fps 0", "--fps: must be a number in (0, 1000], got 0"},
      {"--fps nan", "--fps"},
      {"--width 8", "--width: must be an integer in [16, 8192], got 8"},
      {"--height 100000", "--height: must be an integer in [16, 8192], got 100000"},
      {"--jobs -1", "--jobs: must be an integer in [0, 1024]"},
      {"--video avi", "--video: must be mp4, gif or none, got 'avi'"},
      {"--antialias maybe", "--antialias: must be on or off, got 'maybe'"},
      {"--frame soon", "--frame: expected a time (s) or 'last', got 'soon'"},
      {"--frame 5", "--frame: 5 s is outside the run (0 to 0.3 s)"},
      {"--frame last --video mp4", "--video: mp4 needs every frame"},
  };
  for (const auto& c : cases) {
    const Result r = linx(tmp_, d + c.args);
    EXPECT_EQ(r.status, 2) << c.args << ": " << r.err;
    EXPECT_NE(r.err.find(c.message), std::string::npos) << c.args << ": " << r.err;
    EXPECT_EQ(r.err.find('\n'), r.err.size() - 1) << c.args << ": one line: " << r.err;
  }
  const Result missing = linx(tmp_, "render '" + (tmp_ / "nothing").string() + "'");
  EXPECT_EQ(missing.status, 2) << missing.err;
  EXPECT_NE(missing.err.find("nothing"), std::string::npos) << missing.err;
  EXPECT_FALSE(fs::exists(dir / "render" / "frame_000000.png"));
}

TEST(PickFrames, OneFramePerPeriodNeverMoreThanRecorded) {
  linx::viz::Run run;
  for (int i = 0; i <= 200; ++i) {  // 100 frames a second for 2 s
    linx::viz::Frame frame;
    frame.time = i * 0.01;
    run.frames.push_back(frame);
  }
  const std::vector<std::size_t> at30 = linx::viz::pickFrames(run, 30);
  ASSERT_EQ(at30.size(), 61u);
  EXPECT_EQ(at30.front(), 0u);
  EXPECT_EQ(at30.back(), 200u);
  for (std::size_t k = 0; k < at30.size(); ++k)  // nearest to k / 30 s
    EXPECT_LE(std::abs(run.frames[at30[k]].time - k / 30.0), 0.005 + 1e-12) << k;

  const std::vector<std::size_t> all = linx::viz::pickFrames(run, 1000);
  ASSERT_EQ(all.size(), 201u);
  for (std::size_t k = 0; k < all.size(); ++k) EXPECT_EQ(all[k], k);

  const std::vector<std::size_t> slow = linx::viz::pickFrames(run, 0.3);  // 0 s, and the last
  EXPECT_EQ(slow, (std::vector<std::size_t>{0, 200}));

  // The frames of a long run at a high rate are picked without trying each of the 1e9 times.
  linx::viz::Run sparse;
  for (const double t : {0.0, 1.0, 2.5, 1e6}) {
    linx::viz::Frame frame;
    frame.time = t;
    sparse.frames.push_back(frame);
  }
  EXPECT_EQ(linx::viz::pickFrames(sparse, 1000), (std::vector<std::size_t>{0, 1, 2, 3}));

  EXPECT_EQ(linx::viz::nearestFrame(run, -1), 0u);
  EXPECT_EQ(linx::viz::nearestFrame(run, 0.724), 72u);
  EXPECT_EQ(linx::viz::nearestFrame(run, 0.726), 73u);
  EXPECT_EQ(linx::viz::nearestFrame(run, 9), 200u);
}

// Names are written into `//` comments of the scene: a newline in one must not end the comment
// and turn the rest of the name into POV-Ray code.
TEST(RenderScene, ControlCharactersInNamesStayInTheirComment) {
  linx::viz::Run run;
  linx::viz::RunBody body;
  body.name = "ball\nsphere { 0, 100 }\r\x7f";
  body.mass = 1;
  body.shapes.emplace_back();  // a sphere
  run.bodies.push_back(body);
  linx::viz::RunJoint joint;
  joint.name = "pin\n#declare X = 1;";
  joint.type = "ball";
  joint.body1 = 0;
  run.joints.push_back(joint);
  linx::viz::Frame frame;
  frame.poses.resize(1);
  frame.linear_velocity.resize(1, linx::Vec3::Zero());
  frame.angular_velocity.resize(1, linx::Vec3::Zero());
  frame.joint_coordinate.resize(1, NAN);
  frame.joint_error.resize(1, 0.0);
  run.frames.push_back(frame);
  const std::string scene =
      linx::viz::povInclude(run, linx::viz::chooseCamera(run, 4.0 / 3.0), 4.0 / 3.0);
  // Shown as io::visible shows them: the line ends as the characters \n and \r.
  EXPECT_NE(scene.find("// body 0: ball\\nsphere { 0, 100 }\\r\\x7f\n"), std::string::npos)
      << scene;
  EXPECT_NE(scene.find("// joint 0: pin\\n#declare X = 1; (ball)\n"), std::string::npos) << scene;
  EXPECT_EQ(scene.find("\nsphere { 0, 100 }"), std::string::npos) << scene;
  EXPECT_EQ(scene.find("\n#declare X"), std::string::npos) << scene;
  EXPECT_EQ(scene.find('\r'), std::string::npos);
  EXPECT_EQ(scene.find('\x7f'), std::string::npos);
}

// pickFrames skips the times that pick the same frame again: its picks are those of trying
// every time t0 + k / fps, on irregular recordings and rates.
TEST(PickFrames, SameAsTryingEveryTime) {
  const auto everyTime = [](const linx::viz::Run& run, double fps) {
    std::vector<std::size_t> picked;
    const double t0 = run.frames.front().time, t1 = run.frames.back().time;
    const auto n = static_cast<std::size_t>(std::floor((t1 - t0) * fps + 1e-6));
    for (std::size_t k = 0; k <= n; ++k) {
      const std::size_t i = linx::viz::nearestFrame(run, t0 + static_cast<double>(k) / fps);
      if (picked.empty() || i > picked.back()) picked.push_back(i);
    }
    if (picked.back() != run.frames.size() - 1) picked.push_back(run.frames.size() - 1);
    return picked;
  };
  std::uint32_t seed = 12345;
  const auto uniform = [&seed] {  // a small LCG: the same numbers on every platform
    seed = seed * 1664525u + 1013904223u;
    return (seed >> 8) / 16777216.0;
  };
  for (int trial = 0; trial < 200; ++trial) {
    linx::viz::Run run;
    double t = -3 + 6 * uniform();
    const int frames = 1 + static_cast<int>(60 * uniform());
    const bool regular = trial % 3 == 0;
    const double step = 0.001 + 0.1 * uniform();
    for (int i = 0; i < frames; ++i) {
      linx::viz::Frame frame;
      frame.time = t;
      run.frames.push_back(frame);
      t += regular ? step : (uniform() < 0.2 ? 0.0 : 0.3 * uniform());  // ties included
    }
    for (const double fps : {0.5, 7.0, 29.97, 30.0, 100.0, 999.0, 1000.0}) {
      EXPECT_EQ(linx::viz::pickFrames(run, fps), everyTime(run, fps))
          << "trial " << trial << ", fps " << fps;
    }
  }
}

}  // namespace
