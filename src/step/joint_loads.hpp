// What each joint applied to its first body over the last step: the sum of its rows' impulses
// J^T lambda divided by the length they acted over. The second body got the opposite force and,
// about the common anchor, the opposite torque.
#pragma once

#include <linx/body.hpp>
#include <linx/joint.hpp>
#include <linx/row.hpp>

#include <memory>
#include <span>
#include <vector>

namespace linx::state {
class Archive;
}

namespace linx::step {

class JointLoads {
 public:
  /// From assembled joint rows (keys (joint + 1) << 8 | slot) and their impulses over `h`, with
  /// the bodies at the poses the rows were made at (the torque is taken about the anchor there);
  /// joints without a row here read zero.
  /// With `add`, the loads are added to the ones measured so far (the substeps of one step, each
  /// measured over the whole step's h: their mean).
  void measure(std::span<const Row> rows, std::span<const double> lambda, double h,
               std::span<const std::unique_ptr<Joint>> joints, std::span<const Body> bodies,
               bool add = false);
  /// Joint `joint`'s reaction on its body1, zero before the first step.
  JointReaction of(std::size_t joint) const {
    return joint < loads_.size() ? loads_[joint] : JointReaction{};
  }
  /// Joint `joint` reads zero until the next measure (a removed joint's slot).
  void forget(std::size_t joint) {
    if (joint < loads_.size()) loads_[joint] = JointReaction{};
  }

  /// Reads or writes what carries to the next step (World::saveState).
  void persist(state::Archive& archive);

 private:
  std::vector<JointReaction> loads_, measured_;
};

}  // namespace linx::step
