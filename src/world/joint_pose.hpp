// Setting a joint's coordinate by moving one side of the mechanism (World::setJointCoordinate).
#pragma once

#include <linx/body.hpp>
#include <linx/joint.hpp>

#include <memory>
#include <span>

namespace linx {

/// Moves body1 of `joints[joint]`, and rigidly with it every body joined to it other than through
/// that joint, so that the joint's free coordinate `coordinate` reads `value` (raw, without its
/// reference) and its other free coordinates and equality rows keep theirs. Throws
/// std::invalid_argument as World::setJointCoordinate says.
void moveToCoordinate(std::span<Body> bodies, std::span<const std::unique_ptr<Joint>> joints,
                      std::size_t joint, int coordinate, double value);

}  // namespace linx
