// The `linx` command line (docs/scene-format.md, "Command line"; docs/visualization.md):
//   linx run SCENE.json --out DIR [--duration T] [--timestep H] [--threads N] [--every N]
//            [--checkpoint-every T] [--on-fault stop|continue] [--contacts] [--vtk] [--render]
//   linx resume DIR|CHECKPOINT [--on-fault stop|continue]   linx soak SCENE... [--steps N]
//   (docs/reliability.md) linx check SCENE.json   (SCENE may be ROBOT.urdf [--floating-base] or
//   MODEL.xml, MJCF) linx convert SCENE.json|ROBOT.urdf OUT.json [--floating-base] linx render DIR
//   ...   linx vtk DIR   linx plot DIR ...   linx view DIR ...
// Every input is validated before anything is written. Errors are one line on stderr,
// "linx: FILE: FIELD: PROBLEM". Exit status: 0 success, 1 output or internal failure, 2 bad input
// (scene, flags, usage), 3 the run stopped on a fault (a non-finite state, a bound passed, energy
// made by an unstable solve), 130 interrupted.
#include "cli_common.hpp"
#include "io/output_file.hpp"
#include "io/suggestion.hpp"
#include "plot_command.hpp"
#include "progress.hpp"
#include "render_command.hpp"
#include "run_command.hpp"
#include "schema_command.hpp"
#include "soak_command.hpp"
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
using linx::cli::RunOptions;
using linx::cli::say;

double positiveFlag(const char* flag, double value) {
  if (!(std::isfinite(value) && value > 0))
    throw BadInput(fmt::format("{}: must be a finite number > 0, got {}", flag, value));
  return value;
}

struct ConvertOptions {
  std::string input;
  std::string output;
  bool floating_base = false;  // a URDF's root link is free
  bool allow_outside_paths = false;
};

// Loads a scene or a robot and writes it as a JSON scene file.
int convert(const ConvertOptions& options) {
  std::error_code ec;
  if (std::filesystem::is_directory(options.output, ec))
    throw BadInput(fmt::format("{}: is a directory, expected a file to write", options.output));
  // A device or a pipe is no file to replace: renaming over /dev/null as root would make it one.
  if (const auto status = std::filesystem::symlink_status(options.output, ec);
      !ec && std::filesystem::exists(status) && !std::filesystem::is_regular_file(status) &&
      !std::filesystem::is_symlink(status))
    throw BadInput(fmt::format(
        "{}: not a regular file (a device, a pipe or a socket), expected a file to write",
        options.output));
  linx::Scene scene;
  linx::cli::whileLoading(options.input, [&] {
    scene = linx::loadModel(
        options.input, linx::ImportOptions{.floating_base = options.floating_base,
                                           .allow_outside_paths = options.allow_outside_paths});
  });
  for (const std::string& warning : scene.warnings) say(stderr, "linx: warning: {}\n", warning);
  linx::io::writeFileAtomically(options.output, linx::writeSceneJson(scene));
  say("wrote {} ({} bodies, {} joints)\n", options.output, scene.bodies.size(),
      scene.joints.size());
  return 0;
}

// CLI11 messages may span lines; errors here are one line.
std::string oneLine(std::string text) {
  std::replace(text.begin(), text.end(), '\n', ' ');
  while (!text.empty() && text.back() == ' ') text.pop_back();
  return text;
}

// The subcommand given ("run"), or the app itself.
const CLI::App& givenCommand(const CLI::App& app) {
  const std::vector<CLI::App*> given = app.get_subcommands();
  return given.empty() ? app : *given.front();
}

// "linx run" or "linx".
std::string commandName(const CLI::App& app, const CLI::App& command) {
  return &command == &app ? "linx" : "linx " + command.get_name();
}

// An argument no option took: the first of them, the command's closest flag to it if it is a
// misspelt flag, and where to look.
std::string unexpectedArguments(const CLI::App& app, const CLI::ExtrasError& e) {
  const CLI::App& command = givenCommand(app);
  std::vector<std::string> extras = command.remaining();
  if (extras.empty()) extras = app.remaining();
  const std::string name = commandName(app, command);
  if (extras.empty()) return fmt::format("{} (see {} --help)", oneLine(e.what()), name);
  const std::string& first = extras.front();
  if (!first.starts_with("-"))
    return fmt::format("'{}': an argument {} does not take (see {} --help)", first, name, name);
  std::vector<std::string> flags;
  for (const CLI::Option* option : command.get_options())
    for (const std::string& long_name : option->get_lnames()) flags.push_back("--" + long_name);
  const std::string_view flag = std::string_view(first).substr(0, first.find('='));
  const std::string_view closest = linx::io::closestName(flag, flags);
  return fmt::format("{}: not a flag of {}{} (see {} --help)", flag, name,
                     closest.empty() ? "" : fmt::format("; did you mean {}?", closest), name);
}

// "Could not convert: --every = 1.5" as "--every: '1.5' is not a value it takes".
std::string unconvertible(const CLI::App& app, const CLI::ConversionError& e) {
  const std::string name = commandName(app, givenCommand(app));
  const std::string text = oneLine(e.what());
  constexpr std::string_view kPrefix = "Could not convert: ";
  const auto equals = text.find(" = ");
  if (!text.starts_with(kPrefix) || equals == std::string::npos)
    return fmt::format("{} (see {} --help)", text, name);
  return fmt::format("{}: '{}' is not a value it takes (see {} --help)",
                     text.substr(kPrefix.size(), equals - kPrefix.size()), text.substr(equals + 3),
                     name);
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"linx: rigid multibody dynamics with a unified constraint solver", "linx"};
  app.set_version_flag("--version", "linx " LINX_VERSION);
  app.require_subcommand(1);
  app.footer(
      "Scene format and outputs: docs/scene-format.md.\n"
      "Exit status: 0 success, 1 output or internal failure, 2 bad input, 3 a fault (a non-finite\n"
      "state, a speed or joint error bound passed, or energy made by an unstable solve), 130\n"
      "interrupted (docs/reliability.md).");

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
  double checkpoint_every = 0;
  CLI::Option* checkpoint_opt = run_cmd->add_option(
      "--checkpoint-every", checkpoint_every,
      "Write a checkpoint every T seconds of simulated time (DIR/checkpoints/), to resume from");
  std::string on_fault = "stop";
  run_cmd
      ->add_option("--on-fault", on_fault,
                   "stop: a fault ends the run (exit 3); continue: warn and go on (a non-finite "
                   "state always stops)")
      ->check(CLI::IsMember({"stop", "continue"}))
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
  for (auto [cmd, allow] : {std::pair{run_cmd, &options.allow_outside_paths},
                            std::pair{check_cmd, &options.allow_outside_paths},
                            std::pair{convert_cmd, &convert_options.allow_outside_paths}})
    cmd->add_flag("--allow-outside-paths", *allow,
                  "Read files the scene names (meshes, tables, includes) outside its folder too");

  std::string resume_from;
  CLI::App* resume_cmd = app.add_subcommand(
      "resume", "Go on with a run from its newest checkpoint (or the one given)");
  resume_cmd
      ->add_option("checkpoint", resume_from,
                   "Run folder (its newest checkpoint) or checkpoint file (DIR/checkpoints/*.lxc)")
      ->required();
  std::string resume_on_fault;
  resume_cmd
      ->add_option("--on-fault", resume_on_fault,
                   "stop or continue, as for run (default: as the run was started)")
      ->check(CLI::IsMember({"stop", "continue"}));

  linx::cli::SoakOptions soak_options;
  CLI::App* soak_cmd = app.add_subcommand(
      "soak", "Step scenes a long time (a million steps) and report their memory and faults");
  linx::cli::addSoakOptions(*soak_cmd, soak_options);

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
  linx::cli::SchemaOptions schema_options;
  CLI::App* schema_cmd = app.add_subcommand(
      "schema", "Print the scene format's fields: types, bounds, defaults and meanings");
  linx::cli::addSchemaOptions(*schema_cmd, schema_options);
  linx::cli::ViewOptions view_options;
  CLI::App* view_cmd =
      app.add_subcommand("view", "Serve a 3D viewer of a run on 127.0.0.1 for a browser");
  linx::cli::addViewOptions(*view_cmd, view_options);

  try {
    app.parse(argc, argv);
  } catch (const CLI::Success& e) {  // --help, --version
    return app.exit(e);
  } catch (const CLI::ExtrasError& e) {
    say(stderr, "linx: {}\n", unexpectedArguments(app, e));
    return kExitBadInput;
  } catch (const CLI::ConversionError& e) {
    say(stderr, "linx: {}\n", unconvertible(app, e));
    return kExitBadInput;
  } catch (const CLI::ParseError& e) {
    if (app.get_subcommands().empty() && argc > 1 && argv[1][0] != '-') {
      std::vector<std::string> commands;
      for (const CLI::App* command : app.get_subcommands({}))
        commands.push_back(command->get_name());
      const std::string_view closest = linx::io::closestName(argv[1], commands);
      say(stderr, "linx: '{}': not a command of linx{} (see linx --help)\n", argv[1],
          closest.empty() ? "" : fmt::format("; did you mean {}?", closest));
      return kExitBadInput;
    }
    say(stderr, "linx: {} (see linx --help)\n", oneLine(e.what()));
    return kExitBadInput;
  }

  try {
    if (duration_opt->count()) options.duration = positiveFlag("--duration", duration);
    if (timestep_opt->count()) options.timestep = positiveFlag("--timestep", timestep);
    if (checkpoint_opt->count())
      options.checkpoint_every = positiveFlag("--checkpoint-every", checkpoint_every);
    options.keep_going = on_fault == "continue";
    if (threads_opt->count()) {
      if (threads < 0 || threads > linx::kMaxThreads)
        throw BadInput(fmt::format("--threads: must be an integer in [0, {}], got {}",
                                   linx::kMaxThreads, threads));
      options.threads = threads;
    }
    if (*render_cmd) return linx::cli::render(render_options);
    if (*vtk_cmd) return linx::cli::writeVtk(vtk_dir);
    if (*soak_cmd) return linx::cli::soak(soak_options);
    if (*resume_cmd) {
      options.scene = resume_from;  // names the checkpoint in messages
      return linx::cli::resume(resume_from,
                               resume_on_fault.empty()
                                   ? std::nullopt
                                   : std::optional<bool>(resume_on_fault == "continue"));
    }
    if (*plot_cmd) return linx::cli::plot(plot_options);
    if (*view_cmd) return linx::cli::view(view_options);
    if (*schema_cmd) return linx::cli::schema(schema_options);
    if (*convert_cmd) {
      options.scene = convert_options.input;  // names the input in messages
      return convert(convert_options);
    }
    return *check_cmd ? linx::cli::check(options) : linx::cli::run(options);
  } catch (const linx::SceneError& e) {
    say(stderr, "linx: {}\n", e.what());
    return kExitBadInput;
  } catch (const linx::CheckpointError& e) {
    say(stderr, "linx: {}\n", e.what());
    return kExitBadInput;
  } catch (const linx::viz::RunError& e) {
    say(stderr, "linx: {}\n", e.what());
    return kExitBadInput;
  } catch (const BadInput& e) {
    say(stderr, "linx: {}\n", e.what());
    return kExitBadInput;
  } catch (const std::exception& e) {
    if (options.scene.empty())
      say(stderr, "linx: {}\n", oneLine(e.what()));
    else
      say(stderr, "linx: {}: {}\n", options.scene, oneLine(e.what()));
    return kExitFailure;
  }
}
