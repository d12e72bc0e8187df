// Writes a run's trajectory and reports as CSV files (see docs/scene-format.md, "Outputs"):
//   DIR/bodies.csv  time,body,x,y,z,qw,qx,qy,qz,vx,vy,vz,wx,wy,wz
//   DIR/joints.csv  time,joint,coordinate,error,fx,fy,fz,tx,ty,tz
//   DIR/world.csv   time,kinetic_energy,potential_energy,total_energy,max_joint_error,
//                   solver_iterations,residual
//   DIR/contacts.csv time,body1,body2,x,y,z,nx,ny,nz,depth,normal_impulse   (when asked for)
//   DIR/breaks.csv  time,step,joint,fx,fy,fz,tx,ty,tz: each joint that broke (when asked for)
// and any file added with addFile() (the run's scene.json).
// Files are written under temporary names and renamed by commit(), so an interrupted or failed
// run never leaves half a file under the final names.
#pragma once

#include <linx/world.hpp>

#include <filesystem>
#include <memory>
#include <string>

namespace linx {

struct RecorderOptions {
  bool contacts = false;  ///< also write contacts.csv: every contact point of each recorded step
  /// Also write breaks.csv: every joint that broke (World::jointBreaks), recorded or not.
  bool breaks = false;
};

class Recorder {
 public:
  /// Creates DIR if needed and opens the temporary files. Throws std::runtime_error on failure.
  explicit Recorder(const std::filesystem::path& dir, const RecorderOptions& options = {});
  ~Recorder();  ///< removes the temporary files unless commit() was called
  Recorder(const Recorder&) = delete;
  Recorder& operator=(const Recorder&) = delete;

  /// Appends one row per body, one per joint and one for the world at the world's current time.
  void record(const World& world);
  /// Adds a file DIR/name with the given text, written and renamed with the others by commit()
  /// (scene.json of a run). `name` is a plain file name.
  void addFile(const std::string& name, std::string text);
  /// Flushes and renames the files to their final names. Throws std::runtime_error on failure.
  void commit();

 private:
  struct Files;
  std::filesystem::path dir_;
  std::unique_ptr<Files> files_;
  std::size_t breaks_written_ = 0;
  bool committed_ = false;
};

}  // namespace linx
