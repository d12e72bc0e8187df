// The `linx` command line (docs/scene-format.md, "Command line"; docs/visualization.md):
//   linx run SCENE.json --out DIR [--duration T] [--timestep H] [--threads N] [--every N]
//            [--contacts] [--vtk] [--render]
//   linx check SCENE.json   (SCENE may be ROBOT.urdf [--floating-base] or MODEL.xml, MJCF)
//   linx convert SCENE.json|ROBOT.urdf OUT.json [--floating-base]
//   linx render DIR ...   linx vtk DIR   linx plot DIR ...   linx view DIR ...
// Every input is validated before anything is written. Errors are one line on stderr,
// "linx: FILE: FIELD: PROBLEM". Exit status: 0 success, 1 output or internal failure, 2 bad input
// (scene, flags, usage), 3 the run stopped on a fault (a non-finite state, energy made by an
// unstable solve), 130 interrupted.
#include "cli_common.hpp"
#include "plot_command.hpp"
#include "progress.hpp"
#include "render_command.hpp"
#include "stop_signals.hpp"
#include "view_command.hpp"
#include "viz/run.hpp"
#include "viz/vtk.hpp"

#include <linx/linx.hpp>
#include <linx/run_files.hpp>

#include <fmt/format.h>
#include <unistd.h>
#include <CLI/CLI.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>

#ifndef LINX_VERSION
#error "LINX_VERSION is set by CMakeLists.txt from project(VERSION)"
#endif

namespace {

using linx::cli::BadInput;
using linx::cli::kExitBadInput;
using linx::cli::kExitFailure;
using linx::cli::kExitInterrupted;
using linx::cli::kExitNonFinite;

// Runs longer than this are refused: step numbers and times stay exact in a double.
constexpr double kMaxSteps = 1e15;

struct RunOptions {
  std::string scene;
  std::string out;
  std::optional<double> duration, timestep;
  std::optional<int> threads;
  int every = 1;
  bool contacts = false;
  bool vtk = false;            // also write ParaView files (DIR/vtk/, DIR/run.pvd)
  bool render = false;         // then render POV-Ray frames (linx render DIR)
  bool floating_base = false;  // a URDF's root link is free
};

double positiveFlag(const char* flag, double value) {
  if (!(std::isfinite(value) && value > 0)) {
    throw BadInput(fmt::format("{}: must be a finite number > 0, got {}", flag, value));
  }
  return value;
}

// The number of steps of a run, round(duration / timestep); at least one.
std::int64_t stepCount(const linx::Scene& scene, const RunOptions& options) {
  const double steps = std::round(scene.duration / scene.settings.timestep);
  if (steps >= 1 && steps <= kMaxSteps) return static_cast<std::int64_t>(steps);
  const std::string problem =
      steps < 1 ? fmt::format("{} s is shorter than half a timestep ({} s)", scene.duration,
                              scene.settings.timestep)
                : fmt::format("{} s at a timestep of {} s is more than {:g} steps", scene.duration,
                              scene.settings.timestep, kMaxSteps);
  if (options.duration || options.timestep) {
    throw BadInput(fmt::format("{}: {}", options.duration ? "--duration" : "--timestep", problem));
  }
  throw linx::SceneError(scene.file, "duration", problem);
}

struct Prepared {
  linx::Scene scene;
  linx::World world;
  std::int64_t steps;
};

// Loads the scene, applies the flags and builds the world: everything that can reject the input.
Prepared prepare(const RunOptions& options) {
  linx::Scene scene =
      linx::loadModel(options.scene, linx::ImportOptions{.floating_base = options.floating_base});
  for (const std::string& warning : scene.warnings)
    fmt::print(stderr, "linx: warning: {}\n", warning);
  if (options.duration) scene.duration = *options.duration;
  if (options.timestep) scene.settings.timestep = *options.timestep;
  if (options.threads) scene.settings.threads = *options.threads;
  const std::int64_t steps = stepCount(scene, options);
  linx::World world = linx::buildWorld(scene);
  return {std::move(scene), std::move(world), steps};
}

int check(const RunOptions& options) {
  const Prepared p = prepare(options);
  const auto count = [](std::size_t n, const char* one, const char* many) {
    return fmt::format("{} {}", n, n == 1 ? one : many);
  };
  // Springs and loads only when the scene has them.
  std::string extra;
  if (!p.scene.springs.empty()) extra += ", " + count(p.scene.springs.size(), "spring", "springs");
  if (!p.scene.loads.empty()) extra += ", " + count(p.scene.loads.size(), "load", "loads");
  fmt::print("{}: ok: {}, {}{}, timestep {} s, duration {} s ({} steps), solver {}\n",
             options.scene, count(p.scene.bodies.size(), "body", "bodies"),
             count(p.scene.joints.size(), "joint", "joints"), extra, p.scene.settings.timestep,
             p.scene.duration, p.steps, linx::solverTypeName(p.scene.settings.solver.type));
  return 0;
}

struct ConvertOptions {
  std::string input;
  std::string output;
  bool floating_base = false;  // a URDF's root link is free
};

// Writes `text` to `path` through a temporary file in the same folder, renamed into place: the
// file is either complete or not there at all.
void writeAtomically(const std::filesystem::path& path, const std::string& text) {
  const std::filesystem::path folder = path.parent_path().empty() ? "." : path.parent_path();
  const std::filesystem::path temp =
      folder / fmt::format("{}.tmp-{}", path.filename().string(), getpid());
  try {
    std::ofstream out(temp, std::ios::binary | std::ios::trunc);
    if (!out) throw std::runtime_error(fmt::format("cannot write {}", temp.string()));
    out << text;
    out.close();
    if (!out) throw std::runtime_error(fmt::format("cannot write {}", temp.string()));
    std::filesystem::rename(temp, path);
  } catch (...) {
    std::error_code ec;
    std::filesystem::remove(temp, ec);
    throw;
  }
}

// Loads a scene or a robot and writes it as a JSON scene file.
int convert(const ConvertOptions& options) {
  std::error_code ec;
  if (std::filesystem::is_directory(options.output, ec))
    throw BadInput(fmt::format("{}: is a directory, expected a file to write", options.output));
  const linx::Scene scene =
      linx::loadModel(options.input, linx::ImportOptions{.floating_base = options.floating_base});
  for (const std::string& warning : scene.warnings)
    fmt::print(stderr, "linx: warning: {}\n", warning);
  writeAtomically(options.output, linx::writeSceneJson(scene));
  fmt::print("wrote {} ({} bodies, {} joints)\n", options.output, scene.bodies.size(),
             scene.joints.size());
  return 0;
}

int writeVtk(const std::string& dir);

// One line on stdout for each joint that broke since the last call.
void reportBreaks(const linx::World& world, std::size_t& reported,
                  linx::cli::ProgressBar& progress) {
  const auto breaks = world.jointBreaks();
  for (; reported < breaks.size(); ++reported) {
    const linx::JointBreak& b = breaks[reported];
    const linx::JointDef& def = world.joint(b.joint).def();
    const double force = b.reaction.force.norm(), torque = b.reaction.torque.norm();
    const bool by_force = force > def.break_force.value_or(linx::kInfinity);
    progress.clear();
    fmt::print("t = {:.9g} s: joint '{}' broke: {} (force {:.6g} N, torque {:.6g} N m)\n", b.time,
               def.name,
               by_force ? fmt::format("force above its break_force of {} N", *def.break_force)
                        : fmt::format("torque above its break_torque of {} N m", *def.break_torque),
               force, torque);
  }
}

// "output kept up to t = T in DIR": what a run that stopped early leaves.
std::string keptOutput(const RunOptions& options, double last_frame_time) {
  return fmt::format("output kept up to t = {} s in {}", last_frame_time, options.out);
}

int run(const RunOptions& options) {
  if (options.every < 1) {
    throw BadInput(fmt::format("--every: must be at least 1, got {}", options.every));
  }
  std::error_code ec;
  if (std::filesystem::exists(options.out, ec) && !std::filesystem::is_directory(options.out, ec)) {
    throw BadInput(fmt::format("--out: {}: exists and is not a directory", options.out));
  }
  Prepared p = prepare(options);
  linx::World& world = p.world;
  const linx::cli::StopSignals stop_signals;

  bool breakable = false;
  for (const linx::SceneJoint& j : p.scene.joints)
    breakable = breakable || j.def.break_force || j.def.break_torque;
  // Replaces an earlier run in the folder; every frame is on disk once recorded
  // (docs/reliability.md), so a run stopped at any point keeps what it recorded.
  linx::Recorder recorder(options.out,
                          linx::RecorderOptions{.contacts = options.contacts, .breaks = breakable});
  recorder.record(world);
  recorder.writeFile(std::string(linx::run_files::kScene.name),
                     linx::runSceneJson(p.scene, world, options.every));
  std::int64_t frames = 1, step = 0;
  double last_frame_time = world.time();
  std::size_t breaks_reported = 0;
  linx::cli::ProgressBar progress(isatty(fileno(stderr)) ? stderr : nullptr, p.steps,
                                  p.scene.duration);
  // A step that runs on for a second after SIGINT or SIGTERM (a huge dense solve) is not waited
  // for: the frames recorded are already whole on disk.
  linx::cli::StopWatchdog watchdog(std::chrono::seconds(1), [&] {
    fmt::print(stderr,
               "linx: {}: interrupted inside step {}, still running 1 s after the signal; {}\n",
               options.scene, step, keptOutput(options, last_frame_time));
    std::_Exit(kExitInterrupted);
  });
  const auto recordFrame = [&] {
    recorder.record(world);
    last_frame_time = world.time();
    ++frames;
  };
  for (step = 1; step <= p.steps; ++step) {
    try {
      const linx::cli::StopWatchdog::Busy busy(watchdog);
      world.step();
    } catch (const linx::StepFault& e) {  // a non-finite state or an energy blow-up
      progress.clear();
      recorder.finish();
      fmt::print(stderr, "linx: {}: {}; {}\n", options.scene, e.what(),
                 keptOutput(options, last_frame_time));
      return kExitNonFinite;
    }
    reportBreaks(world, breaks_reported, progress);
    if (step % options.every == 0 || step == p.steps || linx::cli::StopSignals::received())
      recordFrame();
    if (linx::cli::StopSignals::received()) {
      progress.clear();
      recorder.finish();
      fmt::print(stderr, "linx: {}: interrupted at step {} (t = {} s); {}\n", options.scene, step,
                 world.time(), keptOutput(options, last_frame_time));
      return kExitInterrupted;
    }
    progress.update(step, world.time());
  }
  progress.clear();
  recorder.finish();
  fmt::print("wrote {} files to {} ({} frames, {} steps, t = {} s)\n",
             4 + int{options.contacts} + int{breakable}, options.out, frames, p.steps,
             world.time());
  if (options.vtk) writeVtk(options.out);
  if (options.render) return linx::cli::render(linx::cli::RenderOptions{.dir = options.out});
  return 0;
}

int writeVtk(const std::string& dir) {
  const linx::viz::Run run = linx::viz::readRun(dir);
  const linx::viz::VtkSummary written = linx::viz::writeVtk(run, dir);
  fmt::print("wrote {} ({} frames in {})\n", written.collection.string(), written.frames,
             written.folder.string());
  return 0;
}

// CLI11 messages may span lines; errors here are one line.
std::string oneLine(std::string text) {
  std::replace(text.begin(), text.end(), '\n', ' ');
  while (!text.empty() && text.back() == ' ') text.pop_back();
  return text;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"linx: rigid multibody dynamics with a unified constraint solver", "linx"};
  app.set_version_flag("--version", "linx " LINX_VERSION);
  app.require_subcommand(1);
  app.footer(
      "Scene format and outputs: docs/scene-format.md.\n"
      "Exit status: 0 success, 1 output or internal failure, 2 bad input, 3 a fault (a non-finite\n"
      "state, or energy made by an unstable solve), 130 interrupted.");

  RunOptions options;
  double duration = 0, timestep = 0;
  CLI::App* run_cmd = app.add_subcommand("run", "Simulate a scene and write its trajectory as CSV");
  run_cmd
      ->add_option("scene", options.scene,
                   "Scene file (JSON), URDF robot (.urdf) or MuJoCo model (.xml)")
      ->required();
  run_cmd->add_option("-o,--out", options.out, "Output directory (created if needed)")->required();
  CLI::Option* duration_opt =
      run_cmd->add_option("--duration", duration, "Simulated time (s), overrides the scene's");
  CLI::Option* timestep_opt =
      run_cmd->add_option("--timestep", timestep, "Step length (s), overrides the scene's");
  int threads = 0;
  CLI::Option* threads_opt = run_cmd->add_option(
      "--threads", threads, "Worker threads (0: one per hardware thread), overrides the scene's");
  run_cmd->add_option("--every", options.every, "Record every N steps (and the last)")
      ->capture_default_str();
  run_cmd->add_flag("--contacts", options.contacts,
                    "Also write contacts.csv (every contact point of each recorded step)");
  run_cmd->add_flag(
      "--vtk", options.vtk,
      "Also write ParaView files: DIR/vtk/*.vtp per frame and the DIR/run.pvd series");
  run_cmd->add_flag("--render", options.render,
                    "Then render POV-Ray frames and a video, as linx render DIR does");
  CLI::App* check_cmd = app.add_subcommand("check", "Validate a scene and summarize it");
  check_cmd
      ->add_option("scene", options.scene,
                   "Scene file (JSON), URDF robot (.urdf) or MuJoCo model (.xml)")
      ->required();
  ConvertOptions convert_options;
  CLI::App* convert_cmd =
      app.add_subcommand("convert", "Write a scene or a URDF robot as a JSON scene file");
  convert_cmd
      ->add_option("input", convert_options.input,
                   "Scene file (JSON), URDF robot (.urdf) or MuJoCo model (.xml)")
      ->required();
  convert_cmd->add_option("output", convert_options.output, "Scene file to write (JSON)")
      ->required();
  for (auto [cmd, floating_base] :
       {std::pair{run_cmd, &options.floating_base}, std::pair{check_cmd, &options.floating_base},
        std::pair{convert_cmd, &convert_options.floating_base}})
    cmd->add_flag("--floating-base", *floating_base,
                  "URDF: the root link is a free body, not fixed to the world");

  linx::cli::RenderOptions render_options;
  CLI::App* render_cmd =
      app.add_subcommand("render", "Render a run's frames with POV-Ray (PNG, and MP4 or GIF)");
  linx::cli::addRenderOptions(*render_cmd, render_options);
  std::string vtk_dir;
  CLI::App* vtk_cmd = app.add_subcommand(
      "vtk", "Write a run's frames as ParaView files (DIR/vtk/*.vtp and DIR/run.pvd)");
  vtk_cmd->add_option("dir", vtk_dir, "Output folder of linx run")->required();
  linx::cli::PlotOptions plot_options;
  CLI::App* plot_cmd = app.add_subcommand(
      "plot", "Plot a run's energies, joint coordinates and errors, and solver residuals");
  linx::cli::addPlotOptions(*plot_cmd, plot_options);
  linx::cli::ViewOptions view_options;
  CLI::App* view_cmd =
      app.add_subcommand("view", "Serve a 3D viewer of a run on 127.0.0.1 for a browser");
  linx::cli::addViewOptions(*view_cmd, view_options);

  try {
    app.parse(argc, argv);
  } catch (const CLI::Success& e) {  // --help, --version
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    fmt::print(stderr, "linx: {} (see linx --help)\n", oneLine(e.what()));
    return kExitBadInput;
  }

  try {
    if (duration_opt->count()) options.duration = positiveFlag("--duration", duration);
    if (timestep_opt->count()) options.timestep = positiveFlag("--timestep", timestep);
    if (threads_opt->count()) {
      if (threads < 0 || threads > linx::kMaxThreads)
        throw BadInput(fmt::format("--threads: must be an integer in [0, {}], got {}",
                                   linx::kMaxThreads, threads));
      options.threads = threads;
    }
    if (*render_cmd) return linx::cli::render(render_options);
    if (*vtk_cmd) return writeVtk(vtk_dir);
    if (*plot_cmd) return linx::cli::plot(plot_options);
    if (*view_cmd) return linx::cli::view(view_options);
    if (*convert_cmd) {
      options.scene = convert_options.input;  // names the input in messages
      return convert(convert_options);
    }
    return *check_cmd ? check(options) : run(options);
  } catch (const linx::SceneError& e) {
    fmt::print(stderr, "linx: {}\n", e.what());
    return kExitBadInput;
  } catch (const linx::viz::RunError& e) {
    fmt::print(stderr, "linx: {}\n", e.what());
    return kExitBadInput;
  } catch (const BadInput& e) {
    fmt::print(stderr, "linx: {}\n", e.what());
    return kExitBadInput;
  } catch (const std::exception& e) {
    if (options.scene.empty())
      fmt::print(stderr, "linx: {}\n", oneLine(e.what()));
    else
      fmt::print(stderr, "linx: {}: {}\n", options.scene, oneLine(e.what()));
    return kExitFailure;
  }
}
