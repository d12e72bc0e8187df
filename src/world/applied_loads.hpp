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
  int count() const { return static_cast<int>(loads_.size()); }

 private:
  struct Load {
    int body;
    VectorSignal force, torque;
    std::optional<Vec3> point;  // in the body's frame
  };
  std::vector<Load> loads_;
};

}  // namespace linx
