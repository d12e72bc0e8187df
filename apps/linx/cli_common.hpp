// What every `linx` subcommand shares: its exit statuses and the error for a bad flag value.
#pragma once

#include "io/quoting.hpp"

#include <fmt/format.h>

#include <cstdio>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <string_view>
#include <system_error>
#include <utility>

namespace linx::cli {

constexpr int kExitFailure = 1;
constexpr int kExitBadInput = 2;
constexpr int kExitNonFinite = 3;
constexpr int kExitInterrupted = 130;

/// A bad flag value or a bad input folder: reported like a scene error, exit status 2.
class BadInput : public std::runtime_error {
 public:
  explicit BadInput(const std::string& message) : std::runtime_error(io::visible(message)) {}
};

/// Prints a message, warning or summary line to `to`, as io::visible shows it: a name holding
/// terminal escapes or a path holding a NUL is shown, never acted on or cut. The final newline
/// of the format is kept; any other is shown as `\n`. Every line linx prints goes through here
/// (the progress bar's own control sequences aside).
template <typename... T>
void say(std::FILE* to, fmt::format_string<T...> format, T&&... args) {
  std::string text = fmt::format(format, std::forward<T>(args)...);
  const bool newline = !text.empty() && text.back() == '\n';
  if (newline) text.pop_back();
  std::fputs((io::visible(text) + (newline ? "\n" : "")).c_str(), to);
  std::fflush(to);
}

template <typename... T>
void say(fmt::format_string<T...> format, T&&... args) {
  say(stdout, format, std::forward<T>(args)...);
}

/// Refuses an output folder that cannot be one: an empty path, an existing file, or a path through
/// a file (`afile/sub`). `flag` names it in the message ("--out").
inline void checkOutputFolder(std::string_view flag, const std::filesystem::path& out) {
  namespace fs = std::filesystem;
  if (out.empty()) throw BadInput(fmt::format("{}: must not be empty", flag));
  std::error_code ec;
  for (fs::path p = out; !p.empty(); p = p.parent_path()) {
    if (fs::exists(p, ec) && !fs::is_directory(p, ec))
      throw BadInput(
          p == out
              ? fmt::format("{}: {}: exists and is not a directory", flag, out.string())
              : fmt::format("{}: {}: {} is a file, not a folder", flag, out.string(), p.string()));
    if (p == p.parent_path()) break;
  }
}

}  // namespace linx::cli
