// The run folder as linx owns it (docs/reliability.md, "Output that survives a kill"): a recorder
// removes only the entries of run_files.hpp's names and patterns; it holds the folder's lock while
// it writes, so that a second recorder is refused and a repair (viz::openRun) leaves a folder
// being written alone; and openRun cuts the rows a kill left after the last whole frame back to
// exactly the files of the frames it reads.
#include <linx/linx.hpp>
#include <linx/run_files.hpp>

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <sstream>
#include <string>

#include "viz/run.hpp"

namespace fs = std::filesystem;
namespace run_files = linx::run_files;

namespace {

// The patterns: '#' is one or more digits, nothing else.
static_assert(run_files::matchesPattern("step_#.lxc", "step_000000000000042.lxc"));
static_assert(run_files::matchesPattern("step_#.lxc", "step_7.lxc"));
static_assert(!run_files::matchesPattern("step_#.lxc", "step_.lxc"));
static_assert(!run_files::matchesPattern("step_#.lxc", "step_12a.lxc"));
static_assert(!run_files::matchesPattern("step_#.lxc", "step_12.lxc.bak"));
static_assert(!run_files::matchesPattern("frame_#.png", "my_frame_000001.png"));
static_assert(run_files::isFolderEntry(run_files::kPlots, "energy.png"));
static_assert(!run_files::isFolderEntry(run_files::kPlots, "energy.png.bak"));
static_assert(!run_files::isFolderEntry(run_files::kScene, "scene.json"));  // not a folder

class RunFolder : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::temp_directory_path() /
           (std::string("linx_run_folder_") + info->name() + "_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  static std::string read(const fs::path& file) {
    std::ifstream in(file, std::ios::binary);
    std::ostringstream text;
    text << in.rdbuf();
    return text.str();
  }
  static void write(const fs::path& file, const std::string& text,
                    std::ios::openmode mode = std::ios::trunc) {
    fs::create_directories(file.parent_path());
    std::ofstream(file, std::ios::binary | mode) << text;
  }
  // Every file under the folder, with its contents.
  std::map<std::string, std::string> files() const {
    std::map<std::string, std::string> all;
    for (const auto& e : fs::recursive_directory_iterator(dir_))
      if (e.is_regular_file()) all[fs::relative(e.path(), dir_).string()] = read(e.path());
    return all;
  }

  fs::path dir_;
};

constexpr const char* kPendulum = R"({
  "timestep": 0.01,
  "bodies": [{ "name": "bob", "mass": 1, "position": [1, 0, 0],
               "shapes": [{ "type": "sphere", "radius": 0.1 }] }],
  "joints": [{ "name": "pivot", "type": "hinge", "body1": "bob", "anchor": [0, 0, 0],
               "axis": [0, 1, 0] }]
})";

TEST_F(RunFolder, ARecorderRemovesOnlyTheRunsOwnNames) {
  // An earlier run's files and the tools' ...
  const std::vector<std::string> own = {"scene.json",
                                        "bodies.csv",
                                        "world.csv",
                                        "run.pvd",
                                        "render.mp4",
                                        ".scene.json.tmp",
                                        "checkpoints/step_000000000000005.lxc",
                                        "checkpoints/.step_000000000000009.lxc.tmp",
                                        "vtk/bodies_000001.vtp",
                                        "vtk/contacts_1000000.vtp",
                                        "render/frame_000001.png",
                                        "render/.frame_000002.pov.tmp",
                                        "render/still_000012.png",
                                        "render/scene.inc",
                                        "plots/energy.png",
                                        "plots/plots.gp"};
  // ... and the user's, beside and among them.
  const std::map<std::string, std::string> users = {
      {"notes.txt", "mine"},
      {"bodies.csv.orig", "mine"},
      {"checkpoints/step_5.lxc.bak", "backup"},
      {"checkpoints/keep/step_000000000000001.lxc", "in a folder of mine"},
      {"vtk/bodies_x.vtp", "not a frame number"},
      {"vtk/mine.vtp", "mine"},
      {"render/frame_.png", "no digits"},
      {"render/my_frame_000001.png", "mine"},
      {"plots/energy.png.bak", "mine"},
      {"plots/energy.svg/inside.txt", "a folder where linx writes a file"}};
  for (const std::string& f : own) write(dir_ / f, "old run");
  for (const auto& [f, text] : users) write(dir_ / f, text);

  linx::Recorder recorder(dir_);
  recorder.finish();

  std::map<std::string, std::string> expected = users;
  expected["bodies.csv"] = std::string(run_files::kBodies.header) + "\n";
  expected["joints.csv"] = std::string(run_files::kJoints.header) + "\n";
  expected["world.csv"] = std::string(run_files::kWorld.header) + "\n";
  EXPECT_EQ(files(), expected);
  // The run folders that held only the run's files are gone; the others stay.
  EXPECT_TRUE(fs::is_directory(dir_ / "checkpoints"));
  for (const char* name : {"vtk", "render", "plots"}) EXPECT_TRUE(fs::is_directory(dir_ / name));
  fs::remove_all(dir_ / "vtk");
  write(dir_ / "vtk/joints_000003.vtp", "old run");
  { linx::Recorder again(dir_); }
  EXPECT_FALSE(fs::exists(dir_ / "vtk"));
  // A file of the user's named like a run folder is not one.
  fs::remove_all(dir_ / "plots");
  write(dir_ / "plots", "a file of mine");
  { linx::Recorder again(dir_); }
  EXPECT_EQ(read(dir_ / "plots"), "a file of mine");
}

TEST_F(RunFolder, ASecondRecorderIntoAnOpenFolderIsRefusedAndTheFirstGoesOn) {
  const linx::Scene scene = linx::parseScene(kPendulum, "scene.json");
  linx::World world = linx::buildWorld(scene);
  linx::Recorder first(dir_);
  first.record(world);
  const std::map<std::string, std::string> before = files();
  try {
    linx::Recorder second(dir_);
    FAIL() << "a second recorder opened the folder";
  } catch (const linx::RunFolderError& e) {
    EXPECT_EQ(std::string(e.what()),
              dir_.string() +
                  ": another run or recording is writing into this folder (it holds the folder's "
                  "lock); wait for it to end, or choose another folder");
  }
  EXPECT_EQ(files(), before);  // nothing removed or written
  // So is a resume of it.
  EXPECT_THROW({ linx::Recorder resumed(dir_, {}, first.position()); }, linx::RunFolderError);
  world.step();
  first.record(world);
  first.finish();  // the lock is released
  const std::string bodies = read(dir_ / "bodies.csv");
  EXPECT_EQ(std::count(bodies.begin(), bodies.end(), '\n'), 3);  // the header and two frames
  linx::Recorder next(dir_);
}

TEST_F(RunFolder, OpenRunCutsATornRowOnlyWhenNoRecorderHoldsTheFolder) {
  const linx::Scene scene = linx::parseScene(kPendulum, "scene.json");
  linx::World world = linx::buildWorld(scene);
  auto recorder = std::make_unique<linx::Recorder>(dir_, linx::RecorderOptions{.breaks = true});
  recorder->writeFile("scene.json", linx::runSceneJson(scene, world, 1));
  recorder->record(world);
  world.step();
  recorder->record(world);
  const std::map<std::string, std::string> whole = files();

  // What a kill inside the next frame leaves: its body row, half its joint row.
  const std::string torn_bodies = "0.02,bob,1,0,0,1,0,0,0,0,0,0,0,0,0\n", torn_joints = "0.02,piv";
  write(dir_ / "bodies.csv", torn_bodies, std::ios::app);
  write(dir_ / "joints.csv", torn_joints, std::ios::app);
  write(dir_ / "breaks.csv", "0.02,2,piv", std::ios::app);
  const std::map<std::string, std::string> torn = files();

  // The recorder still holds the folder: read as it is, nothing cut.
  const linx::viz::Run live = linx::viz::openRun(dir_);
  EXPECT_EQ(live.frames.size(), 2u);
  EXPECT_TRUE(live.truncated);
  EXPECT_EQ(files(), torn);

  recorder.reset();  // the writer is gone (as a killed process's lock is)
  const linx::viz::Run repaired = linx::viz::openRun(dir_);
  EXPECT_EQ(repaired.frames.size(), 2u);
  EXPECT_EQ(files(), whole);  // every file exactly as it was after its last whole frame
  EXPECT_FALSE(linx::viz::readRun(dir_).truncated);
  EXPECT_EQ(linx::viz::readRun(dir_).whole_bytes.at("bodies.csv"), whole.at("bodies.csv").size());
}

}  // namespace
