// Reading an input file whole, safely (docs/reliability.md, "Inputs"): only a regular file (not a
// device such as /dev/zero, a pipe or a folder), of at most a size limit per kind of file, read
// through one descriptor so that the file checked is the file read. And the rule that a file a
// scene names lies in the scene's folder, unless the user allows otherwise.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace linx::io {

/// Size limits of the files linx reads (bytes).
inline constexpr std::uint64_t kMiB = 1024 * 1024;
inline constexpr std::uint64_t kSceneLimit = 256 * kMiB;  ///< a JSON scene
inline constexpr std::uint64_t kModelLimit = 64 * kMiB;   ///< a URDF or MJCF file
inline constexpr std::uint64_t kMeshLimit = 512 * kMiB;   ///< an OBJ or STL mesh
inline constexpr std::uint64_t kTableLimit = 256 * kMiB;  ///< a CSV table of a drive or load

/// The file's bytes. Throws std::runtime_error with the problem alone ("cannot open it: No such
/// file or directory", "not a regular file (a device, a pipe or a folder)", "is 600 MiB, above
/// the limit of 512 MiB for a mesh"): callers name the file and the field.
std::string readInputFile(const std::filesystem::path& path, std::uint64_t limit, const char* kind);

/// A file that readInputFile read: the path it was given, the kind of file ("a table"), and the
/// file's identity (device and inode, links followed).
struct InputRead {
  std::filesystem::path path;
  std::string kind;
  std::uint64_t device = 0, inode = 0;
};

/// Keeps a list of every file readInputFile reads on this thread while it lives (the files a
/// scene loads: itself, its model files and includes, meshes, tables), so that a run can refuse
/// to replace one of its own inputs. Logs nest: the innermost one records.
class InputLog {
 public:
  InputLog();
  ~InputLog();
  InputLog(const InputLog&) = delete;
  InputLog& operator=(const InputLog&) = delete;
  const std::vector<InputRead>& files() const { return files_; }
  /// The log open on this thread, or nullptr.
  static InputLog* current();
  void add(InputRead read) { files_.push_back(std::move(read)); }

 private:
  InputLog* outer_;
  std::vector<InputRead> files_;
};

/// Throws std::runtime_error unless `path` (links followed) lies inside `folder` (links followed)
/// or `allowed` (--allow-outside-paths).
void checkInsideFolder(const std::filesystem::path& path, const std::filesystem::path& folder,
                       bool allowed);

}  // namespace linx::io
