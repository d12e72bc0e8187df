// Writes a run's trajectory and reports as CSV files (see docs/scene-format.md, "Outputs", and
// include/linx/run_files.hpp for the list):
//   DIR/bodies.csv  time,body,x,y,z,qw,qx,qy,qz,vx,vy,vz,wx,wy,wz
//   DIR/joints.csv  time,joint,coordinate,error,fx,fy,fz,tx,ty,tz,coordinate2..coordinate6
//   DIR/world.csv   time,kinetic_energy,potential_energy,total_energy,max_joint_error,
//                   solver_iterations,residual
//   DIR/contacts.csv time,body1,body2,x,y,z,nx,ny,nz,depth,normal_impulse   (when asked for)
//   DIR/breaks.csv  time,step,joint,fx,fy,fz,tx,ty,tz: each joint that broke (when asked for)
// and any file written with writeFile() (the run's scene.json).
//
// What survives (docs/reliability.md): every frame is handed to the operating system before
// record() returns, so killing the process at any moment (SIGKILL included) leaves each file
// complete up to its last frame but one at worst, where the last may end part-way (readers drop
// it). Opening a recorder takes the folder's lock (one writer at a time), then removes an earlier
// run's files from DIR (only the names of the run file list, scene.json first), so old and new
// files are never mixed. Nothing is ever removed
// afterwards, and every file is reached through the folder opened at the start: if DIR is renamed
// or replaced during the run, the run goes on writing into the folder it opened.
#pragma once

#include <linx/world.hpp>

#include <array>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <stdexcept>
#include <string>

namespace linx {

/// The output folder cannot take a recording: another run or recording holds its lock, a folder
/// of the user's is where a run file goes, or (resuming) a file is not the checkpoint's run's.
class RunFolderError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct RecorderOptions {
  bool contacts = false;  ///< also write contacts.csv: every contact point of each recorded step
  /// Also write breaks.csv: every joint that broke (World::jointBreaks), recorded or not.
  bool breaks = false;
};

/// How far a recorder has written: the size of each of its files (bodies, joints, world,
/// contacts, breaks; 0 for a file it does not write) and the joint breaks written. A checkpoint
/// keeps it, so that a resumed run cuts its files back to where the checkpoint was taken.
struct RecorderPosition {
  std::array<std::uint64_t, 5> bytes{};
  std::uint64_t breaks = 0;
};

class Recorder {
 public:
  /// Creates DIR if needed, takes its lock (held until finish() or the destructor), removes an
  /// earlier run's files from it (run_files.hpp's names only) and creates the CSV files with
  /// their headers. Throws RunFolderError when another run or recording holds the folder, or a
  /// folder is where a run file goes (nothing is removed then); std::runtime_error naming the
  /// file and the reason on other failures.
  explicit Recorder(const std::filesystem::path& dir, const RecorderOptions& options = {});
  /// Reopens the files of a run in DIR to go on from `at` (a checkpoint's position), holding the
  /// folder's lock: each is cut back to its size there, and nothing else in DIR changes. Throws
  /// RunFolderError (nothing changed) when the folder is locked, or a file is missing, not a
  /// file, shorter than that, or does not start with its header (not the checkpoint's run).
  Recorder(const std::filesystem::path& dir, const RecorderOptions& options,
           const RecorderPosition& at);
  ~Recorder();  ///< closes the files (what was recorded stays)
  Recorder(const Recorder&) = delete;
  Recorder& operator=(const Recorder&) = delete;

  /// Appends one row per body, one per joint and one for the world at the world's current time,
  /// and writes them out. Throws std::runtime_error naming the file on a write error (a full disk,
  /// the file size limit).
  void record(const World& world);
  /// Writes DIR/name with the given text, complete or not at all (a temporary file renamed into
  /// place): the run's scene.json. `name` is a plain file name.
  void writeFile(const std::string& name, const std::string& text);
  /// Forces everything to the disk (fsync) and closes the files: the run survives a power loss
  /// from here on. Throws std::runtime_error naming the file on failure.
  void finish();

  const std::filesystem::path& dir() const { return dir_; }
  RecorderPosition position() const { return position_; }

 private:
  struct Files;
  std::filesystem::path dir_;
  std::unique_ptr<Files> files_;
  RecorderPosition position_;
  bool finished_ = false;
};

}  // namespace linx
