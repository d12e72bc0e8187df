// What the engine refuses in an imported model, named by the model's own elements.
#pragma once

#include <linx/scene.hpp>

#include <optional>
#include <span>
#include <string>
#include <string_view>

namespace linx::io {

/// Completes an imported scene's mass properties as the scene reader does (a body given by its
/// shapes' densities gets their mass, centre and inertia: completeMassProperties), then builds it
/// once, so that a body or joint that World refuses (a bad inertia, a degenerate hull, a joint on
/// one body twice) is reported as `ELEMENT 'name'` of the model file (`link 'arm'`, `body
/// 'torso'`, `joint 'knee'`) rather than by its place in the Scene. Throws SceneError.
void completeImported(Scene& scene, std::string_view body_element);

/// A joint of an imported model that starts (at its reference) outside its range.
struct StartOutside {
  std::string joint;  ///< as the model file names it
  double start = 0.0, lower = 0.0, upper = 0.0;
  bool angular = true;
};

/// MuJoCo and PyBullet load a model whose joint starts outside its range, and so does linx: the
/// coordinate starts at its nearest bound (CoordinateDef::initial: the scene builder places the
/// bodies there by the model's kinematics, at rest, so no energy is made). Returns what it did,
/// or nothing when `c` starts inside its limits (to rounding) or is given an initial value.
std::optional<StartOutside> startInsideLimits(CoordinateDef& c, std::string joint, bool angular);

/// One warning for all of them, naming the first four: "2 joints start outside their range and
/// start at its nearest bound: 'knee' at 0 rad, range [0.5, 1.2]; ...".
std::string startOutsideWarning(std::span<const StartOutside> joints);

}  // namespace linx::io
