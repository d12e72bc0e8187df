// `linx render DIR`: POV-Ray frames of a recorded run (docs/visualization.md).
#pragma once

#include <CLI/CLI.hpp>

#include <string>

namespace linx::cli {

/// Every field has the default of `linx render DIR` without flags (`linx run --render` uses them).
struct RenderOptions {
  std::string dir;
  int width = 800, height = 600;  ///< pixels, in [16, 8192]
  double fps = 30;                ///< pictures per second of simulated time, in (0, 1000]
  std::string frame{};            ///< "": every picked frame and a video; a time (s) or "last"
  int jobs = 0;                   ///< povray processes at once; 0: two per hardware thread
  std::string video{};            ///< "mp4", "gif", "none"; "": mp4 when ffmpeg is found
  std::string antialias = "on";   ///< "on" or "off"
};

/// Adds the render flags to `cmd` (the `render` subcommand).
void addRenderOptions(CLI::App& cmd, RenderOptions& options);
/// Renders the run in options.dir; returns the exit status. Throws BadInput or viz::RunError.
int render(const RenderOptions& options);

}  // namespace linx::cli
