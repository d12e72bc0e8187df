// The benchmark's table and its targets (issue 4), as text on stdout and as Markdown.
#pragma once

#include "runner.hpp"

#include <string>
#include <vector>

namespace bench {

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

}  // namespace bench
