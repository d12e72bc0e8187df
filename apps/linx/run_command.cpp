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

#include "io/input_file.hpp"
#include "io/run_folder.hpp"

#include <fcntl.h>
#include <fmt/format.h>
#include <sys/stat.h>
#include <unistd.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <optional>
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
// A stop signal ends it (whileLoading).
Prepared prepare(const RunOptions& options) {
  std::optional<Prepared> prepared;
  whileLoading(options.scene, [&] {
    Scene scene =
        loadModel(options.scene, ImportOptions{.floating_base = options.floating_base,
                                               .allow_outside_paths = options.allow_outside_paths});
    for (const std::string& warning : scene.warnings) say(stderr, "linx: warning: {}\n", warning);
    if (options.duration) scene.duration = *options.duration;
    if (options.timestep) scene.settings.timestep = *options.timestep;
    if (options.threads) scene.settings.threads = *options.threads;
    if (options.keep_going) scene.settings.faults.stop = false;
    const std::int64_t steps = stepCount(scene, options);
    World world = buildWorld(scene);
    prepared.emplace(Prepared{std::move(scene), std::move(world), steps});
  });
  return std::move(*prepared);
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
    say("t = {:.9g} s: joint '{}' broke: {} (force {:.6g} N, torque {:.6g} N m)\n", b.time,
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
    // step_N.lxc only: another file of the folder is the user's, never taken or pruned.
    if (run_files::matchesPattern(run_files::kCheckpointNames[0], name))
      found.push_back(it->path());
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
    say(stderr, "linx: {}: interrupted inside step {}, still running 1 s after the signal; {}\n",
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
      say(stderr, "linx: warning: {}: {}; going on (--on-fault continue)\n", s.run.source,
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
      say(stderr, "linx: {}: {}; {}; the last good state (t = {} s) is in {}\n", s.run.source,
          e.what(), keptOutput(s, last_frame_time), last_good_time, saved.string());
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
      say(stderr, "linx: {}: interrupted at step {} (t = {} s); {}\n", s.run.source, step,
          world.time(), keptOutput(s, last_frame_time));
      return kExitInterrupted;
    }
    progress.update(step, world.time());
  }
  progress.clear();
  s.recorder.finish();
  if (world.faultCount() > static_cast<std::int64_t>(kFaultWarnings))
    say(stderr, "linx: warning: {}: {} faults in all, the first {} shown above\n", s.run.source,
        world.faultCount(), kFaultWarnings);
  say("wrote {} files to {} ({} frames, {} steps, t = {} s)\n",
      4 + int{s.run.contacts} + int{s.run.breaks}, s.out.string(), s.run.frames, steps,
      world.time());
  return 0;
}

// A checkpoint that lies outside its run folder (a link to another run's, or in a checkpoints
// folder that is a link) is another run's: refused.
void refuseOutsideFolder(const fs::path& file, const fs::path& out) {
  std::error_code ec;
  const fs::path target = fs::weakly_canonical(file, ec), folder = fs::weakly_canonical(out, ec);
  const auto [end, at] = std::mismatch(folder.begin(), folder.end(), target.begin(), target.end());
  if (end == folder.end()) return;
  throw CheckpointError(
      file.string(), "file",
      fmt::format("{} {}, outside the run folder {}: another run's checkpoint; resume that run's "
                  "own folder",
                  fs::is_symlink(file, ec) ? "a link to" : "lies in a linked folder, at",
                  target.string(), out.string()));
}

// The newest checkpoint that reads, of a file or a run folder; `file` is set to it.
RunCheckpoint loadCheckpoint(const std::string& given, fs::path& out, fs::path& file) {
  std::error_code ec;
  if (!fs::is_directory(given, ec)) {
    // DIR/checkpoints/FILE: the run folder is the checkpoint folder's parent.
    out = fs::absolute(given).parent_path().parent_path();
    file = given;
    RunCheckpoint c = readCheckpoint(given);
    refuseOutsideFolder(file, out);
    return c;
  }
  out = given;
  std::vector<fs::path> all = checkpoints(out);
  if (all.empty())
    throw BadInput(fmt::format("{}: no checkpoints in {} (run with --checkpoint-every)", given,
                               checkpointFolder(out).string()));
  // The newest is written whole or not at all; an older one serves if it was damaged since.
  for (std::size_t i = all.size(); i-- > 0;) {
    refuseOutsideFolder(all[i], out);  // not a damaged one: another run's, refused outright
    try {
      file = all[i];
      return readCheckpoint(all[i]);
    } catch (const CheckpointError& e) {
      if (i == 0) throw;
      say(stderr, "linx: warning: {}; taking an older checkpoint\n", e.what());
    }
  }
  throw BadInput(fmt::format("{}: no checkpoint reads", given));
}

// Refuses a checkpoint whose counts would make more work than its scene's run: its steps are
// at most the scene's duration / timestep + 1, the world's step, time and frames within them.
void checkBounds(const fs::path& file, const RunCheckpoint& c, const Scene& scene,
                 const World& world) {
  const double h = scene.settings.timestep;
  const double most = std::floor(scene.duration / h) + 1;
  const std::string name = file.string();
  if (static_cast<double>(c.steps) > most)
    throw CheckpointError(name, "steps",
                          fmt::format("{} steps, more than its scene's duration / timestep + 1 "
                                      "({} s / {} s + 1 = {:.0f})",
                                      c.steps, scene.duration, h, most));
  const std::int64_t step = world.stepCount();
  if (step < 0)
    throw CheckpointError(name, "state", fmt::format("step {} is before the start", step));
  if (!(world.time() >= 0 && world.time() <= static_cast<double>(c.steps + 1) * h))
    throw CheckpointError(name, "state",
                          fmt::format("time {} s is outside the run (0 to (steps + 1) * timestep "
                                      "= {} s)",
                                      world.time(), static_cast<double>(c.steps + 1) * h));
  if (c.frames > step + 1)
    throw CheckpointError(
        name, "frames",
        fmt::format("{} frames at step {}: more than one per step and the first", c.frames, step));
}

// Refuses a checkpoint that is not of the run in `out`: the folder's scene.json must be the one
// the checkpoint's run wrote, with the bodies and joints of the checkpoint's world, in order.
void checkRunFolder(const fs::path& file, const RunCheckpoint& c, const World& world,
                    const fs::path& out) {
  const std::string name = file.string();
  const fs::path scene_path = out / run_files::kScene.name;
  std::string text;
  try {
    text = io::readInputFile(scene_path, io::kSceneLimit, "a scene");
  } catch (const std::runtime_error& e) {
    throw CheckpointError(name, "run folder",
                          fmt::format("{}: {}: the folder holds no run to go on with",
                                      scene_path.string(), e.what()));
  }
  if (text.size() != c.run_scene_bytes || checksumOf(text) != c.run_scene_crc)
    throw CheckpointError(
        name, "run folder",
        fmt::format("{} is not the scene.json of the checkpoint's run ({} bytes, CRC-32 {:08x}; "
                    "the run wrote {} bytes, CRC-32 {:08x}): another run's checkpoint?",
                    scene_path.string(), text.size(), checksumOf(text), c.run_scene_bytes,
                    c.run_scene_crc));
  if (world.bodyCount() != c.bodies || world.jointCount() != c.joints)
    throw CheckpointError(name, "scene",
                          fmt::format("{} bodies and {} joints; its run recorded {} and {}",
                                      world.bodyCount(), world.jointCount(), c.bodies, c.joints));
  // The rows of a frame are the scene.json's bodies and joints: the checkpoint's world's.
  const nlohmann::json doc = nlohmann::json::parse(text, nullptr, false);
  const auto names = [&](const char* key, int count, auto nameOf) {
    const auto list = doc.is_object() ? doc.find(key) : doc.end();
    bool same = doc.is_object() && list != doc.end() && list->is_array() &&
                list->size() == static_cast<std::size_t>(count);
    for (int i = 0; same && i < count; ++i) {
      const nlohmann::json& item = (*list)[static_cast<std::size_t>(i)];
      same = item.is_object() && item.contains("name") && item["name"].is_string() &&
             item["name"].get<std::string>() == nameOf(i);
    }
    if (!same)
      throw CheckpointError(name, "scene",
                            fmt::format("its {} are not those of {}", key, scene_path.string()));
  };
  names("bodies", world.bodyCount(), [&](int i) { return world.body(BodyId{i}).name(); });
  names("joints", world.jointCount(), [&](int i) { return world.joint(JointId{i}).name(); });
}

// The recorder of a new run in `out`: a folder that cannot take it (another run writes it, a
// folder of the user's is in the way) is bad input.
Recorder openRecorder(const std::string& out, const RunCheckpoint& run) {
  try {
    return Recorder(out, RecorderOptions{.contacts = run.contacts, .breaks = run.breaks});
  } catch (const RunFolderError& e) {
    throw BadInput(fmt::format("--out: {}", e.what()));
  }
}

// Refuses a run that would remove or replace one of the files its scene was read from: an input
// that is one of the earlier run's entries in `out` (run_files.hpp), by its identity (device and
// inode), so that a link to it, or a path through a linked folder, is found too.
void refuseOwnInputs(const std::vector<io::InputRead>& inputs, const std::string& out) {
  const int dir_fd = ::open(out.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (dir_fd < 0) return;  // no folder yet: nothing of it is read
  struct Closer {
    int fd;
    ~Closer() { ::close(fd); }
  } closer{dir_fd};
  for (const fs::path& entry : io::earlierRunEntries(dir_fd, out)) {
    // The entry itself: a link is removed as a link, what it points to is kept.
    struct stat st {};
    if (::fstatat(dir_fd, entry.c_str(), &st, AT_SYMLINK_NOFOLLOW) != 0) continue;
    for (const io::InputRead& input : inputs) {
      if (input.device != static_cast<std::uint64_t>(st.st_dev) ||
          input.inode != static_cast<std::uint64_t>(st.st_ino))
        continue;
      throw BadInput(fmt::format(
          "--out: {}: the run would replace its own input {} ({}; {} is a run file); move it "
          "out of the folder, or choose another folder",
          out, input.path.string(), input.kind, entry.string()));
    }
  }
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
  say("{}: ok: {}, {}{}, timestep {} s, duration {} s ({} steps), solver {}{}\n", options.scene,
      count(p.scene.bodies.size(), "body", "bodies"),
      count(p.scene.joints.size(), "joint", "joints"), extra, p.scene.settings.timestep,
      p.scene.duration, p.steps, solverTypeName(p.scene.settings.solver.type), integrator);
  return 0;
}

int run(const RunOptions& options) {
  if (options.every < 1)
    throw BadInput(fmt::format("--every: must be at least 1, got {}", options.every));
  checkOutputFolder("--out", options.out);
  // Every file the scene reads is logged, so that none of them is one the run replaces.
  const io::InputLog inputs;
  Prepared p = prepare(options);
  refuseOwnInputs(inputs.files(), options.out);
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

  run.bodies = p.world.bodyCount();
  run.joints = p.world.jointCount();

  const StopSignals stop_signals;
  // Replaces an earlier run in the folder; every frame is on disk once recorded
  // (docs/reliability.md), so a run stopped at any point keeps what it recorded.
  Session s{std::move(p.world), openRecorder(options.out, run), options.out, std::move(run)};
  s.recorder.record(s.world);
  s.run.frames = 1;
  const std::string scene_json = runSceneJson(p.scene, s.world, options.every);
  s.run.run_scene_bytes = scene_json.size();
  s.run.run_scene_crc = checksumOf(scene_json);
  s.recorder.writeFile(std::string(run_files::kScene.name), scene_json);
  const int status = simulate(s);
  if (status != 0) return status;
  if (options.vtk) writeVtk(options.out);
  if (options.render) return render(RenderOptions{.dir = options.out});
  return 0;
}

int resume(const std::string& given, std::optional<bool> keep_going) {
  fs::path out, file;
  RunCheckpoint c = loadCheckpoint(given, out, file);
  if (keep_going) c.keep_going = *keep_going;
  std::optional<Scene> loaded;
  std::optional<World> built;
  whileLoading(given, [&] {
    loaded.emplace(parseScene(c.scene, file.string() + " (its scene)"));
    built.emplace(buildWorld(*loaded));
  });
  const Scene& scene = *loaded;
  World world = std::move(*built);
  try {
    world.restoreState(c.state);
  } catch (const std::invalid_argument& e) {
    throw CheckpointError(file.string(), "state", e.what());
  }
  if (c.keep_going) world.settings().faults.stop = false;
  if (world.stepCount() >= c.steps)
    throw BadInput(
        fmt::format("{}: the run had ended (step {} of {})", given, world.stepCount(), c.steps));
  checkBounds(file, c, scene, world);
  checkRunFolder(file, c, world, out);
  const RecorderOptions recording{.contacts = c.contacts, .breaks = c.breaks};
  const RecorderPosition at = c.output;
  // Reopens the files, cut back to the checkpoint, under the folder's lock: refused when a file
  // is missing, shorter than then, or not its kind (its header), with nothing changed.
  const auto reopen = [&] {
    try {
      return Recorder(out, recording, at);
    } catch (const RunFolderError& e) {
      throw CheckpointError(file.string(), "run folder", e.what());
    }
  };
  const StopSignals stop_signals;
  Session s{std::move(world), reopen(), out, std::move(c)};
  say(stderr, "linx: resuming {} at step {} (t = {} s) in {}\n", s.run.source, s.world.stepCount(),
      s.world.time(), out.string());
  return simulate(s);
}

int writeVtk(const std::string& dir) {
  const viz::Run run = viz::openRun(dir);
  const viz::VtkSummary written = viz::writeVtk(run, dir);
  say("wrote {} ({} frames in {})\n", written.collection.string(), written.frames,
      written.folder.string());
  return 0;
}

}  // namespace linx::cli
