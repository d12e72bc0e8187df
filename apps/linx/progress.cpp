// The progress bar of `linx run` (see progress.hpp).
#include "progress.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <utility>

namespace linx::cli {

namespace {

std::string bar(std::int64_t done, std::int64_t total, int width) {
  const double fraction =
      total > 0 ? std::clamp(static_cast<double>(done) / static_cast<double>(total), 0.0, 1.0)
                : 1.0;
  const int filled = static_cast<int>(fraction * width);
  return fmt::format("[{}{}] {:3d}%", std::string(filled, '#'), std::string(width - filled, ' '),
                     static_cast<int>(fraction * 100));
}

}  // namespace

std::string renderCountProgress(std::int64_t done, std::int64_t total, const std::string& noun,
                                int width) {
  return fmt::format("{}  {} {}/{}", bar(done, total, width), noun, done, total);
}

std::string renderProgress(std::int64_t done, std::int64_t total, double time, double end,
                           int width) {
  return fmt::format("{}  t = {:.6g} / {:.6g} s", bar(done, total, width), time, end);
}

ProgressBar::ProgressBar(std::FILE* out, std::int64_t total, double end)
    : out_(out), total_(total), end_(end) {}

ProgressBar::ProgressBar(std::FILE* out, std::int64_t total, std::string noun)
    : out_(out), total_(total), noun_(std::move(noun)) {}

void ProgressBar::update(std::int64_t done, double time) {
  if (!out_) return;
  const auto now = std::chrono::steady_clock::now();
  if (drawn_ && done < total_ && now - last_draw_ < std::chrono::milliseconds(100)) return;
  // Carriage return and "erase to end of line" redraw the bar in place.
  fmt::print(out_, "\r\033[K{}",
             noun_.empty() ? renderProgress(done, total_, time, end_)
                           : renderCountProgress(done, total_, noun_));
  std::fflush(out_);
  last_draw_ = now;
  drawn_ = true;
}

void ProgressBar::clear() {
  if (!out_ || !drawn_) return;
  std::fputs("\r\033[K", out_);  // no exceptions: also called from the destructor
  std::fflush(out_);
  drawn_ = false;
}

}  // namespace linx::cli
