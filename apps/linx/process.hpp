// Running helper programs (povray, ffmpeg, gnuplot) for `linx render` and `linx plot`: finding
// them on PATH, starting them without a shell, waiting for them, and reading their logs.
#pragma once

#include <sys/types.h>

#include <chrono>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace linx::cli {

/// The executable `name` on PATH, or nothing. Checked before anything is started, so that a
/// missing program is told apart from one that fails.
std::optional<std::string> findProgram(const std::string& name);

/// Starts `program` (a path, as findProgram returns) with `args` in folder `cwd`, stdin from
/// /dev/null and stdout and stderr to `log` (truncated); no shell. Throws std::runtime_error when
/// the log cannot be written or the program cannot be started.
pid_t spawn(const std::string& program, const std::vector<std::string>& args,
            const std::filesystem::path& cwd, const std::filesystem::path& log);

/// Waits for child `pid` to end and returns its wait status, retrying when a signal interrupts
/// the wait. Throws std::runtime_error (naming `what`) when waitpid fails.
int waitFor(pid_t pid, const std::string& what);

/// Whether child `pid` has ended, without blocking; if so its wait status is in `status`. Throws
/// std::runtime_error (naming `what`) when waitpid fails.
bool hasEnded(pid_t pid, int& status, const std::string& what);

/// Stops children `pids`: SIGTERM, then SIGKILL to those still running after `grace`, and waits
/// for all of them, so that none is left running or unreaped. Does not throw.
void stopChildren(const std::vector<pid_t>& pids,
                  std::chrono::milliseconds grace = std::chrono::seconds(2));

/// Sleeps for `duration` (the polling step of the loops that wait for children and signals).
void sleepFor(std::chrono::milliseconds duration);

/// Whether a wait status is a normal exit with status 0.
bool succeeded(int status);

/// "exit status N" or "killed by signal N", for messages.
std::string describeStatus(int status);

/// The last `count` non-empty lines of a log file, joined with " | " (one line for a message), or
/// "(no output)".
std::string logTail(const std::filesystem::path& log, std::size_t count = 3);

}  // namespace linx::cli
