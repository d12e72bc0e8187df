// What every `linx` subcommand shares: its exit statuses and the error for a bad flag value.
#pragma once

#include <fmt/format.h>

#include <filesystem>
#include <stdexcept>
#include <string_view>
#include <system_error>

namespace linx::cli {

constexpr int kExitFailure = 1;
constexpr int kExitBadInput = 2;
constexpr int kExitNonFinite = 3;
constexpr int kExitInterrupted = 130;

/// A bad flag value or a bad input folder: reported like a scene error, exit status 2.
class BadInput : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

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
