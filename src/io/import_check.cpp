#include "io/import_check.hpp"

#include <linx/mass_properties.hpp>

#include <fmt/format.h>

#include <algorithm>
#include <stdexcept>

namespace linx::io {

void completeImported(Scene& scene, std::string_view body_element) {
  World world(scene.settings);
  for (BodyDef& body : scene.bodies) {
    try {
      completeMassProperties(body);
      world.createBody(body);
    } catch (const std::invalid_argument& e) {
      throw SceneError(scene.file, fmt::format("{} '{}'", body_element, body.name), e.what());
    }
  }
  for (const SceneJoint& joint : scene.joints) {
    try {
      world.createJoint(joint.type, joint.def);
    } catch (const std::invalid_argument& e) {
      throw SceneError(scene.file, fmt::format("joint '{}'", joint.def.name), e.what());
    }
  }
  for (const ActuatorDef& actuator : scene.actuators) {
    try {
      world.createActuator(actuator);
    } catch (const std::invalid_argument& e) {
      throw SceneError(scene.file, fmt::format("actuator '{}'", actuator.name), e.what());
    }
  }
}

// As the scene builder's start check: rounding, not a modelling choice.
constexpr double kStartTolerance = 1e-6;

std::optional<StartOutside> startInsideLimits(CoordinateDef& c, std::string joint, bool angular) {
  if (!c.limits || c.initial || c.locked) return std::nullopt;
  const double start = c.reference;  // the coordinate is zero where the model is built
  const JointLimits& l = *c.limits;
  if (start >= l.lower - kStartTolerance && start <= l.upper + kStartTolerance) return std::nullopt;
  c.initial = std::clamp(start, l.lower, l.upper);
  return StartOutside{std::move(joint), start, l.lower, l.upper, angular};
}

std::string startOutsideWarning(std::span<const StartOutside> joints) {
  constexpr std::size_t kNamed = 4;
  std::string list;
  for (std::size_t k = 0; k < std::min(joints.size(), kNamed); ++k) {
    const StartOutside& j = joints[k];
    const char* unit = j.angular ? "rad" : "m";
    list += fmt::format("{}'{}' at {:.6g} {}, range [{:.6g}, {:.6g}]", k ? "; " : "", j.joint,
                        j.start, unit, j.lower, j.upper);
  }
  if (joints.size() > kNamed) list += fmt::format("; and {} more", joints.size() - kNamed);
  const bool one = joints.size() == 1;
  return fmt::format(
      "{} outside {} range, moved to the nearest bound (the bodies placed there at "
      "rest, as MuJoCo and PyBullet load it): {}",
      one ? "1 joint starts" : fmt::format("{} joints start", joints.size()), one ? "its" : "their",
      list);
}

}  // namespace linx::io
