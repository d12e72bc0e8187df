// Builds a World from a validated Scene: bodies in file order (so BodyId{i} is Scene::bodies[i]),
// then joints, springs (spring joints) and standing loads. A definition the engine refuses is
// reported against its place in the file.
#include <linx/scene.hpp>

#include <fmt/format.h>

#include <stdexcept>
#include <string>

namespace linx {

World buildWorld(const Scene& scene) {
  World world(scene.settings);
  for (std::size_t i = 0; i < scene.bodies.size(); ++i) {
    try {
      world.createBody(scene.bodies[i]);
    } catch (const std::invalid_argument& e) {
      throw SceneError(scene.file, fmt::format("bodies[{}]", i), e.what());
    }
  }
  for (std::size_t i = 0; i < scene.joints.size(); ++i) {
    try {
      world.createJoint(scene.joints[i].type, scene.joints[i].def);
    } catch (const std::invalid_argument& e) {
      throw SceneError(scene.file, fmt::format("joints[{}]", i), e.what());
    }
  }
  for (std::size_t i = 0; i < scene.springs.size(); ++i) {
    try {
      world.createJoint(scene.springs[i].type, scene.springs[i].def);
    } catch (const std::invalid_argument& e) {
      throw SceneError(scene.file, fmt::format("springs[{}]", i), e.what());
    }
  }
  // Coordinates that start elsewhere than where the model was built: once every joint is made,
  // so that each moves its whole side of the mechanism.
  for (std::size_t i = 0; i < scene.joints.size(); ++i) {
    const auto& coordinates = scene.joints[i].def.coordinates;
    for (std::size_t c = 0; c < coordinates.size(); ++c) {
      if (!coordinates[c].initial) continue;
      try {
        world.setJointCoordinate(JointId{static_cast<int>(i)}, static_cast<int>(c),
                                 *coordinates[c].initial);
      } catch (const std::invalid_argument& e) {
        throw SceneError(scene.file, fmt::format("joints[{}]", i), e.what());
      }
    }
  }
  for (const SceneLoad& load : scene.loads) {
    try {
      world.addLoad(load.def);
    } catch (const std::invalid_argument& e) {
      throw SceneError(scene.file, load.field, e.what());
    }
  }
  return world;
}

}  // namespace linx
