// JSON scene files (docs/scene-format.md): reading, validating and building a World from them.
#pragma once

#include <linx/actuator.hpp>
#include <linx/body.hpp>
#include <linx/joint.hpp>
#include <linx/loads.hpp>
#include <linx/world.hpp>

#include <filesystem>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace linx {

/// A bad scene: which file, which field (a path such as `bodies[2].mass`) and what is wrong.
/// what() is the one-line message "FILE: FIELD: PROBLEM".
class SceneError : public std::runtime_error {
 public:
  SceneError(std::string file, std::string field, std::string problem);
  const std::string& file() const { return file_; }
  const std::string& field() const { return field_; }
  const std::string& problem() const { return problem_; }

 private:
  std::string file_, field_, problem_;
};

struct SceneJoint {
  std::string type;  ///< "fixed", "slider", "hinge", "ball"
  JointDef def;      ///< body ids index Scene::bodies in order
};

/// A top-level force or torque of a scene file, with its place in the file (for messages).
struct SceneLoad {
  std::string field;  ///< "forces[2]", "torques[0]"
  LoadDef def;
};

/// The camera of pictures and of the viewer (`view` in a scene file). Fields left out are chosen
/// from the scene's bounding box when a picture is made (docs/visualization.md, "Camera").
struct SceneView {
  std::optional<Vec3> eye;     ///< camera position (m)
  std::optional<Vec3> target;  ///< the point looked at (m)
  std::optional<Vec3> up;      ///< unit; default: against gravity
  double fov = 40.0;           ///< vertical field of view (degrees), in (0, 180)
};

/// A validated scene: everything needed to build a World and run it.
struct Scene {
  std::string file;  ///< where it came from (for messages)
  WorldSettings settings;
  double duration = 1.0;  ///< (s)
  std::vector<BodyDef> bodies;
  std::vector<SceneJoint> joints;
  /// Top-level springs: spring joints (type "spring"), created after `joints`.
  std::vector<SceneJoint> springs;
  std::vector<SceneLoad> loads;  ///< top-level forces and torques
  /// Actuators on the joints' coordinates (their joint ids index `joints`), created after them.
  std::vector<ActuatorDef> actuators;
  std::optional<SceneView> view;
  /// What the file held that linx does not use (an imported model's unsupported elements), one
  /// line each, to be shown to the user.
  std::vector<std::string> warnings;
};

/// How model and scene files are read (loadScene, loadModel, importUrdf, importMjcf).
struct ImportOptions {
  /// URDF: the root link is a free body (a mobile robot, a dropped object) instead of being fixed
  /// to the world.
  bool floating_base = false;
  /// Read files the model names (meshes, tables, includes) outside the model file's folder too
  /// (`--allow-outside-paths`); by default such a file is refused.
  bool allow_outside_paths = false;
};

/// Reads and validates a scene file (at most 256 MiB, docs/reliability.md). Throws SceneError.
Scene loadScene(const std::filesystem::path& path, const ImportOptions& options = {});
/// Parses and validates scene text; `file` names it in messages and is where files it names are
/// looked for. Throws SceneError.
Scene parseScene(std::string_view text, const std::string& file, const ImportOptions& options = {});
/// The scene as the text of a scene file (docs/scene-format.md) that parseScene reads back to a
/// scene whose world behaves the same to the bit: meshes inline, tables from CSV files inline,
/// defaults left out. Throws std::runtime_error naming a field no scene file can hold.
std::string writeSceneJson(const Scene& scene);
/// Builds the world (bodies in order, then joints, springs, actuators and loads). Throws SceneError.
World buildWorld(const Scene& scene);

/// The resolved scene of a run as the text of `scene.json` (docs/scene-format.md, "Outputs"):
/// bodies with their shapes (hulls and meshes as triangles), joints with their anchors and axes in
/// the bodies' frames, and the view. `world` is buildWorld(scene) before its first step; `every`
/// is the run's recording interval (steps per frame).
std::string runSceneJson(const Scene& scene, const World& world, int every);

}  // namespace linx
