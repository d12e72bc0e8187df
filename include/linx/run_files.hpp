// The files of a run's output folder (docs/scene-format.md, "Outputs"; docs/reliability.md): the
// one list that the recorder writes, viz::readRun reads back, `linx view` serves, and `linx run`
// clears of an earlier run's before it writes its own. Only these entries are ever removed, by
// their exact names or the exact name patterns of the files linx writes inside the run's folders:
// any other entry of the output folder, or of its checkpoints/, vtk/, render/ and plots/ folders,
// is the user's and is left alone.
#pragma once

#include <array>
#include <span>
#include <string_view>

namespace linx::run_files {

struct RunFile {
  std::string_view name;    ///< in the run folder; a name ending in '/' is a folder
  std::string_view header;  ///< a CSV file's header line (its columns); empty for other files
  bool read_back = false;   ///< read by viz::readRun and served by `linx view`
  /// A folder's entries that linx writes (and so removes): name patterns in which '#' stands for
  /// one or more decimal digits. Empty for a file.
  std::span<const std::string_view> contents{};
};

/// Checkpoints: step_N.lxc (N the step, 15 digits), and the temporary file of the one being
/// written (apps/linx/run_command.cpp, src/io/output_file.cpp).
inline constexpr std::array<std::string_view, 2> kCheckpointNames = {"step_#.lxc",
                                                                     ".step_#.lxc.tmp"};
/// ParaView frames of `linx vtk` (src/viz/vtk.cpp), and their temporary names while written.
inline constexpr std::array<std::string_view, 6> kVtkNames = {
    "bodies_#.vtp",     "joints_#.vtp",     "contacts_#.vtp",
    "bodies_#.vtp.tmp", "joints_#.vtp.tmp", "contacts_#.vtp.tmp"};
/// POV-Ray scenes, pictures and logs of `linx render` (apps/linx/render_command.cpp): frame_N of
/// a whole render, still_N of --frame.
inline constexpr std::array<std::string_view, 20> kRenderNames = {"scene.inc",
                                                                  ".scene.inc.tmp",
                                                                  "linx.ini",
                                                                  ".linx.ini.tmp",
                                                                  "povray.log",
                                                                  "ffmpeg.log",
                                                                  "frame_#.pov",
                                                                  ".frame_#.pov.tmp",
                                                                  "frame_#.png",
                                                                  "frame_#.part.png",
                                                                  ".frame_#.log",
                                                                  "frame_#.log",
                                                                  "frame_#.part.pov-state",
                                                                  "still_#.pov",
                                                                  ".still_#.pov.tmp",
                                                                  "still_#.png",
                                                                  "still_#.part.png",
                                                                  ".still_#.log",
                                                                  "still_#.log",
                                                                  "still_#.part.pov-state"};
/// The pictures, script and log of `linx plot` (apps/linx/plot_command.cpp), and the temporary
/// names they are drawn under.
inline constexpr std::array<std::string_view, 19> kPlotNames = {"energy.png",
                                                                "energy.svg",
                                                                "joint_coordinates.png",
                                                                "joint_coordinates.svg",
                                                                "joint_errors.png",
                                                                "joint_errors.svg",
                                                                "solver.png",
                                                                "solver.svg",
                                                                "plots.gp",
                                                                ".plots.gp.tmp",
                                                                ".gnuplot.log",
                                                                ".energy.png.tmp",
                                                                ".energy.svg.tmp",
                                                                ".joint_coordinates.png.tmp",
                                                                ".joint_coordinates.svg.tmp",
                                                                ".joint_errors.png.tmp",
                                                                ".joint_errors.svg.tmp",
                                                                ".solver.png.tmp",
                                                                ".solver.svg.tmp"};

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
inline constexpr RunFile kCheckpoints{"checkpoints/", "", false, kCheckpointNames};
/// What the tools make of a run: ParaView files, POV-Ray frames and video, plots.
inline constexpr RunFile kVtkSeries{"run.pvd", "", false};
inline constexpr RunFile kVtkFrames{"vtk/", "", false, kVtkNames};
inline constexpr RunFile kRenderFrames{"render/", "", false, kRenderNames};
inline constexpr RunFile kRenderMp4{"render.mp4", "", false};
inline constexpr RunFile kRenderGif{"render.gif", "", false};
inline constexpr RunFile kPlots{"plots/", "", false, kPlotNames};
/// The temporary files of the folder's own entries while they are written (a kill can leave one):
/// scene.json's, run.pvd's and the video's.
inline constexpr RunFile kSceneTemporary{".scene.json.tmp", "", false};
inline constexpr RunFile kVtkSeriesTemporary{"run.pvd.tmp", "", false};
inline constexpr RunFile kRenderMp4Temporary{".render.part.mp4", "", false};
inline constexpr RunFile kRenderGifTemporary{".render.part.gif", "", false};

/// Every file and folder of a run, scene.json first: the order in which an earlier run's are
/// removed, so that an interrupted clear-up never leaves a scene.json beside another run's files.
inline constexpr std::array kAll = {kScene,
                                    kBodies,
                                    kJoints,
                                    kWorld,
                                    kContacts,
                                    kBreaks,
                                    kCheckpoints,
                                    kVtkSeries,
                                    kVtkFrames,
                                    kRenderFrames,
                                    kRenderMp4,
                                    kRenderGif,
                                    kPlots,
                                    kSceneTemporary,
                                    kVtkSeriesTemporary,
                                    kRenderMp4Temporary,
                                    kRenderGifTemporary};

/// Whether `name` is a folder entry (no '/') of the name pattern `pattern` ('#': one or more
/// decimal digits).
constexpr bool matchesPattern(std::string_view pattern, std::string_view name) {
  while (!pattern.empty()) {
    if (pattern.front() == '#') {
      std::size_t digits = 0;
      while (digits < name.size() && name[digits] >= '0' && name[digits] <= '9') ++digits;
      if (digits == 0) return false;
      pattern.remove_prefix(1);
      name.remove_prefix(digits);  // '#' is followed by a non-digit in every pattern
      continue;
    }
    if (name.empty() || name.front() != pattern.front()) return false;
    pattern.remove_prefix(1);
    name.remove_prefix(1);
  }
  return name.empty();
}

/// Whether `name` is one of the entries linx writes in the run folder `folder` (kCheckpoints,
/// kVtkFrames, kRenderFrames, kPlots).
constexpr bool isFolderEntry(const RunFile& folder, std::string_view name) {
  for (const std::string_view pattern : folder.contents)
    if (matchesPattern(pattern, name)) return true;
  return false;
}

}  // namespace linx::run_files
