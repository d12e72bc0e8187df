// The files of a run's output folder (docs/scene-format.md, "Outputs"; docs/reliability.md): the
// one list that the recorder writes, viz::readRun reads back, `linx view` serves, and `linx run`
// clears of an earlier run's before it writes its own.
#pragma once

#include <array>
#include <string_view>

namespace linx::run_files {

struct RunFile {
  std::string_view name;    ///< in the run folder; a name ending in '/' is a folder
  std::string_view header;  ///< a CSV file's header line (its columns); empty for other files
  bool read_back = false;   ///< read by viz::readRun and served by `linx view`
};

/// The resolved scene of the run. Written after the CSV files are created, so that a folder whose
/// scene.json is there holds one run's files only.
inline constexpr RunFile kScene{"scene.json", "", true};
inline constexpr RunFile kBodies{"bodies.csv", "time,body,x,y,z,qw,qx,qy,qz,vx,vy,vz,wx,wy,wz",
                                 true};
inline constexpr RunFile kJoints{
    "joints.csv",
    "time,joint,coordinate,error,fx,fy,fz,tx,ty,tz,coordinate2,coordinate3,coordinate4,"
    "coordinate5,coordinate6",
    true};
inline constexpr RunFile kWorld{
    "world.csv",
    "time,kinetic_energy,potential_energy,total_energy,max_joint_error,solver_iterations,residual",
    true};
inline constexpr RunFile kContacts{"contacts.csv",
                                   "time,body1,body2,x,y,z,nx,ny,nz,depth,normal_impulse", true};
inline constexpr RunFile kBreaks{"breaks.csv", "time,step,joint,fx,fy,fz,tx,ty,tz", false};
/// Checkpoints (`linx run --checkpoint-every`, and the last good state of a faulted run).
inline constexpr RunFile kCheckpoints{"checkpoints/", "", false};
/// What the tools make of a run: ParaView files, POV-Ray frames and video, plots.
inline constexpr RunFile kVtkSeries{"run.pvd", "", false};
inline constexpr RunFile kVtkFrames{"vtk/", "", false};
inline constexpr RunFile kRenderFrames{"render/", "", false};
inline constexpr RunFile kRenderMp4{"render.mp4", "", false};
inline constexpr RunFile kRenderGif{"render.gif", "", false};
inline constexpr RunFile kPlots{"plots/", "", false};

/// Every file and folder of a run, scene.json first: the order in which an earlier run's are
/// removed, so that an interrupted clear-up never leaves a scene.json beside another run's files.
inline constexpr std::array kAll = {kScene,     kBodies,      kJoints,    kWorld,     kContacts,
                                    kBreaks,    kCheckpoints, kVtkSeries, kVtkFrames, kRenderFrames,
                                    kRenderMp4, kRenderGif,   kPlots};

}  // namespace linx::run_files
