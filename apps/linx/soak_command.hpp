// `linx soak SCENE... [--steps N] [--report-every N]` (docs/reliability.md, "Soak"): steps each
// scene a long time (a million steps by default, sleep off so that every step does its work) and
// reports the memory in use at intervals, the growth after warm-up, and any fault.
#pragma once

#include <CLI/CLI.hpp>

#include <cstdint>
#include <string>
#include <vector>

namespace linx::cli {

struct SoakOptions {
  std::vector<std::string> scenes;
  std::int64_t steps = 1'000'000;
  std::int64_t report_every = 100'000;
  double max_growth = 0.05;  ///< heap growth after warm-up (fraction) above which the soak fails
};

void addSoakOptions(CLI::App& cmd, SoakOptions& options);
/// 0 when every scene stepped to the end with its memory flat; 3 on a fault; 1 when the memory
/// grew past max_growth after warm-up.
int soak(const SoakOptions& options);

}  // namespace linx::cli
