// What the engine refuses in an imported model, named by the model's own elements.
#pragma once

#include <linx/scene.hpp>

#include <string_view>

namespace linx::io {

/// Completes an imported scene's mass properties as the scene reader does (a body given by its
/// shapes' densities gets their mass, centre and inertia: completeMassProperties), then builds it
/// once, so that a body or joint that World refuses (a bad inertia, a degenerate hull, a joint on
/// one body twice) is reported as `ELEMENT 'name'` of the model file (`link 'arm'`, `body
/// 'torso'`, `joint 'knee'`) rather than by its place in the Scene. Throws SceneError.
void completeImported(Scene& scene, std::string_view body_element);

}  // namespace linx::io
