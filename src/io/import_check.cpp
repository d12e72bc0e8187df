#include "io/import_check.hpp"

#include <linx/mass_properties.hpp>

#include <fmt/format.h>

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
}

}  // namespace linx::io
