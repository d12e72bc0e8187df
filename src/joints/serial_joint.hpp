#pragma once

#include "joints/row_parts.hpp"

#include <vector>

namespace linx::joints {

class SerialJoint final : public Joint {
 public:
  SerialJoint(const JointDef& def, const BodyState& b1, const BodyState& b2);
  std::string_view type() const override { return "serial"; }
  int maxRows() const override {
    const int k = static_cast<int>(axes_.size());
    return (6 - k) + k * kCoordinateRows;  // the held directions, + the coordinates' rows
  }
  int fill(const JointContext& ctx, std::span<Row> rows) const override;
  JointCoordinates coordinates(const BodyState& b1, const BodyState& b2) const override;
  void track(const BodyState& b1, const BodyState& b2) override;

 protected:
  void persistTracked(state::Archive& archive) override;

 public:
  /// One hinge or slide, in body 1's frame at creation.
  struct Axis {
    bool linear = false;
    Vec3 direction = Vec3::UnitZ();  ///< unit
    Vec3 point = Vec3::Zero();       ///< on a hinge's axis
  };
  /// Twists (angular, linear) of body 1 relative to body 2, world frame, linear part at a point:
  /// a column per axis.
  using Twists = Eigen::Matrix<double, 6, Eigen::Dynamic, 0, 6, kMaxCoordinates>;
  /// A basis of the directions the joint holds: (angular, linear) rows' weights.
  using Held = Eigen::Matrix<double, 6, Eigen::Dynamic, 0, 6, 6>;

 private:
  /// The coordinates that put the chain nearest body 1 (least squares), from `last_`, with the
  /// axes' twists at body 1's centre and what is left between the chain's end and body 1.
  struct Fit {
    JointCoordinates q;
    Twists twists;  // at body 1's centre of mass
    Vec6 residual;  // (rotation vector, displacement) from the chain's end to body 1, world frame
  };
  Fit fit(const BodyState& b1, const BodyState& b2) const;
  /// The held directions at this fit: `held_` (body 1's frame) turned to the world and made
  /// orthogonal to the axes' twists, orthonormal (the basis nearest the last one: it turns
  /// smoothly with the mechanism, so its rows keep their meaning from step to step).
  Held held(const Fit& fit, const BodyState& b1) const;
  /// The orthonormal basis nearest `a`'s columns (independent): a (a^T a)^-1/2.
  static Held orthonormalized(const Held& a);

  std::vector<Axis> axes_;
  Quat rest_rotation_ = Quat::Identity();  // body 1 in body 2's frame at creation
  Vec3 rest_offset_ = Vec3::Zero();
  JointCoordinates last_;  // the coordinates at the last track()
  Held held_;              // the held directions at the last track(), body 1's frame
};

}  // namespace linx::joints
