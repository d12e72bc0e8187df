// The CSV recorder: exact headers, one row per body / joint / frame, numbers that read back to
// the same doubles; every frame on disk when record() returns; an earlier run's files replaced and
// nothing else touched, even when the folder is swapped for another during the run.
#include <linx/recorder.hpp>
#include <linx/world.hpp>

#include <gtest/gtest.h>
#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <csignal>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace fs = std::filesystem;

namespace {

// A fresh empty directory for one test, removed afterwards.
class RecorderTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    root_ = fs::temp_directory_path() /
            (std::string("linx_recorder_") + info->name() + "_" + std::to_string(::getpid()));
    fs::remove_all(root_);
    fs::create_directories(root_);
  }
  void TearDown() override { fs::remove_all(root_); }

  fs::path root_;
};

std::vector<std::string> lines(const fs::path& file) {
  std::ifstream in(file);
  std::vector<std::string> out;
  for (std::string line; std::getline(in, line);) out.push_back(line);
  return out;
}

std::vector<std::string> split(const std::string& line) {
  std::vector<std::string> fields;
  std::stringstream in(line);
  for (std::string field; std::getline(in, field, ',');) fields.push_back(field);
  if (!line.empty() && line.back() == ',') fields.emplace_back();
  return fields;
}

std::vector<std::string> listing(const fs::path& dir) {
  std::vector<std::string> names;
  for (const auto& entry : fs::directory_iterator(dir)) names.push_back(entry.path().filename());
  std::sort(names.begin(), names.end());
  return names;
}

// A pendulum bob on a hinge, and a body with an awkward name fixed to the world.
linx::World makeWorld() {
  linx::World world;
  linx::BodyDef bob;
  bob.name = "bob";
  bob.position = linx::Vec3(1.0 / 3.0, 0, 0);
  bob.mass = 1.0;
  bob.inertia = linx::Mat3::Identity() * 0.01;
  const linx::BodyId b = world.createBody(bob);
  linx::BodyDef other = bob;
  other.name = "a \"quoted\", name";
  other.position = linx::Vec3(0, 0, -1);
  const linx::BodyId o = world.createBody(other);

  linx::JointDef hinge;
  hinge.name = "pivot";
  hinge.body1 = b;
  hinge.anchor = linx::Vec3::Zero();
  hinge.axis = linx::Vec3::UnitY();
  world.createJoint("hinge", hinge);
  linx::JointDef fixed;
  fixed.name = "weld";
  fixed.body1 = o;
  world.createJoint("fixed", fixed);
  return world;
}

TEST_F(RecorderTest, WritesHeadersRowsAndFullPrecision) {
  linx::World world = makeWorld();
  const fs::path dir = root_ / "out";
  {
    linx::Recorder recorder(dir);
    recorder.record(world);
    world.step();
    recorder.record(world);
    // Both frames are in the files before finish(): a kill now would keep them.
    EXPECT_EQ(lines(dir / "bodies.csv").size(), 5u);
    EXPECT_EQ(lines(dir / "world.csv").size(), 3u);
    recorder.finish();
  }
  EXPECT_EQ(listing(dir), (std::vector<std::string>{"bodies.csv", "joints.csv", "world.csv"}));

  const auto bodies = lines(dir / "bodies.csv");
  ASSERT_EQ(bodies.size(), 1u + 2 * 2);
  EXPECT_EQ(bodies[0], "time,body,x,y,z,qw,qx,qy,qz,vx,vy,vz,wx,wy,wz");
  EXPECT_EQ(bodies[1], "0,bob,0.3333333333333333,0,0,1,0,0,0,0,0,0,0,0,0");
  EXPECT_EQ(bodies[2].substr(0, 26), "0,\"a \"\"quoted\"\", name\",0,0");  // RFC 4180 quoting

  // The last frame reads back to the world's state exactly.
  const auto last = split(bodies[3]);
  ASSERT_EQ(last.size(), 15u);
  const linx::Body& bob = world.body(linx::BodyId{0});
  EXPECT_EQ(std::strtod(last[0].c_str(), nullptr), world.time());
  EXPECT_EQ(last[1], "bob");
  for (int i = 0; i < 3; ++i) {
    EXPECT_EQ(std::strtod(last[2 + i].c_str(), nullptr), bob.position()[i]);
    EXPECT_EQ(std::strtod(last[9 + i].c_str(), nullptr), bob.linearVelocity()[i]);
    EXPECT_EQ(std::strtod(last[12 + i].c_str(), nullptr), bob.angularVelocity()[i]);
  }
  EXPECT_EQ(std::strtod(last[5].c_str(), nullptr), bob.orientation().w());
  EXPECT_EQ(std::strtod(last[7].c_str(), nullptr), bob.orientation().y());

  const auto joints = lines(dir / "joints.csv");
  ASSERT_EQ(joints.size(), 1u + 2 * 2);
  EXPECT_EQ(joints[0],
            "time,joint,coordinate,error,fx,fy,fz,tx,ty,tz,coordinate2,coordinate3,coordinate4,"
            "coordinate5,coordinate6");
  EXPECT_EQ(joints[1], "0,pivot,0,0,0,0,0,0,0,0,,,,,");  // a hinge has one coordinate
  const auto hinge = split(joints[3]);
  ASSERT_EQ(hinge.size(), 15u);
  EXPECT_EQ(std::strtod(hinge[2].c_str(), nullptr), world.jointCoordinates(linx::JointId{0})[0]);
  EXPECT_EQ(std::strtod(hinge[3].c_str(), nullptr), world.jointError(linx::JointId{0}));
  const linx::JointReaction reaction = world.jointReaction(linx::JointId{0});
  for (int i = 0; i < 3; ++i) {
    EXPECT_EQ(std::strtod(hinge[4 + i].c_str(), nullptr), reaction.force[i]);
    EXPECT_EQ(std::strtod(hinge[7 + i].c_str(), nullptr), reaction.torque[i]);
  }
  EXPECT_GT(reaction.force.z(), 0.0);  // the pivot holds the bob up
  const auto weld = split(joints[4]);
  ASSERT_EQ(weld.size(), 15u);
  EXPECT_EQ(weld[1], "weld");
  EXPECT_EQ(weld[2], "");  // a fixed joint has no coordinate

  const auto frames = lines(dir / "world.csv");
  ASSERT_EQ(frames.size(), 1u + 2);
  EXPECT_EQ(frames[0],
            "time,kinetic_energy,potential_energy,total_energy,max_joint_error,solver_iterations,"
            "residual");
  const auto row = split(frames[2]);
  ASSERT_EQ(row.size(), 7u);
  const linx::Energy energy = world.energy();
  EXPECT_EQ(std::strtod(row[1].c_str(), nullptr), energy.kinetic);
  EXPECT_EQ(std::strtod(row[2].c_str(), nullptr), energy.potential);
  EXPECT_EQ(std::strtod(row[3].c_str(), nullptr), energy.total());
  EXPECT_EQ(std::strtod(row[4].c_str(), nullptr), world.maxJointError());
  EXPECT_EQ(std::stoi(row[5]), world.lastReport().iterations);
  EXPECT_EQ(std::strtod(row[6].c_str(), nullptr), world.lastReport().residual);
}

TEST_F(RecorderTest, ReplacesAnEarlierRunAndNothingElse) {
  const linx::World world = makeWorld();
  const fs::path dir = root_ / "out", outside = root_ / "outside";
  fs::create_directories(dir / "vtk");
  fs::create_directories(dir / "render");
  fs::create_directories(outside);
  for (const char* name : {"scene.json", "bodies.csv", "contacts.csv", "breaks.csv", "run.pvd",
                           "vtk/bodies_000000.vtp", "render/frame_000000.png", "notes.txt"})
    std::ofstream(dir / name) << "earlier run\n";
  std::ofstream(outside / "keep.txt") << "not the run's\n";
  fs::create_directory_symlink(outside, dir / "plots");  // a run file's name, but a link
  {
    linx::Recorder recorder(dir);
    recorder.record(world);
  }
  // The earlier run's files are gone, the links among them removed without following them, and a
  // file that is not a run's is kept.
  EXPECT_EQ(listing(dir),
            (std::vector<std::string>{"bodies.csv", "joints.csv", "notes.txt", "world.csv"}));
  EXPECT_EQ(lines(dir / "notes.txt"), std::vector<std::string>{"earlier run"});
  EXPECT_EQ(lines(outside / "keep.txt"), std::vector<std::string>{"not the run's"});
  EXPECT_EQ(lines(dir / "bodies.csv").size(), 3u);
}

TEST_F(RecorderTest, AFolderSwappedDuringTheRunIsNeverTouched) {
  linx::World world = makeWorld();
  const fs::path dir = root_ / "out", moved = root_ / "moved";
  linx::Recorder recorder(dir);
  recorder.record(world);
  // The folder is renamed and a file put in its place while the run goes on.
  fs::rename(dir, moved);
  std::ofstream(dir) << "someone else's file\n";
  world.step();
  recorder.record(world);
  recorder.writeFile("scene.json", "{}\n");
  recorder.finish();
  EXPECT_EQ(lines(dir), std::vector<std::string>{"someone else's file"});
  EXPECT_EQ(lines(moved / "bodies.csv").size(), 5u);
  EXPECT_EQ(lines(moved / "scene.json"), std::vector<std::string>{"{}"});
  EXPECT_THROW(recorder.record(world), std::logic_error);
}

// Past the file size limit (ulimit -f) with SIGXFSZ ignored, as `linx run` does: a write error
// that names the file, not a silent death.
TEST_F(RecorderTest, AWriteErrorNamesTheFile) {
  linx::World world = makeWorld();
  const auto old_handler = std::signal(SIGXFSZ, SIG_IGN);
  rlimit old_limit{};
  ASSERT_EQ(getrlimit(RLIMIT_FSIZE, &old_limit), 0);
  rlimit limit = old_limit;
  limit.rlim_cur = 4096;
  ASSERT_EQ(setrlimit(RLIMIT_FSIZE, &limit), 0);
  std::string message;
  try {
    linx::Recorder recorder(root_);
    for (int i = 0; i < 100; ++i) recorder.record(world);
  } catch (const std::runtime_error& e) {
    message = e.what();
  }
  setrlimit(RLIMIT_FSIZE, &old_limit);
  std::signal(SIGXFSZ, old_handler);
  EXPECT_NE(message.find("cannot write " + (root_ / "bodies.csv").string() + ": File too large"),
            std::string::npos)
      << message;
}

TEST_F(RecorderTest, UnusableDirectoryThrows) {
  std::ofstream(root_ / "file") << "x";
  EXPECT_THROW(linx::Recorder(root_ / "file"), std::runtime_error);
  EXPECT_THROW(linx::Recorder(root_ / "file" / "sub"), std::runtime_error);
}

}  // namespace
