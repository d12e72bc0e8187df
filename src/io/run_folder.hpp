// A run's output folder as linx owns it (docs/reliability.md, "Output that survives a kill"): the
// exclusive lock a run or recording holds on it while it writes, and the entries of an earlier run
// in it, known by the exact names and name patterns of include/linx/run_files.hpp. Everything is
// reached through a descriptor of the folder (openat, unlinkat), links are never followed.
#pragma once

#include <filesystem>
#include <vector>

namespace linx::io {

/// What tryLockFolder found.
enum class FolderLock {
  kTaken,       ///< this descriptor holds the lock now (until it is closed)
  kHeld,        ///< another descriptor holds it: a run, a recording or a repair is writing
  kUnsupported  ///< the file system has no locks (some network ones)
};

/// Takes the folder's exclusive lock (flock on the descriptor `dir_fd`, held until the descriptor
/// is closed). Throws ioError on any failure but those above.
FolderLock tryLockFolder(int dir_fd, const std::filesystem::path& shown);

/// The entries of an earlier run in the folder `dir_fd`, as paths inside it: each file of the run
/// file list (a link as a link), and inside the run's folders (checkpoints/, vtk/, render/,
/// plots/) each file of their name patterns. A folder in place of a run file, a file in place of
/// a run folder, and every other name are the user's and are not listed.
std::vector<std::filesystem::path> earlierRunEntries(int dir_fd,
                                                     const std::filesystem::path& shown);

/// Removes the entries earlierRunEntries lists, scene.json first, then each run folder that is
/// left empty. Throws ioError naming the entry on failure.
void clearEarlierRun(int dir_fd, const std::filesystem::path& shown);

}  // namespace linx::io
