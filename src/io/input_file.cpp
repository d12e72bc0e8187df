#include "io/input_file.hpp"

#include "io/quoting.hpp"

#include <fcntl.h>
#include <fmt/format.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <stdexcept>
#include <system_error>

namespace linx::io {

namespace fs = std::filesystem;

namespace {

std::string size(std::uint64_t bytes) {
  return bytes >= kMiB ? fmt::format("{:.4g} MiB", static_cast<double>(bytes) / kMiB)
                       : fmt::format("{} bytes", bytes);
}

}  // namespace

namespace {
thread_local InputLog* current_log = nullptr;
}  // namespace

InputLog::InputLog() : outer_(current_log) {
  current_log = this;
}
InputLog::~InputLog() {
  current_log = outer_;
}
InputLog* InputLog::current() {
  return current_log;
}

std::string readInputFile(const fs::path& path, std::uint64_t limit, const char* kind) {
  // The system would open the name only up to the NUL: another file than the one named.
  if (path.native().find('\0') != std::string::npos)
    throw std::runtime_error("cannot open: the file name holds a NUL byte");
  // O_NONBLOCK: opening a FIFO must not wait for a writer; it is refused below.
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC | O_NONBLOCK);
  if (fd < 0)
    throw std::runtime_error(
        fmt::format("cannot open: {}", std::generic_category().message(errno)));
  struct Closer {
    int fd;
    ~Closer() { ::close(fd); }
  } closer{fd};
  struct stat st {};
  if (::fstat(fd, &st) != 0)
    throw std::runtime_error(
        fmt::format("cannot read it: {}", std::generic_category().message(errno)));
  if (!S_ISREG(st.st_mode))
    throw std::runtime_error(S_ISDIR(st.st_mode)
                                 ? "is a directory"
                                 : "not a regular file (a device, a pipe or a socket)");
  if (InputLog* log = InputLog::current())
    log->add(
        {path, kind, static_cast<std::uint64_t>(st.st_dev), static_cast<std::uint64_t>(st.st_ino)});
  const auto bytes = static_cast<std::uint64_t>(st.st_size);
  if (bytes > limit)
    throw std::runtime_error(
        fmt::format("is {}, above the limit of {} for {}", size(bytes), size(limit), kind));
  std::string text(static_cast<std::size_t>(bytes), '\0');
  std::size_t done = 0;
  while (done < text.size()) {
    const ssize_t n = ::read(fd, text.data() + done, text.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0)
      throw std::runtime_error(
          fmt::format("cannot read it: {}", std::generic_category().message(errno)));
    if (n == 0) break;  // shorter than it was: what is there
    done += static_cast<std::size_t>(n);
  }
  text.resize(done);
  return text;
}

void checkInsideFolder(const fs::path& path, const fs::path& folder, bool allowed) {
  if (allowed) return;
  std::error_code ec;
  const fs::path base = fs::weakly_canonical(fs::absolute(folder.empty() ? "." : folder), ec);
  const fs::path target = fs::weakly_canonical(fs::absolute(path), ec);
  const fs::path relative = target.lexically_relative(base);
  if (!relative.empty() && *relative.begin() != ".." && relative.is_relative()) return;
  throw std::runtime_error(
      fmt::format("'{}' is outside the scene's folder {} (linx reads only files there; "
                  "--allow-outside-paths lifts this)",
                  visible(path.string()), visible(base.string())));
}

}  // namespace linx::io
