// `linx run`, `linx check` and `linx resume` (docs/scene-format.md, "Command line";
// docs/reliability.md): a scene simulated into a run folder, with checkpoints to go on from.
#pragma once

#include <cstdint>
#include <optional>
#include <string>

namespace linx::cli {

struct RunOptions {
  std::string scene;
  std::string out;
  std::optional<double> duration, timestep;
  std::optional<int> threads;
  int every = 1;
  std::optional<double> checkpoint_every;  ///< (s) simulated time between checkpoints
  bool keep_going = false;                 ///< --on-fault continue
  bool contacts = false;
  bool vtk = false;                  ///< also write ParaView files (DIR/vtk/, DIR/run.pvd)
  bool render = false;               ///< then render POV-Ray frames (linx render DIR)
  bool floating_base = false;        ///< a URDF's root link is free
  bool allow_outside_paths = false;  ///< read files the scene names outside its folder
};

/// Validates the scene and prints a summary; 0, or throws as the scene reader does.
int check(const RunOptions& options);
/// Simulates the scene into options.out; returns the exit status (docs/reliability.md).
int run(const RunOptions& options);
/// Goes on with a run from a checkpoint file, or from the newest checkpoint of a run folder.
/// `keep_going` overrides the run's --on-fault (true: continue, false: stop).
int resume(const std::string& checkpoint, std::optional<bool> keep_going = std::nullopt);
/// `linx vtk DIR`.
int writeVtk(const std::string& dir);

}  // namespace linx::cli
