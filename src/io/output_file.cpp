#include "io/output_file.hpp"

#include <fmt/format.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <string>
#include <system_error>

namespace linx::io {

namespace fs = std::filesystem;

std::runtime_error ioError(std::string_view what, const fs::path& path, int error) {
  return std::runtime_error(
      fmt::format("cannot {} {}: {}", what, path.string(), std::generic_category().message(error)));
}

namespace {

// Writes all of `data` to `fd`; 0, or the errno of the failure.
int writeAllOrError(int fd, std::string_view data) {
  while (!data.empty()) {
    const ssize_t n = ::write(fd, data.data(), data.size());
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return n < 0 ? errno : EIO;
    data.remove_prefix(static_cast<std::size_t>(n));
  }
  return 0;
}

}  // namespace

void writeAll(int fd, std::string_view data, const fs::path& shown) {
  if (const int error = writeAllOrError(fd, data); error != 0) throw ioError("write", shown, error);
}

void writeFileAtomically(const fs::path& path, std::string_view data, int dir_fd,
                         const fs::path& shown) {
  const fs::path& name = shown.empty() ? path : shown;
  // Only a file (or a link, replaced as a link) is replaced: renaming over a device, a pipe or a
  // socket would put a file in its place (as root, /dev/null).
  struct stat existing {};
  if (::fstatat(dir_fd, path.c_str(), &existing, AT_SYMLINK_NOFOLLOW) == 0 &&
      !S_ISREG(existing.st_mode) && !S_ISLNK(existing.st_mode))
    throw std::runtime_error(
        fmt::format("cannot write {}: not a regular file (a device, a pipe, a socket or a folder)",
                    name.string()));
  const std::string temp =
      (path.parent_path() / fmt::format(".{}.tmp", path.filename().string())).string();
  const int fd =
      ::openat(dir_fd, temp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_NOFOLLOW | O_CLOEXEC, 0644);
  if (fd < 0) throw ioError("write", name, errno);
  int error = writeAllOrError(fd, data);
  if (error == 0 && ::fsync(fd) != 0) error = errno;
  if (::close(fd) != 0 && error == 0) error = errno;
  if (error == 0 && ::renameat(dir_fd, temp.c_str(), dir_fd, path.c_str()) != 0) error = errno;
  if (error != 0) {
    ::unlinkat(dir_fd, temp.c_str(), 0);
    throw ioError("write", name, error);
  }
}

}  // namespace linx::io
