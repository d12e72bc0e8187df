// Mimic joints that follow each other round a cycle (a follows b, b follows a): each holds its
// follower at r times its leader, so a cycle holds its joints at zero unless the ratios multiply to
// 1, freezing the mechanism. The scene reader and the URDF importer refuse one, naming it alike.
#pragma once

#include <linx/scene.hpp>

#include <cstddef>
#include <optional>
#include <string>

namespace linx::io {

struct MimicCycle {
  std::size_t mimic;    ///< the index in Scene::joints of the mimic joint the cycle is named from
  std::string problem;  ///< "the mimic joints form a cycle ('a' follows 'b', 'b' follows 'a'): ..."
};

/// The first cycle of the scene's mimic joints (followers to leaders, from the first mimic joint
/// in the scene's order), or nullopt. Linear in the number of joints.
std::optional<MimicCycle> findMimicCycle(const Scene& scene);

}  // namespace linx::io
