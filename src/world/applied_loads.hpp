// The world's standing loads (World::addLoad): each step, every load's force and torque at the
// step's start, added to its body before the step.
#pragma once

#include <linx/body.hpp>
#include <linx/loads.hpp>

#include <span>
#include <vector>

namespace linx {

class AppliedLoads {
 public:
  /// Throws std::invalid_argument for a body that is not one of `bodies` or is static, a
  /// non-finite point, or a table that validateSignal refuses.
  LoadId add(const LoadDef& def, std::span<const Body> bodies);
  /// Adds each load's force (at its point, as the body carries it) and torque at `time`.
  void apply(std::span<Body> bodies, double time) const;
  /// The loads in effect (the removed ones not counted).
  int count() const { return count_; }
  /// Removes the loads on body `body` (a removed body); the others keep their ids.
  void removeBody(int body);
  /// Removes one load; throws std::out_of_range if it is not one in effect.
  void remove(LoadId id);

 private:
  struct Load {
    int body;  // -1: removed
    VectorSignal force, torque;
    std::optional<Vec3> point;  // in the body's frame
  };
  std::vector<Load> loads_;
  int count_ = 0;
};

}  // namespace linx
