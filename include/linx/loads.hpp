// Loads applied to bodies at every step: a force (at a point) and a torque, constant or given in
// time (World::addLoad; "forces" and "torques" in a scene file).
#pragma once

#include <linx/body.hpp>
#include <linx/signal.hpp>

#include <optional>

namespace linx {

/// A force and a torque on one body, in the world frame, applied at every step (their values at the
/// step's start) on top of gravity and of what Body::applyForce adds.
struct LoadDef {
  BodyId body;              ///< must be a dynamic body
  VectorSignal force = {};  ///< (N), world frame
  /// Where the force acts (m), world frame at creation, carried by the body from then on; default
  /// its centre of mass (no torque).
  std::optional<Vec3> point = std::nullopt;
  VectorSignal torque = {};  ///< (N m), world frame
};

struct LoadId {
  int index = -1;
  friend bool operator==(LoadId, LoadId) = default;
};

}  // namespace linx
