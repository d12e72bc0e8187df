#include "process.hpp"

#include <fcntl.h>
#include <fmt/format.h>
#include <spawn.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <csignal>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <deque>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <system_error>

extern char** environ;

namespace linx::cli {

namespace fs = std::filesystem;

namespace {

// A file descriptor closed when it goes out of scope.
class Fd {
 public:
  explicit Fd(int fd) : fd_(fd) {}
  ~Fd() {
    if (fd_ >= 0) ::close(fd_);
  }
  Fd(const Fd&) = delete;
  Fd& operator=(const Fd&) = delete;
  int get() const { return fd_; }

 private:
  int fd_;
};

// posix_spawn's file actions, destroyed when they go out of scope.
class FileActions {
 public:
  FileActions() { posix_spawn_file_actions_init(&actions_); }
  ~FileActions() { posix_spawn_file_actions_destroy(&actions_); }
  FileActions(const FileActions&) = delete;
  FileActions& operator=(const FileActions&) = delete;
  posix_spawn_file_actions_t* get() { return &actions_; }

 private:
  posix_spawn_file_actions_t actions_{};
};

}  // namespace

std::optional<std::string> findProgram(const std::string& name) {
  const char* path = std::getenv("PATH");
  std::stringstream dirs(path ? path : "/usr/local/bin:/usr/bin:/bin");
  for (std::string dir; std::getline(dirs, dir, ':');) {
    // An empty entry is the current folder. (Built with fmt rather than assigned and +: GCC 12
    // warns falsely, -Wrestrict, on those inlined string copies.)
    const std::string candidate = fmt::format("{}/{}", dir.empty() ? "." : dir, name);
    struct stat st {};
    if (::stat(candidate.c_str(), &st) == 0 && S_ISREG(st.st_mode) &&
        ::access(candidate.c_str(), X_OK) == 0)
      return candidate;
  }
  return std::nullopt;
}

pid_t spawn(const std::string& program, const std::vector<std::string>& args, const fs::path& cwd,
            const fs::path& log) {
  std::vector<std::string> all{program};
  all.insert(all.end(), args.begin(), args.end());
  std::vector<char*> argv;
  for (std::string& a : all) argv.push_back(a.data());
  argv.push_back(nullptr);
  // The log is opened here rather than by a file action, so that its error names the file.
  const Fd out(::open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644));
  if (out.get() < 0)
    throw std::runtime_error(
        fmt::format("{}: cannot write: {}", log.string(), std::strerror(errno)));
  // posix_spawn (not fork) reports a program that cannot be executed as an error here, instead
  // of as an exit status of a child that only wrote a note to the log.
  FileActions actions;
  posix_spawn_file_actions_addopen(actions.get(), STDIN_FILENO, "/dev/null", O_RDONLY, 0);
  posix_spawn_file_actions_adddup2(actions.get(), out.get(), STDOUT_FILENO);
  posix_spawn_file_actions_adddup2(actions.get(), out.get(), STDERR_FILENO);
  posix_spawn_file_actions_addchdir_np(actions.get(), cwd.c_str());
  pid_t pid = 0;
  const int error =
      posix_spawn(&pid, program.c_str(), actions.get(), nullptr, argv.data(), environ);
  if (error != 0)
    throw std::runtime_error(fmt::format("cannot start {}: {}", program, std::strerror(error)));
  return pid;
}

int waitFor(pid_t pid, const std::string& what) {
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0) {
    if (errno != EINTR)
      throw std::runtime_error(fmt::format("waiting for {}: {}", what, std::strerror(errno)));
  }
  return status;
}

bool hasEnded(pid_t pid, int& status, const std::string& what) {
  for (;;) {
    const pid_t got = ::waitpid(pid, &status, WNOHANG);
    if (got == pid) return true;
    if (got == 0) return false;
    if (errno != EINTR)
      throw std::runtime_error(fmt::format("waiting for {}: {}", what, std::strerror(errno)));
  }
}

void stopChildren(const std::vector<pid_t>& pids, std::chrono::milliseconds grace) {
  for (pid_t pid : pids) ::kill(pid, SIGTERM);
  std::vector<pid_t> left = pids;
  const auto deadline = std::chrono::steady_clock::now() + grace;
  while (!left.empty()) {
    std::erase_if(left, [](pid_t pid) {
      int status = 0;
      const pid_t got = ::waitpid(pid, &status, WNOHANG);
      // An error (not EINTR) means there is no such child left to wait for.
      return got == pid || (got < 0 && errno != EINTR);
    });
    if (left.empty()) break;
    if (std::chrono::steady_clock::now() >= deadline) {
      // A program that ignores SIGTERM, or is stuck: it must not outlive linx.
      for (pid_t pid : left) {
        ::kill(pid, SIGKILL);
        int status = 0;
        while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
        }
      }
      break;
    }
    sleepFor(std::chrono::milliseconds(20));
  }
}

void sleepFor(std::chrono::milliseconds duration) {
  const auto seconds = std::chrono::duration_cast<std::chrono::seconds>(duration);
  timespec ts{};
  ts.tv_sec = static_cast<std::time_t>(seconds.count());
  ts.tv_nsec = static_cast<long>(
      std::chrono::duration_cast<std::chrono::nanoseconds>(duration - seconds).count());
  // Not resumed after a signal: the caller checks for one as soon as possible.
  ::nanosleep(&ts, nullptr);
}

bool succeeded(int status) {
  return WIFEXITED(status) && WEXITSTATUS(status) == 0;
}

std::string describeStatus(int status) {
  if (WIFEXITED(status)) return fmt::format("exit status {}", WEXITSTATUS(status));
  if (WIFSIGNALED(status)) return fmt::format("killed by signal {}", WTERMSIG(status));
  return "stopped";
}

std::string logTail(const fs::path& log, std::size_t count) {
  std::ifstream in(log);
  std::deque<std::string> lines;
  for (std::string line; std::getline(in, line);) {
    while (!line.empty() && (line.back() == '\r' || line.back() == ' ')) line.pop_back();
    if (line.empty()) continue;
    lines.push_back(line);
    if (lines.size() > count) lines.pop_front();
  }
  std::string text;
  for (const std::string& l : lines) text += (text.empty() ? "" : " | ") + l;
  return text.empty() ? "(no output)" : text;
}

}  // namespace linx::cli
