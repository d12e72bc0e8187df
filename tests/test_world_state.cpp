// World::saveState and restoreState: a world restored from a state steps on exactly as the world
// it was saved from, bit for bit (the truth: the same world never interrupted). Every example
// scene is checked, saved at a step where its contacts, joints, drives and sleep are under way,
// restored into a fresh world built from the same scene and into the same world rewound.
#include <linx/linx.hpp>

#include "world/state_archive.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

namespace fs = std::filesystem;

namespace {

// Everything a step's outcome shows: every body's pose and velocities, the joints' reactions and
// coordinates, the contacts and the time, as raw doubles.
std::vector<double> snapshot(const linx::World& world) {
  std::vector<double> out{world.time(), static_cast<double>(world.stepCount())};
  for (int i = 0; i < world.bodyCount(); ++i) {
    const linx::Body& b = world.body(linx::BodyId{i});
    for (const linx::Vec3& v : {b.position(), b.linearVelocity(), b.angularVelocity()})
      out.insert(out.end(), v.data(), v.data() + 3);
    out.insert(out.end(), b.orientation().coeffs().data(), b.orientation().coeffs().data() + 4);
    out.push_back(world.isAsleep(linx::BodyId{i}) ? 1.0 : 0.0);
  }
  for (int i = 0; i < world.jointCount(); ++i) {
    const linx::JointReaction r = world.jointReaction(linx::JointId{i});
    out.insert(out.end(), r.force.data(), r.force.data() + 3);
    out.insert(out.end(), r.torque.data(), r.torque.data() + 3);
    const linx::JointCoordinates q = world.jointCoordinates(linx::JointId{i});
    out.insert(out.end(), q.data(), q.data() + q.size());
  }
  for (const linx::Contact& c : world.contacts()) {
    out.push_back(c.normal_impulse);
    out.insert(out.end(), c.point.data(), c.point.data() + 3);
  }
  out.push_back(static_cast<double>(world.contacts().size()));
  out.push_back(world.lastReport().residual);
  out.push_back(world.lastReport().iterations);
  return out;
}

// Steps `world` n times and returns the snapshot after each.
std::vector<std::vector<double>> advance(linx::World& world, int n) {
  std::vector<std::vector<double>> out;
  for (int i = 0; i < n; ++i) {
    world.step();
    out.push_back(snapshot(world));
  }
  return out;
}

// The first step (1-based) at which two runs differ, 0 for none.
int firstDifference(const std::vector<std::vector<double>>& a,
                    const std::vector<std::vector<double>>& b) {
  for (std::size_t i = 0; i < a.size(); ++i)
    if (i >= b.size() || a[i].size() != b[i].size() ||
        std::memcmp(a[i].data(), b[i].data(), a[i].size() * sizeof(double)) != 0)
      return static_cast<int>(i) + 1;
  return 0;
}

// One check: a scene, where to save it, and the settings it is run with.
struct Case {
  std::string file;                        // under examples/
  std::optional<linx::SolverType> solver;  // instead of the scene's
  int saved_at = 0;  // 0: a third of the run, at most 400 steps (100 for the benchmarks)
  int threads = 1;
  bool expect_asleep = false;  // some body sleeps when the state is saved
};

// The truth: the world stepped on without a break. A fresh world built from the same scene and
// given the state, and the same world rewound to it, must step exactly as it did.
void checkCase(const Case& c) {
  linx::Scene scene = linx::loadModel(std::string(LINX_EXAMPLES_DIR) + "/" + c.file);
  if (c.solver) scene.settings.solver.type = *c.solver;
  scene.settings.threads = c.threads;
  const int steps = static_cast<int>(std::round(scene.duration / scene.settings.timestep));
  // The benchmark scenes run long, with the accurate integrator: a hundred frames is enough there.
  const int most = c.file.starts_with("benchmarks/") ? 100 : 400;
  const int saved_at = c.saved_at > 0 ? c.saved_at : std::min(most, std::max(1, steps / 3));
  const int after = 60;
  linx::World world = linx::buildWorld(scene);
  for (int i = 0; i < saved_at; ++i) world.step();
  if (c.expect_asleep) {
    bool asleep = false;
    for (const linx::BodyId id : world.bodyIds()) asleep = asleep || world.isAsleep(id);
    ASSERT_TRUE(asleep) << "nothing sleeps at step " << saved_at;
  }
  const linx::WorldState state = world.saveState();
  const std::vector<std::vector<double>> truth = advance(world, after);

  linx::World fresh = linx::buildWorld(scene);
  fresh.restoreState(state);
  EXPECT_EQ(firstDifference(truth, advance(fresh, after)), 0) << "a fresh world";

  world.restoreState(state);  // the same world, rewound
  EXPECT_EQ(firstDifference(truth, advance(world, after)), 0) << "the world rewound";
  // A state saved after a restore is the same bytes.
  world.restoreState(state);
  EXPECT_TRUE(world.saveState().bytes == state.bytes);
}

class ExampleState : public ::testing::TestWithParam<std::string> {};

TEST_P(ExampleState, RestoredWorldsStepOnBitForBit) {
  checkCase(Case{GetParam(), std::nullopt, 0, 1, false});
}

// Every example, and the robots (URDF, MJCF).
std::vector<std::string> examples() {
  std::vector<std::string> names;
  for (const auto& entry : fs::recursive_directory_iterator(LINX_EXAMPLES_DIR)) {
    const std::string ext = entry.path().extension().string();
    if (ext == ".json" || ext == ".urdf" || ext == ".xml")
      names.push_back(fs::relative(entry.path(), LINX_EXAMPLES_DIR).string());
  }
  std::sort(names.begin(), names.end());
  return names;
}

INSTANTIATE_TEST_SUITE_P(Examples, ExampleState, ::testing::ValuesIn(examples()),
                         [](const auto& info) {
                           std::string name = info.param.substr(0, info.param.find('.'));
                           for (char& c : name)
                             if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
                           return name;
                         });

// The soft step (substeps, soft contacts, exact joints inside), threads, and sleeping islands.
TEST(WorldState, TheSoftStepResumesBitForBit) {
  for (const char* file : {"pyramid.json", "box_stack.json", "chain_drop.json", "ragdoll.json",
                           "car_ramp.json", "wrecking_ball.json", "gripper.json"}) {
    SCOPED_TRACE(file);
    checkCase(Case{file, linx::SolverType::Soft, 0, 1, false});
  }
}

TEST(WorldState, TwoThreadsResumeBitForBit) {
  checkCase(Case{"pyramid.json", std::nullopt, 0, 2, false});
  checkCase(Case{"poured_spheres.json", linx::SolverType::Soft, 200, 2, false});
}

TEST(WorldState, SleepingIslandsResumeBitForBit) {
  // The stack settles and sleeps within 8 s (960 steps of 1/120 s).
  checkCase(Case{"box_stack.json", std::nullopt, 960, 1, true});
  checkCase(Case{"box_stack.json", linx::SolverType::Soft, 960, 1, true});
}

// Found by fuzz_state (scripts/fuzz.sh): a byte read back as a bool that is neither 0 nor 1 was
// undefined behaviour; it is refused.
TEST(WorldState, ABooleanThatIsNeitherZeroNorOneIsRefused) {
  for (const int value : {0, 1, 27}) {
    const std::vector<std::byte> bytes{static_cast<std::byte>(value)};
    linx::state::Archive a = linx::state::Archive::reader(bytes);
    bool b = false;
    if (value > 1) {
      EXPECT_THROW(a(b), linx::state::StateError);
    } else {
      a(b);
      EXPECT_EQ(b, value == 1);
    }
  }
}

// A state put in a world of another shape, or damaged, is refused and leaves the world as it was.
TEST(WorldState, AStateOfAnotherWorldOrDamagedIsRefused) {
  const linx::Scene pendulum = linx::loadModel(std::string(LINX_EXAMPLES_DIR) + "/pendulum.json");
  const linx::Scene chain = linx::loadModel(std::string(LINX_EXAMPLES_DIR) + "/hinge_chain.json");
  linx::World a = linx::buildWorld(pendulum), b = linx::buildWorld(chain);
  for (int i = 0; i < 10; ++i) a.step();
  const linx::WorldState state = a.saveState();
  const std::vector<double> before = snapshot(b);
  try {
    b.restoreState(state);
    ADD_FAILURE() << "a pendulum's state went into a chain";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("restoreState: the state is of another world"),
              std::string::npos)
        << e.what();
  }
  EXPECT_EQ(snapshot(b), before);

  linx::World c = linx::buildWorld(pendulum);
  const std::vector<double> fresh = snapshot(c);
  // Cut short at every length, and with one byte flipped in the middle of its numbers: refused
  // or, where the flip lands in a number, taken; never a crash or a read past the end.
  for (std::size_t n = 0; n < state.bytes.size(); n += 7) {
    linx::WorldState cut{std::vector<std::byte>(state.bytes.begin(), state.bytes.begin() + n)};
    EXPECT_THROW(c.restoreState(cut), std::invalid_argument) << n;
    EXPECT_EQ(snapshot(c), fresh);
  }
  linx::WorldState longer = state;
  longer.bytes.push_back(std::byte{0});
  EXPECT_THROW(c.restoreState(longer), std::invalid_argument);
  EXPECT_EQ(snapshot(c), fresh);
}

// A state whose integrator parts hold values the step never writes (a wait above the longest, a
// step size that is not a finite number) is refused: with "auto", the default, they are read on
// the next step (a wait doubled past the int range was undefined behaviour).
TEST(WorldState, IntegratorWaitsAndStepSizeOutOfRangeAreRefused) {
  const linx::Scene pendulum = linx::loadModel(std::string(LINX_EXAMPLES_DIR) + "/pendulum.json");
  ASSERT_EQ(pendulum.bodies.size(), 1u);
  linx::World world = linx::buildWorld(pendulum);
  world.step();
  const linx::WorldState state = world.saveState();
  // The state ends with the accurate integrator's step size (a double) and its held limits (two
  // counts, none held), then "auto"'s waits and back-offs (a count and an int32 each, one body),
  // then the bodies behind (a count, a byte).
  const std::size_t end = state.bytes.size(), backoff = end - 9 - 4, wait = backoff - 8 - 4,
                    held = wait - 8 - 16, step_size = held - 8;
  const auto at = [&](std::size_t offset, auto value) {
    std::memcpy(&value, state.bytes.data() + offset, sizeof value);
    return value;
  };
  ASSERT_EQ(at(end - 9, std::uint64_t{}), 1u);
  ASSERT_EQ(at(backoff - 8, std::uint64_t{}), 1u);
  ASSERT_EQ(at(wait - 8, std::uint64_t{}), 1u);
  ASSERT_EQ(at(wait, std::int32_t{}), 0);  // its one step a frame held: no wait
  ASSERT_EQ(at(held, std::uint64_t{}), 0u);
  ASSERT_EQ(at(held + 8, std::uint64_t{}), 0u);
  const std::vector<double> before = snapshot(world);
  const auto refused = [&](std::size_t at, const auto& value, const char* what) {
    linx::WorldState bad = state;
    std::memcpy(bad.bytes.data() + at, &value, sizeof value);
    try {
      world.restoreState(bad);
      ADD_FAILURE() << what << " was taken";
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find(what), std::string::npos) << e.what();
    }
    EXPECT_EQ(snapshot(world), before);
  };
  refused(backoff, std::int32_t{0x7fffffff}, "integrator waits out of range");
  refused(wait, std::int32_t{-3}, "integrator waits out of range");
  refused(step_size, std::nan(""), "step size not a finite number >= 0");
  refused(step_size, -1.0, "step size not a finite number >= 0");
  // The state itself goes back in and steps on.
  world.restoreState(state);
  world.step();
}

}  // namespace
