// `linx plot DIR`: PNG and SVG plots of a recorded run by gnuplot (docs/visualization.md, "Plots"):
// energies, joint coordinates, joint errors and the solver's residual and iterations over time.
#pragma once

#include <CLI/CLI.hpp>

#include <string>

namespace linx::cli {

struct PlotOptions {
  std::string dir;
  std::string out;  ///< where the plots go; default DIR/plots
  int width = 900, height = 500;
};

/// Adds the plot flags to `cmd` (the `plot` subcommand).
void addPlotOptions(CLI::App& cmd, PlotOptions& options);
/// Plots the run in options.dir; returns the exit status. Throws BadInput or viz::RunError.
int plot(const PlotOptions& options);

}  // namespace linx::cli
