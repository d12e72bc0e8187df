// Opening a run folder as a linx command does: the rows a killed run left after its last whole
// frame are cut off first (docs/reliability.md, "Output that survives a kill"), under the folder's
// lock, so that a folder a run is still writing is never cut.
#include "viz/run.hpp"

#include "io/quoting.hpp"
#include "io/run_folder.hpp"

#include <linx/run_files.hpp>

#include <fcntl.h>
#include <fmt/format.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cstdio>
#include <string>

namespace linx::viz {

namespace fs = std::filesystem;

namespace {

struct Descriptor {
  int fd;
  ~Descriptor() {
    if (fd >= 0) ::close(fd);
  }
};

// The size of the file `fd` up to its last line break.
off_t completeLines(int fd, off_t size) {
  char block[4096];
  for (off_t end = size; end > 0;) {
    const off_t start = end > static_cast<off_t>(sizeof block) ? end - sizeof block : 0;
    const ssize_t n = ::pread(fd, block, static_cast<std::size_t>(end - start), start);
    if (n != end - start) return size;  // unreadable: left as it is
    for (ssize_t i = n; i-- > 0;)
      if (block[i] == '\n') return start + i + 1;
    end = start;
  }
  return 0;
}

// Cuts the file `name` of the folder `dir_fd` to `keep` bytes (or, with keep < 0, to its last
// line break); a link, a missing file or one that cannot be written is left alone.
void cutTo(int dir_fd, const fs::path& dir, const std::string& name, off_t keep) {
  const Descriptor file{::openat(dir_fd, name.c_str(), O_RDWR | O_NOFOLLOW | O_CLOEXEC)};
  struct stat st {};
  if (file.fd < 0 || ::fstat(file.fd, &st) != 0 || !S_ISREG(st.st_mode)) return;
  if (keep < 0) keep = completeLines(file.fd, st.st_size);
  if (st.st_size <= keep || ::ftruncate(file.fd, keep) != 0) return;
  fmt::print(stderr,
             "linx: note: {}: cut {} bytes after its last whole frame (left by a run that was "
             "killed)\n",
             io::visible((dir / name).string()), st.st_size - keep);
}

}  // namespace

Run openRun(const fs::path& dir) {
  const Descriptor folder{::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC)};
  bool locked = false;
  try {
    locked = folder.fd >= 0 && io::tryLockFolder(folder.fd, dir) == io::FolderLock::kTaken;
  } catch (const std::runtime_error&) {  // read as it is
  }
  Run run = readRun(dir);
  // A run may be writing it (its last frame on its way), or no lock tells: read as it is.
  if (!locked) return run;
  for (const auto& [name, size] : run.whole_bytes)
    cutTo(folder.fd, dir, name, static_cast<off_t>(size));
  cutTo(folder.fd, dir, std::string(run_files::kBreaks.name), -1);
  return run;
}

}  // namespace linx::viz
