// `linx view DIR`: the browser viewer of a recorded run (docs/visualization.md). Serves the
// viewer page (viewer/, bundled at build time and compiled into linx) and the run's files on
// 127.0.0.1 until Ctrl-C or SIGTERM.
#pragma once

#include <CLI/CLI.hpp>

#include <string>

namespace linx::cli {

struct ViewOptions {
  std::string dir;
  int port = 0;  ///< 0: any free port
};

/// Adds the view flags to `cmd` (the `view` subcommand).
void addViewOptions(CLI::App& cmd, ViewOptions& options);
/// Serves the viewer of the run in options.dir until interrupted (Ctrl-C or SIGTERM), then
/// returns 0. Throws BadInput (bad --port, port taken) or viz::RunError (bad folder).
int view(const ViewOptions& options);

}  // namespace linx::cli
