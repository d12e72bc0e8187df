// Models from other formats, read as a Scene (docs/model-import.md): URDF robots and MuJoCo's
// MJCF models. The Scene
// is the same as a scene file's, so every command and buildWorld take it as they are.
#pragma once

#include <linx/scene.hpp>

#include <filesystem>

namespace linx {

/// Reads a URDF robot (through urdfdom): one body per link with its inertial, the link frames at
/// the joints' zero positions, one joint per URDF joint, collision geometry as shapes. Links that
/// a fixed joint attaches and that have no mass become part of their parent. What linx does not
/// use is named in Scene::warnings. Throws SceneError naming the file, the element and the
/// problem.
Scene importUrdf(const std::filesystem::path& path, const ImportOptions& options = {});

/// Reads a MuJoCo MJCF model (a subset, docs/model-import.md): bodies with their inertials or the
/// mass of their geoms at their density, sphere/capsule/cylinder/box/plane geoms (fromto too),
/// hinge, slide, ball and free joints with range, stiffness, damping, frictionloss and ref,
/// default classes, <include>, equality connect and weld. What linx does not use is named in
/// Scene::warnings. Throws SceneError naming the file, the element (and its line) and the problem.
Scene importMjcf(const std::filesystem::path& path, const ImportOptions& options = {});

/// A model file by its extension: `.urdf` (importUrdf), `.xml` (importMjcf), anything else a JSON
/// scene (loadScene). Joints that repeat one another (the same type between the same bodies at
/// the same anchor and axis) are named in Scene::warnings.
Scene loadModel(const std::filesystem::path& path, const ImportOptions& options = {});

}  // namespace linx
