// A recorded run read back from its output folder (docs/scene-format.md, "Outputs"): the resolved
// scene from scene.json and every frame of bodies.csv, joints.csv, world.csv and, when present,
// contacts.csv. This is what every picture is drawn from: POV-Ray frames, VTK files, plots and the
// browser viewer all read a run through here (or, for the viewer, the same files).
#pragma once

#include <linx/scene.hpp>
#include <linx/shape.hpp>
#include <linx/types.hpp>

#include <cstdint>
#include <filesystem>
#include <map>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace linx::viz {

/// A bad or missing output file: "FILE: FIELD: PROBLEM" (FIELD is a JSON path, or "line N").
class RunError : public std::runtime_error {
 public:
  RunError(const std::string& file, const std::string& field, const std::string& problem);
};

struct RunBody {
  std::string name;
  bool is_static = false;
  double mass = 0.0;
  /// In the body frame. Convex shapes and meshes carry `points` (the vertices) and `triangles`.
  std::vector<ShapeDef> shapes;
};

struct RunJoint {
  std::string name, type;
  int body1 = -1, body2 = -1;        ///< indices into Run::bodies; -1 is the world
  Vec3 anchor1 = Vec3::Zero();       ///< body1 frame
  Vec3 anchor2 = Vec3::Zero();       ///< body2 frame (world frame for the world)
  std::optional<Vec3> axis1, axis2;  ///< hinge and slider joints
};

struct RunContact {
  int body1 = -1, body2 = -1;
  Vec3 point = Vec3::Zero(), normal = Vec3::UnitZ();
  double depth = 0.0, normal_impulse = 0.0;
};

/// One recorded instant. Vectors are indexed like Run::bodies and Run::joints.
struct Frame {
  double time = 0.0;
  std::vector<Pose> poses;
  std::vector<Vec3> linear_velocity, angular_velocity;
  std::vector<double> joint_coordinate;  ///< NaN for joints without one
  std::vector<double> joint_error;
  std::vector<RunContact> contacts;  ///< empty unless the run wrote contacts.csv
  double kinetic_energy = 0.0, potential_energy = 0.0, residual = 0.0;
  int solver_iterations = 0;
};

struct Run {
  std::filesystem::path dir;
  std::string source;  ///< the scene file the run came from
  Vec3 gravity = Vec3::Zero();
  double timestep = 0.0;
  int every = 1;
  std::optional<SceneView> view;
  std::vector<RunBody> bodies;
  std::vector<RunJoint> joints;
  std::vector<Frame> frames;
  bool has_contacts = false;
  /// The files ended part-way through a frame (a run killed while writing it): the frames every
  /// file holds in full were read, the rest left out.
  bool truncated = false;
  /// Each CSV file read (by its name in the folder) and its size up to the end of the last frame
  /// read: what a file torn by a kill is cut back to (openRun).
  std::map<std::string, std::uint64_t> whole_bytes;
};

/// Reads a `linx run` output folder, also one whose run was killed or stopped part-way (the
/// complete frames). Throws RunError naming the file, the field or line, and the problem (a
/// missing scene.json says to rerun with a linx that writes it).
Run readRun(const std::filesystem::path& dir);

/// Reads a run folder as a linx command opens it: first, unless a run or recording is writing the
/// folder (holds its lock, io::tryLockFolder), the rows that a killed run left after its last
/// whole frame (a torn row, a frame not in every file) are cut off, each CSV file truncated to
/// the frames readRun reads, so that other readers (pandas, numpy) see whole rows only. A note
/// on stderr names each file cut. A folder that cannot be written is read as it is.
Run openRun(const std::filesystem::path& dir);

/// World position of a point given in body `body`'s frame (the world frame for -1) at `frame`.
Vec3 worldPoint(const Frame& frame, int body, const Vec3& local);

}  // namespace linx::viz
