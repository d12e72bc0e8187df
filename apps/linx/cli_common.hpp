// What every `linx` subcommand shares: its exit statuses and the error for a bad flag value.
#pragma once

#include <stdexcept>

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

}  // namespace linx::cli
