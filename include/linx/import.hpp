// Models from other formats, read as a Scene (docs/model-import.md): URDF robots now. The Scene
// is the same as a scene file's, so every command and buildWorld take it as they are.
#pragma once

#include <linx/scene.hpp>

#include <filesystem>

namespace linx {

struct ImportOptions {
  /// URDF: the root link is a free body (a mobile robot, a dropped object) instead of being fixed
  /// to the world.
  bool floating_base = false;
};

/// Reads a URDF robot (through urdfdom): one body per link with its inertial, the link frames at
/// the joints' zero positions, one joint per URDF joint, collision geometry as shapes. Links that
/// a fixed joint attaches and that have no mass become part of their parent. What linx does not
/// use is named in Scene::warnings. Throws SceneError naming the file, the element and the
/// problem.
Scene importUrdf(const std::filesystem::path& path, const ImportOptions& options = {});

/// A model file by its extension: `.urdf` (importUrdf), anything else a JSON scene (loadScene).
Scene loadModel(const std::filesystem::path& path, const ImportOptions& options = {});

}  // namespace linx
