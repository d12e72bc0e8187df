// A progress bar for long runs of `linx run` (steps) and `linx render` (frames), drawn on one
// line of a terminal.
#pragma once

#include <chrono>
#include <cstdint>
#include <cstdio>
#include <string>

namespace linx::cli {

/// The bar's text after `done` of `total` steps, at simulated time `time` of `end` (s):
/// "[#############                 ]  45%  t = 2.25 / 5 s". `width` is the bar's number of cells.
std::string renderProgress(std::int64_t done, std::int64_t total, double time, double end,
                           int width = 30);

/// The bar's text after `done` of `total` items: "[#############                 ]  45%  frame
/// 9/20" (for `noun` "frame").
std::string renderCountProgress(std::int64_t done, std::int64_t total, const std::string& noun,
                                int width = 30);

/// Redraws the bar in place at most ten times a second, and always at the last step. Draws
/// nothing when `out` is null (use it only when the stream is a terminal).
class ProgressBar {
 public:
  ProgressBar(std::FILE* out, std::int64_t total, double end);
  /// A bar that counts items ("frame 9/20") instead of simulated time; update it with update(done).
  ProgressBar(std::FILE* out, std::int64_t total, std::string noun);
  ~ProgressBar() { clear(); }
  ProgressBar(const ProgressBar&) = delete;
  ProgressBar& operator=(const ProgressBar&) = delete;

  void update(std::int64_t done, double time);
  void update(std::int64_t done) { update(done, 0.0); }
  /// Erases the bar, e.g. before a message is printed.
  void clear();

 private:
  std::FILE* out_;
  std::int64_t total_;
  double end_ = 0;
  std::string noun_;  // counts items when set
  std::chrono::steady_clock::time_point last_draw_;
  bool drawn_ = false;
};

}  // namespace linx::cli
