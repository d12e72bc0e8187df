// The benchmark's table and its targets (issue 4), as text on stdout and as Markdown.
#pragma once

#include "runner.hpp"

#include <functional>
#include <string>
#include <vector>

namespace bench {

/// A table, fixed-width (columns padded, `right` ones aligned right) or Markdown.
std::string render(const std::vector<std::string>& head,
                   const std::vector<std::vector<std::string>>& rows,
                   const std::function<bool(std::size_t)>& right, bool markdown);

/// Machine, compiler and date, one line each.
std::vector<std::string> machineDescription();

/// The table, fixed-width (markdown = false) or as a Markdown table.
std::string table(const std::vector<Result>& results, bool markdown);

/// The Pareto table (linx-bench --pareto): per scene, its rows by median time, each with its swept
/// count (Result::knob), its mean time too (the median of a run that sleeps more than half its
/// steps is a sleeping step's) and a mark for the Pareto front: the rows that ran every step to a
/// finite accuracy figure and that no other such row matches in both median time and accuracy
/// while beating it in one (accuracy figures below 1e-9 m count as equal).
std::string paretoTable(const std::vector<Result>& results, bool markdown);

struct Target {
  bool met = false;
  bool measured = true;  ///< false: not measured in this run (the line says why)
  std::string text;
};
/// Each of the targets that this run's results can decide.
std::vector<Target> targets(const std::vector<Result>& results);
std::string targetLines(const std::vector<Target>& targets, bool markdown);

/// The integrator table (linx-bench --integrators): per mechanism, each row's time per step and
/// over the run, its distance from the known path, its energy drift and its joints' separation.
std::string integratorTable(const std::vector<Result>& results, bool markdown);
/// Issue 19's speed target on each mechanism: at equal accuracy, linx's accurate integrator
/// (its default row) faster than MuJoCo's RK4 and than Simbody's RK Merson (the error-controlled
/// integrator of its examples; its CPodes rows are shown, not judged).
std::vector<Target> integratorTargets(const std::vector<Result>& results);

}  // namespace bench
