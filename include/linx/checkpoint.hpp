// Checkpoints of a run (docs/reliability.md, "Checkpoints"): the world's whole state
// (World::saveState), the run's scene as a scene file, and where the run stood (its step count,
// frames and output files), in one versioned, checksummed binary file. `linx run
// --checkpoint-every T` writes them, and `linx resume` goes on from one: the resumed run's files
// are bit for bit those of the run that was not stopped.
#pragma once

#include <linx/recorder.hpp>
#include <linx/world.hpp>

#include <cstdint>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <string_view>

namespace linx {

/// The checkpoint format this linx writes and reads.
/// (2: with the identity of the run folder it belongs to, RunCheckpoint::run_scene_bytes ...)
inline constexpr std::uint32_t kCheckpointVersion = 2;

/// A checkpoint that cannot be read: "FILE: FIELD: PROBLEM".
class CheckpointError : public std::runtime_error {
 public:
  CheckpointError(const std::string& file, const std::string& field, const std::string& problem);
};

struct RunCheckpoint {
  std::string scene;       ///< the run's scene as a scene file (writeSceneJson): what is rebuilt
  std::string source;      ///< the file the run was started from (for messages)
  std::int64_t steps = 0;  ///< the run's steps in all
  int every = 1;           ///< a frame every `every` steps (and the last)
  std::int64_t checkpoint_every = 0;  ///< steps between checkpoints; 0: none
  bool contacts = false;              ///< the run writes contacts.csv
  bool breaks = false;                ///< ... and breaks.csv
  bool keep_going = false;            ///< --on-fault continue
  std::int64_t frames = 0;            ///< frames recorded when the checkpoint was taken
  RecorderPosition output;            ///< the files' sizes then
  WorldState state;                   ///< the world then (World::saveState)
  /// What identifies the run folder the checkpoint belongs to: its scene.json as the run wrote it
  /// (size and CRC-32), and the bodies and joints of its world (the rows of a frame).
  std::uint64_t run_scene_bytes = 0;
  std::uint32_t run_scene_crc = 0;
  std::int64_t bodies = 0, joints = 0;
};

/// The CRC-32 (zlib) of `text`: how a checkpoint identifies its run's scene.json.
std::uint32_t checksumOf(std::string_view text);

/// Writes `checkpoint` to `file`, complete or not at all (a temporary file in the same folder,
/// forced to disk and renamed into place). Throws std::runtime_error naming the file.
void writeCheckpoint(const std::filesystem::path& file, const RunCheckpoint& checkpoint);
/// Reads a checkpoint, checking its format, version, byte order, length and checksum. Throws
/// CheckpointError naming the file and what is wrong with it.
RunCheckpoint readCheckpoint(const std::filesystem::path& file);

}  // namespace linx
