// Random body states for the tests that check a joint's rows against their own definition at
// arbitrary poses (test_row_parts, test_geometric_stiffness).
#pragma once

#include <linx/joint.hpp>

#include "math/rotation.hpp"

#include <random>

namespace linx::test {

/// A vector with coordinates uniform in [-scale, scale].
inline Vec3 randomVec(std::mt19937& rng, double scale) {
  std::uniform_real_distribution<double> u(-scale, scale);
  return Vec3(u(rng), u(rng), u(rng));
}

/// A pose within a metre of the origin, any orientation, and velocities of order one.
inline BodyState randomState(std::mt19937& rng) {
  return BodyState{Pose{randomVec(rng, 1.0), math::expMap(randomVec(rng, 2.0))},
                   randomVec(rng, 1.0), randomVec(rng, 2.0)};
}

}  // namespace linx::test
