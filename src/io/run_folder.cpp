#include "io/run_folder.hpp"

#include "io/output_file.hpp"

#include <linx/run_files.hpp>

#include <dirent.h>
#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <functional>
#include <string>

namespace linx::io {

namespace fs = std::filesystem;

namespace {

// An entry found: the descriptor of the folder that holds it, its name there, its path inside
// the run folder.
using Visit = std::function<void(int parent_fd, const std::string& name, const fs::path& inside)>;

// The type of the entry `name` of `dir_fd` (not following a link), or 0 when there is none.
mode_t entryType(int dir_fd, const std::string& name, const fs::path& shown) {
  struct stat st {};
  if (::fstatat(dir_fd, name.c_str(), &st, AT_SYMLINK_NOFOLLOW) == 0) return st.st_mode & S_IFMT;
  if (errno == ENOENT || errno == ENOTDIR) return 0;
  throw ioError("look at", shown / name, errno);
}

// Calls `visit` on each earlier run entry of `dir_fd`, scene.json first; `folder_done(name)` after
// the entries of each run folder that is a real folder.
void forEachEntry(int dir_fd, const fs::path& shown, const Visit& visit,
                  const std::function<void(const std::string&)>& folder_done) {
  for (const run_files::RunFile& file : run_files::kAll) {
    std::string name(file.name);
    const bool folder = name.back() == '/';
    if (folder) name.pop_back();
    const mode_t type = entryType(dir_fd, name, shown);
    if (type == 0) continue;
    if (type == S_IFLNK) {  // a link in place of a file or a folder: removed as a link
      visit(dir_fd, name, name);
      continue;
    }
    if (!folder) {
      if (type != S_IFDIR) visit(dir_fd, name, name);
      continue;
    }
    if (type != S_IFDIR) continue;  // a file named like a run folder is not one
    const int fd = ::openat(dir_fd, name.c_str(), O_RDONLY | O_DIRECTORY | O_NOFOLLOW | O_CLOEXEC);
    if (fd < 0) throw ioError("open", shown / name, errno);
    DIR* dir = ::fdopendir(fd);
    if (!dir) {
      const int error = errno;
      ::close(fd);
      throw ioError("read", shown / name, error);
    }
    std::vector<std::string> children;  // collected first: removing while reading skips entries
    while (const dirent* entry = ::readdir(dir)) {
      if (run_files::isFolderEntry(file, entry->d_name)) children.emplace_back(entry->d_name);
    }
    std::sort(children.begin(), children.end());
    try {
      for (const std::string& child : children) {
        const mode_t child_type = entryType(fd, child, shown / name);
        if (child_type != 0 && child_type != S_IFDIR) visit(fd, child, fs::path(name) / child);
      }
    } catch (...) {
      ::closedir(dir);
      throw;
    }
    ::closedir(dir);
    folder_done(name);
  }
}

}  // namespace

FolderLock tryLockFolder(int dir_fd, const fs::path& shown) {
  while (::flock(dir_fd, LOCK_EX | LOCK_NB) != 0) {
    if (errno == EWOULDBLOCK) return FolderLock::kHeld;
    if (errno == ENOLCK || errno == EOPNOTSUPP || errno == ENOSYS) return FolderLock::kUnsupported;
    if (errno != EINTR) throw ioError("lock", shown, errno);
  }
  return FolderLock::kTaken;
}

std::vector<fs::path> earlierRunEntries(int dir_fd, const fs::path& shown) {
  std::vector<fs::path> found;
  forEachEntry(
      dir_fd, shown,
      [&](int, const std::string&, const fs::path& inside) { found.push_back(inside); },
      [](const std::string&) {});
  return found;
}

void clearEarlierRun(int dir_fd, const fs::path& shown) {
  forEachEntry(
      dir_fd, shown,
      [&](int parent_fd, const std::string& name, const fs::path& inside) {
        if (::unlinkat(parent_fd, name.c_str(), 0) != 0 && errno != ENOENT)
          throw ioError("remove", shown / inside, errno);
      },
      [&](const std::string& folder) {
        // Only once empty: a file of the user's inside keeps the folder.
        if (::unlinkat(dir_fd, folder.c_str(), AT_REMOVEDIR) != 0 && errno != ENOTEMPTY &&
            errno != EEXIST && errno != ENOENT)
          throw ioError("remove", shown / folder, errno);
      });
}

}  // namespace linx::io
