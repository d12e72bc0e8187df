#pragma once

#include <linx/body.hpp>
#include <linx/world.hpp>

#include <span>

namespace linx::dynamics {

/// Kinetic energy and gravitational potential energy (zero at the origin) of a set of bodies (J).
Energy computeEnergy(std::span<const Body> bodies, const Vec3& gravity);

}  // namespace linx::dynamics
