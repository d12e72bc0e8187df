// `linx run`, `linx check` and `linx resume`. A run is a loop of steps that records frames,
// writes checkpoints and stops on a fault or a signal; `resume` rebuilds the world from a
// checkpoint (its scene, then its state) and enters the same loop where the checkpoint was taken.
#include "run_command.hpp"

#include "cli_common.hpp"
#include "progress.hpp"
#include "render_command.hpp"
#include "stop_signals.hpp"
#include "viz/run.hpp"
#include "viz/vtk.hpp"

#include <linx/bounds.hpp>
#include <linx/linx.hpp>
#include <linx/run_files.hpp>

#include <fmt/format.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <system_error>
#include <utility>
#include <vector>

namespace linx::cli {

namespace fs = std::filesystem;

namespace {

// Runs longer than this are refused: step numbers and times stay exact in a double.
constexpr double kMaxSteps = 1e15;
// Checkpoints kept in DIR/checkpoints: the newest and the one before it.
constexpr std::size_t kCheckpointsKept = 2;
// How often (wall-clock time) the state at a recorded frame is kept as a fault's last good state.
constexpr std::chrono::seconds kLastGoodInterval{1};
// Faults reported one by one under --on-fault continue; the rest are counted.
constexpr std::size_t kFaultWarnings = 10;

// The number of steps of a run, round(duration / timestep); at least one.
std::int64_t stepCount(const Scene& scene, const RunOptions& options) {
  if (const double h = scene.settings.timestep; !(h >= kMinTimestep)) {
    const std::string problem = fmt::format(
        "{:g} s is below {:g} s, the shortest step whose square (the step forms h^2) is a normal "
        "double",
        h, kMinTimestep);
    if (options.timestep) throw BadInput("--timestep: " + problem);
    throw SceneError(scene.file, "timestep", problem);
  }
  const double steps = std::round(scene.duration / scene.settings.timestep);
  if (steps >= 1 && steps <= kMaxSteps) return static_cast<std::int64_t>(steps);
  const std::string problem =
      steps < 1 ? fmt::format("{} s is shorter than half a timestep ({} s)", scene.duration,
                              scene.settings.timestep)
                : fmt::format("{} s at a timestep of {} s is more than {:g} steps", scene.duration,
                              scene.settings.timestep, kMaxSteps);
  if (options.duration || options.timestep)
    throw BadInput(fmt::format("{}: {}", options.duration ? "--duration" : "--timestep", problem));
  throw SceneError(scene.file, "duration", problem);
}

struct Prepared {
  Scene scene;
  World world;
  std::int64_t steps;
};

// Loads the scene, applies the flags and builds the world: everything that can reject the input.
Prepared prepare(const RunOptions& options) {
  Scene scene =
      loadModel(options.scene, ImportOptions{.floating_base = options.floating_base,
                                             .allow_outside_paths = options.allow_outside_paths});
  for (const std::string& warning : scene.warnings)
    fmt::print(stderr, "linx: warning: {}\n", warning);
  if (options.duration) scene.duration = *options.duration;
  if (options.timestep) scene.settings.timestep = *options.timestep;
  if (options.threads) scene.settings.threads = *options.threads;
  if (options.keep_going) scene.settings.faults.stop = false;
  const std::int64_t steps = stepCount(scene, options);
  World world = buildWorld(scene);
  return {std::move(scene), std::move(world), steps};
}

// One line on stdout for each joint that broke since the last call.
void reportBreaks(const World& world, std::size_t& reported, ProgressBar& progress) {
  const auto breaks = world.jointBreaks();
  for (; reported < breaks.size(); ++reported) {
    const JointBreak& b = breaks[reported];
    const JointDef& def = world.joint(b.joint).def();
    const double force = b.reaction.force.norm(), torque = b.reaction.torque.norm();
    const bool by_force = force > def.break_force.value_or(kInfinity);
    progress.clear();
    fmt::print("t = {:.9g} s: joint '{}' broke: {} (force {:.6g} N, torque {:.6g} N m)\n", b.time,
               def.name,
               by_force ? fmt::format("force above its break_force of {} N", *def.break_force)
                        : fmt::format("torque above its break_torque of {} N m", *def.break_torque),
               force, torque);
  }
}

// A run in progress: its world, its files and where it stands (RunCheckpoint's fields).
struct Session {
  World world;
  Recorder recorder;
  fs::path out;
  RunCheckpoint run;  // scene, source, steps, every, ...; frames and output kept current
};

fs::path checkpointFolder(const fs::path& out) {
  std::string name(run_files::kCheckpoints.name);
  name.pop_back();  // the trailing '/'
  return out / name;
}

fs::path checkpointPath(const fs::path& out, std::int64_t step) {
  return checkpointFolder(out) / fmt::format("step_{:015}.lxc", step);
}

// The checkpoints of a run folder, oldest first.
std::vector<fs::path> checkpoints(const fs::path& out) {
  std::vector<fs::path> found;
  std::error_code ec;
  for (fs::directory_iterator it(checkpointFolder(out), ec), end; !ec && it != end;
       it.increment(ec)) {
    const std::string name = it->path().filename().string();
    if (name.starts_with("step_") && name.ends_with(".lxc")) found.push_back(it->path());
  }
  std::sort(found.begin(), found.end());
  return found;
}

// Writes a checkpoint of the session as it is now (or of `state` and `output` given), and
// removes the older ones beyond the last kCheckpointsKept.
fs::path writeRunCheckpoint(Session& s, const WorldState& state, const RecorderPosition& output,
                            std::int64_t frames, std::int64_t step) {
  std::error_code ec;
  fs::create_directories(checkpointFolder(s.out), ec);
  RunCheckpoint c = s.run;
  c.state = state;
  c.output = output;
  c.frames = frames;
  const fs::path file = checkpointPath(s.out, step);
  writeCheckpoint(file, c);
  std::vector<fs::path> all = checkpoints(s.out);
  for (std::size_t i = 0; i + kCheckpointsKept < all.size(); ++i) fs::remove(all[i], ec);
  return file;
}

// "output kept up to t = T s in DIR": what a run that stopped early leaves.
std::string keptOutput(const Session& s, double last_frame_time) {
  return fmt::format("output kept up to t = {} s in {}", last_frame_time, s.out.string());
}

// Steps the session to its end. Returns the exit status.
int simulate(Session& s) {
  World& world = s.world;
  const std::int64_t steps = s.run.steps;
  // The last recorded frame: its time, and the world and files then (a fault's last good state).
  double last_frame_time = world.time();
  WorldState last_good = world.saveState();
  RecorderPosition last_good_output = s.recorder.position();
  std::int64_t last_good_frames = s.run.frames, last_good_step = world.stepCount();
  double last_good_time = world.time();
  std::size_t breaks_reported = world.jointBreaks().size(), faults_reported = 0;
  std::int64_t step = world.stepCount();
  ProgressBar progress(isatty(fileno(stderr)) ? stderr : nullptr, steps,
                       static_cast<double>(steps) * world.settings().timestep);
  // A step that runs on for a second after SIGINT or SIGTERM (a huge dense solve) is not waited
  // for: the frames recorded are already whole on disk.
  StopWatchdog watchdog(std::chrono::seconds(1), [&] {
    fmt::print(stderr,
               "linx: {}: interrupted inside step {}, still running 1 s after the signal; {}\n",
               s.run.source, step, keptOutput(s, last_frame_time));
    std::_Exit(kExitInterrupted);
  });
  // The last good state is taken at a recorded frame, at most once a second of the run's own
  // time: a state costs as much as a fifth of a step (a pyramid's), too much for every frame.
  auto last_good_taken = std::chrono::steady_clock::now();
  const auto recordFrame = [&] {
    s.recorder.record(world);
    ++s.run.frames;
    last_frame_time = world.time();
    const auto now = std::chrono::steady_clock::now();
    if (now - last_good_taken < kLastGoodInterval) return;
    last_good_taken = now;
    last_good = world.saveState();
    last_good_output = s.recorder.position();
    last_good_frames = s.run.frames;
    last_good_step = world.stepCount();
    last_good_time = world.time();
  };
  const auto reportFaults = [&] {
    const auto faults = world.faults();
    for (; faults_reported < faults.size(); ++faults_reported) {
      if (faults_reported >= kFaultWarnings) continue;
      progress.clear();
      fmt::print(stderr, "linx: warning: {}: {}; going on (--on-fault continue)\n", s.run.source,
                 faults[faults_reported]);
    }
  };

  for (step = world.stepCount() + 1; step <= steps; ++step) {
    try {
      const StopWatchdog::Busy busy(watchdog);
      world.step();
    } catch (const StepFault& e) {  // a non-finite state, energy made, a bound passed
      progress.clear();
      s.recorder.finish();
      const fs::path saved =
          writeRunCheckpoint(s, last_good, last_good_output, last_good_frames, last_good_step);
      fmt::print(stderr, "linx: {}: {}; {}; the last good state (t = {} s) is in {}\n",
                 s.run.source, e.what(), keptOutput(s, last_frame_time), last_good_time,
                 saved.string());
      return kExitNonFinite;
    }
    reportBreaks(world, breaks_reported, progress);
    if (s.run.keep_going) reportFaults();
    if (step % s.run.every == 0 || step == steps || StopSignals::received()) recordFrame();
    if (s.run.checkpoint_every > 0 && step % s.run.checkpoint_every == 0 && step < steps)
      writeRunCheckpoint(s, world.saveState(), s.recorder.position(), s.run.frames, step);
    if (StopSignals::received()) {
      progress.clear();
      s.recorder.finish();
      fmt::print(stderr, "linx: {}: interrupted at step {} (t = {} s); {}\n", s.run.source, step,
                 world.time(), keptOutput(s, last_frame_time));
      return kExitInterrupted;
    }
    progress.update(step, world.time());
  }
  progress.clear();
  s.recorder.finish();
  if (world.faultCount() > static_cast<std::int64_t>(kFaultWarnings))
    fmt::print(stderr, "linx: warning: {}: {} faults in all, the first {} shown above\n",
               s.run.source, world.faultCount(), kFaultWarnings);
  fmt::print("wrote {} files to {} ({} frames, {} steps, t = {} s)\n",
             4 + int{s.run.contacts} + int{s.run.breaks}, s.out.string(), s.run.frames, steps,
             world.time());
  return 0;
}

// The newest checkpoint that reads, of a file or a run folder.
RunCheckpoint loadCheckpoint(const std::string& given, fs::path& out) {
  std::error_code ec;
  if (!fs::is_directory(given, ec)) {
    RunCheckpoint c = readCheckpoint(given);
    // DIR/checkpoints/FILE: the run folder is the checkpoint folder's parent.
    out = fs::absolute(given).parent_path().parent_path();
    return c;
  }
  out = given;
  std::vector<fs::path> all = checkpoints(out);
  if (all.empty())
    throw BadInput(fmt::format("{}: no checkpoints in {} (run with --checkpoint-every)", given,
                               checkpointFolder(out).string()));
  // The newest is written whole or not at all; an older one serves if it was damaged since.
  for (std::size_t i = all.size(); i-- > 0;) {
    try {
      return readCheckpoint(all[i]);
    } catch (const CheckpointError& e) {
      if (i == 0) throw;
      fmt::print(stderr, "linx: warning: {}; taking an older checkpoint\n", e.what());
    }
  }
  throw BadInput(fmt::format("{}: no checkpoint reads", given));
}

}  // namespace

// What the first step would stop on (a fault: a state or an energy that is not finite, a bound
// passed; with faults.stop false all but the first are kept) is found by taking it, and refused
// with the fault's message, which names the body (the accurate integrator's, the body and the
// joints of its island): masses, inertias, loads, gravity or gains that the step cannot hold in a
// double, which no bound on one field finds.
void checkFirstStep(const Scene& scene, World& world) {
  try {
    world.step();
  } catch (const StepFault& fault) {
    throw SceneError(scene.file, "", fmt::format("the first step would stop: {}", fault.what()));
  }
}

int check(const RunOptions& options) {
  Prepared p = prepare(options);
  checkFirstStep(p.scene, p.world);
  const auto count = [](std::size_t n, const char* one, const char* many) {
    return fmt::format("{} {}", n, n == 1 ? one : many);
  };
  // Springs and loads only when the scene has them.
  std::string extra;
  if (!p.scene.springs.empty()) extra += ", " + count(p.scene.springs.size(), "spring", "springs");
  if (!p.scene.loads.empty()) extra += ", " + count(p.scene.loads.size(), "load", "loads");
  // The integrator, with its tolerance unless it is the step (which has none).
  const IntegratorSettings& i = p.scene.settings.integrator;
  const std::string integrator =
      i.type == IntegratorType::Step
          ? std::string(", integrator step")
          : fmt::format(", integrator {} (tolerance {})", integratorTypeName(i.type), i.tolerance);
  fmt::print("{}: ok: {}, {}{}, timestep {} s, duration {} s ({} steps), solver {}{}\n",
             options.scene, count(p.scene.bodies.size(), "body", "bodies"),
             count(p.scene.joints.size(), "joint", "joints"), extra, p.scene.settings.timestep,
             p.scene.duration, p.steps, solverTypeName(p.scene.settings.solver.type), integrator);
  return 0;
}

int run(const RunOptions& options) {
  if (options.every < 1)
    throw BadInput(fmt::format("--every: must be at least 1, got {}", options.every));
  checkOutputFolder("--out", options.out);
  std::error_code ec;
  // A run clears its folder's run files: never the scene it is about to read.
  const fs::path input = fs::weakly_canonical(fs::absolute(options.scene), ec);
  for (const run_files::RunFile& file : run_files::kAll) {
    std::string name(file.name);
    if (name.back() == '/') name.pop_back();
    const fs::path output = fs::weakly_canonical(fs::absolute(fs::path(options.out) / name), ec);
    const auto [end, at] = std::mismatch(output.begin(), output.end(), input.begin(), input.end());
    if (end == output.end())  // the input is that file, or in that folder
      throw BadInput(
          fmt::format("--out: {}: the run would replace its own input {} ({} is a run "
                      "file); choose another folder",
                      options.out, options.scene, name));
  }
  Prepared p = prepare(options);
  bool breakable = false;
  for (const SceneJoint& j : p.scene.joints)
    breakable = breakable || j.def.break_force || j.def.break_torque;
  RunCheckpoint run;
  run.scene = writeSceneJson(p.scene);
  run.source = options.scene;
  run.steps = p.steps;
  run.every = options.every;
  if (options.checkpoint_every)
    run.checkpoint_every = std::max<std::int64_t>(
        1, std::llround(*options.checkpoint_every / p.scene.settings.timestep));
  run.contacts = options.contacts;
  run.breaks = breakable;
  run.keep_going = options.keep_going;

  const StopSignals stop_signals;
  // Replaces an earlier run in the folder; every frame is on disk once recorded
  // (docs/reliability.md), so a run stopped at any point keeps what it recorded.
  Session s{std::move(p.world),
            Recorder(options.out, RecorderOptions{.contacts = run.contacts, .breaks = run.breaks}),
            options.out, std::move(run)};
  s.recorder.record(s.world);
  s.run.frames = 1;
  s.recorder.writeFile(std::string(run_files::kScene.name),
                       runSceneJson(p.scene, s.world, options.every));
  const int status = simulate(s);
  if (status != 0) return status;
  if (options.vtk) writeVtk(options.out);
  if (options.render) return render(RenderOptions{.dir = options.out});
  return 0;
}

int resume(const std::string& given, std::optional<bool> keep_going) {
  fs::path out;
  RunCheckpoint c = loadCheckpoint(given, out);
  if (keep_going) c.keep_going = *keep_going;
  const Scene scene = parseScene(c.scene, given + " (its scene)");
  World world = buildWorld(scene);
  try {
    world.restoreState(c.state);
  } catch (const std::invalid_argument& e) {
    throw CheckpointError(given, "state", e.what());
  }
  if (c.keep_going) world.settings().faults.stop = false;
  if (world.stepCount() >= c.steps)
    throw BadInput(
        fmt::format("{}: the run had ended (step {} of {})", given, world.stepCount(), c.steps));
  const StopSignals stop_signals;
  fmt::print(stderr, "linx: resuming {} at step {} (t = {} s) in {}\n", c.source, world.stepCount(),
             world.time(), out.string());
  const RecorderOptions recording{.contacts = c.contacts, .breaks = c.breaks};
  const RecorderPosition at = c.output;
  Session s{std::move(world), Recorder(out, recording, at), out, std::move(c)};
  return simulate(s);
}

int writeVtk(const std::string& dir) {
  const viz::Run run = viz::readRun(dir);
  const viz::VtkSummary written = viz::writeVtk(run, dir);
  fmt::print("wrote {} ({} frames in {})\n", written.collection.string(), written.frames,
             written.folder.string());
  return 0;
}

}  // namespace linx::cli
