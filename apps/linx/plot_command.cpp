// The plots are drawn by gnuplot (Debian's gnuplot-nox): this file only writes the data into a
// gnuplot script, DIR/plots/plots.gp, with the run's numbers as inline data blocks, and runs it.
// The script stays next to the pictures, so that a user can restyle a plot and run it again.
#include "plot_command.hpp"

#include "cli_common.hpp"
#include "io/output_file.hpp"
#include "io/quoting.hpp"
#include "process.hpp"
#include "viz/run.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <optional>
#include <stdexcept>
#include <string>
#include <system_error>
#include <utility>
#include <vector>

namespace linx::cli {

namespace fs = std::filesystem;

namespace {

// More joints than this are drawn without a legend (a chain's hundred hinges).
constexpr std::size_t kMaxLegend = 12;

// Every text in the script (titles, labels, file names, the folder in the comment line) is a
// gnuplot string literal written by io::gnuplotString, in which gnuplot substitutes nothing.
std::string quoted(const std::string& text) {
  return io::gnuplotString(text);
}

// gnuplot's titles treat _ and ^ as sub- and superscripts under the enhanced text mode; the
// script turns it off, so names are shown as they are.
struct Plot {
  std::string name;      // file stem
  std::string data;      // its data block, written once at the top of the script
  std::string commands;  // drawn once per terminal, after `set output`

  // From the text a *Plot function makes: a data block up to its EOD line, then the commands.
  Plot(std::string stem, const std::string& text) : name(std::move(stem)) {
    const std::size_t end = text.find("\nEOD\n") + 5;
    data = text.substr(0, end);
    commands = text.substr(end);
  }
};

std::string header(const PlotOptions& o, const std::string& file, const std::string& terminal) {
  return fmt::format(
      "reset\nset datafile missing \"NaN\"\n"
      "set terminal {} size {},{} noenhanced font \"DejaVu Sans,11\"\nset output {}\n",
      terminal, o.width, o.height, quoted(file));
}

std::string energyPlot(const viz::Run& run) {
  std::string s = "$energy << EOD\n";
  for (const viz::Frame& f : run.frames) {
    s += fmt::format("{} {} {} {}\n", f.time, f.kinetic_energy, f.potential_energy,
                     f.kinetic_energy + f.potential_energy);
  }
  s += "EOD\n";
  s += "set title \"Energy\"\nset xlabel \"time (s)\"\nset ylabel \"energy (J)\"\n"
       "set key outside right top\nset grid\n"
       "plot $energy using 1:2 with lines lw 2 title \"kinetic\", "
       "$energy using 1:3 with lines lw 2 title \"potential\", "
       "$energy using 1:4 with lines lw 2 dt 2 title \"total\"\n";
  return s;
}

// How a plot of values that should be positive (errors, residuals) is scaled. A log scale shows
// them best, but zeros have no logarithm: when no value is positive (a run without constraint
// error, or whose solver always converged exactly), a log plot would have no point at all and
// gnuplot would fail, so the plot is drawn on a linear scale instead, with a note in its title.
// Every plot is still drawn, so the set of pictures depends only on the run's joints and frames.
struct Scale {
  bool log = true;
  std::string note;      // appended to the title
  std::string commands;  // gnuplot commands that set the y axis up
};

Scale positiveScale(const std::vector<double>& values, const std::string& ylabel) {
  bool positive = false, nonzero = false;
  for (double v : values) {
    if (!std::isfinite(v)) continue;
    positive = positive || v > 0;
    nonzero = nonzero || v != 0;
  }
  Scale scale;
  scale.commands = fmt::format("set ylabel {}\n", quoted(ylabel));
  if (positive) {
    scale.commands += "set logscale y\nset format y \"%.0e\"\n";
    return scale;
  }
  scale.log = false;
  // Only zeros (or nothing finite): a fixed range, as gnuplot cannot autoscale an empty plot.
  scale.note = nonzero ? "; none positive, linear scale" : "; all zero, linear scale";
  if (!nonzero) scale.commands += "set yrange [-1:1]\n";
  return scale;
}

// One data block per joint column: time, then one column per joint (NaN where a joint has none).
std::string jointPlot(const viz::Run& run, bool errors) {
  std::vector<std::size_t> joints;
  for (std::size_t j = 0; j < run.joints.size(); ++j) {
    if (errors || !std::isnan(run.frames.front().joint_coordinate[j])) joints.push_back(j);
  }
  if (joints.empty()) return {};
  const char* block = errors ? "$errors" : "$coordinates";
  std::string s = fmt::format("{} << EOD\n", block);
  for (const viz::Frame& f : run.frames) {
    s += fmt::format("{}", f.time);
    for (std::size_t j : joints) {
      const double v = errors ? f.joint_error[j] : f.joint_coordinate[j];
      s += std::isfinite(v) ? fmt::format(" {}", v) : std::string(" NaN");
    }
    s += "\n";
  }
  s += "EOD\n";
  const bool legend = joints.size() <= kMaxLegend;
  Scale scale{false, "", "set ylabel \"coordinate (rad or m)\"\n"};
  if (errors) {
    std::vector<double> values;
    for (const viz::Frame& f : run.frames) {
      for (std::size_t j : joints) values.push_back(f.joint_error[j]);
    }
    scale = positiveScale(values, "position error (m or rad)");
  }
  s += fmt::format(
      "set title {}\nset xlabel \"time (s)\"\nset grid\n",
      quoted(fmt::format("{} ({} joints{}{})", errors ? "Joint errors" : "Joint coordinates",
                         joints.size(), legend ? "" : ", legend omitted", scale.note)));
  s += scale.commands;
  s += legend ? "set key outside right top\n" : "unset key\n";
  s += "plot ";
  for (std::size_t k = 0; k < joints.size(); ++k) {
    const viz::RunJoint& joint = run.joints[joints[k]];
    // Zero errors have no logarithm: they are left out of the log plot.
    const std::string column =
        scale.log ? fmt::format("(${0} > 0 ? ${0} : NaN)", k + 2) : fmt::format("{}", k + 2);
    s += fmt::format("{}{} using 1:{} with lines lw 2 title {}", k ? ", " : "", block, column,
                     quoted(fmt::format("{} ({})", joint.name, joint.type)));
  }
  s += "\n";
  if (scale.log) s += "unset logscale y\nset format y \"%g\"\n";
  return s;
}

std::string solverPlot(const viz::Run& run) {
  int most = 1;
  for (const viz::Frame& f : run.frames) most = std::max(most, f.solver_iterations);
  // The first frame is the initial state: no solve yet.
  std::vector<double> residuals;
  for (std::size_t i = 1; i < run.frames.size(); ++i) residuals.push_back(run.frames[i].residual);
  const Scale scale = positiveScale(residuals, "residual (m/s)");
  std::string s = "$solver << EOD\n";
  for (std::size_t i = 1; i < run.frames.size(); ++i) {
    const viz::Frame& f = run.frames[i];
    // On the log scale, zeros are left out (NaN), as they have no logarithm.
    const bool shown = std::isfinite(f.residual) && (f.residual > 0 || !scale.log);
    s += fmt::format("{} {} {}\n", f.time, shown ? fmt::format("{}", f.residual) : "NaN",
                     f.solver_iterations);
  }
  s += "EOD\n";
  s += fmt::format("set title {}\nset xlabel \"time (s)\"\nset grid\n",
                   quoted(fmt::format("Solver (last step of each frame{})", scale.note)));
  s += scale.commands;
  s += "set y2label \"iterations\"\nset y2tics\nset ytics nomirror\n"
       "set key outside right top\n";
  s += fmt::format("set y2range [0:{}]\n", most + most / 4 + 1);
  s += "plot $solver using 1:2 with lines lw 2 title \"residual\", "
       "$solver using 1:3 axes x1y2 with steps lw 1 title \"iterations\"\n"
       "unset logscale y\nset format y \"%g\"\nunset y2tics\nunset y2label\nset ytics mirror\n";
  return s;
}

}  // namespace

void addPlotOptions(CLI::App& cmd, PlotOptions& options) {
  cmd.add_option("dir", options.dir, "Output folder of linx run")->required();
  cmd.add_option("-o,--out", options.out, "Folder for the plots (default: DIR/plots)");
  cmd.add_option("--width", options.width, "Picture width (pixels)")->capture_default_str();
  cmd.add_option("--height", options.height, "Picture height (pixels)")->capture_default_str();
}

int plot(const PlotOptions& options) {
  for (const auto& [flag, value] :
       {std::pair{"--width", options.width}, {"--height", options.height}}) {
    if (value < 100 || value > 10000)
      throw BadInput(fmt::format("{}: must be an integer in [100, 10000], got {}", flag, value));
  }
  const viz::Run run = viz::openRun(options.dir);
  const fs::path out =
      options.out.empty() ? fs::path(options.dir) / "plots" : fs::path(options.out);
  checkOutputFolder("--out", out);
  std::error_code ec;
  fs::create_directories(out, ec);
  if (ec) throw std::runtime_error(fmt::format("cannot create {}: {}", out.string(), ec.message()));

  std::vector<Plot> plots;
  plots.emplace_back("energy", energyPlot(run));
  if (std::string s = jointPlot(run, false); !s.empty()) plots.emplace_back("joint_coordinates", s);
  if (!run.joints.empty()) plots.emplace_back("joint_errors", jointPlot(run, true));
  if (run.frames.size() > 1) plots.emplace_back("solver", solverPlot(run));

  // One script draws every plot twice (PNG, SVG). Pictures are drawn under temporary names and
  // renamed once gnuplot has succeeded, so a failure never leaves half a picture.
  std::string script = fmt::format(
      "# linx plot {}: rerun with `gnuplot plots.gp` in this folder\n"
      "set datafile missing \"NaN\"\n",
      quoted(options.dir));
  for (const Plot& p : plots) script += p.data;  // `reset` below keeps data blocks
  std::vector<std::string> pictures;
  for (const Plot& p : plots) {
    for (const auto& [ext, terminal] :
         {std::pair{"png", "pngcairo"}, std::pair{"svg", "svg dynamic background rgb \"white\""}}) {
      const std::string file = fmt::format("{}.{}", p.name, ext);
      pictures.push_back(file);
      script +=
          header(options, fmt::format(".{}.tmp", file), terminal) + p.commands + "unset output\n";
    }
  }
  const fs::path script_path = out / "plots.gp";
  io::writeFileAtomically(script_path, script);

  // Looked for up front, so that a missing gnuplot is told apart from one that fails.
  const std::optional<std::string> gnuplot = findProgram("gnuplot");
  if (!gnuplot)
    throw std::runtime_error(
        "plot: gnuplot not found on PATH (install it with scripts/install-deps.sh: Debian's "
        "gnuplot-nox)");
  const fs::path log = out / ".gnuplot.log";
  const auto removeTemporaries = [&] {
    fs::remove(log, ec);
    for (const std::string& file : pictures) fs::remove(out / fmt::format(".{}.tmp", file), ec);
  };
  int status = 0;
  try {
    status = waitFor(spawn(*gnuplot, {"plots.gp"}, out, log), "gnuplot");
  } catch (...) {
    removeTemporaries();
    throw;
  }
  if (!succeeded(status)) {
    // The message carries the end of gnuplot's output; the whole of it comes again with
    // `gnuplot plots.gp` in the folder, so the log is not kept.
    const std::string tail = logTail(log);
    removeTemporaries();
    throw std::runtime_error(fmt::format("gnuplot failed ({}) on {}: {}", describeStatus(status),
                                         script_path.string(), tail));
  }
  fs::remove(log, ec);
  for (const std::string& file : pictures) {
    fs::rename(out / fmt::format(".{}.tmp", file), out / file, ec);
    if (ec)
      throw std::runtime_error(
          fmt::format("cannot rename to {}: {}", (out / file).string(), ec.message()));
  }
  std::string names;
  for (const Plot& p : plots) names += (names.empty() ? "" : ", ") + p.name;
  say("wrote {} plots to {} (PNG and SVG): {}\n", plots.size(), out.string(), names);
  return 0;
}

}  // namespace linx::cli
