#pragma once

#include "joints/row_parts.hpp"

namespace linx::joints {

class RackPinionJoint final : public Joint {
 public:
  RackPinionJoint(const JointDef& def, const BodyState& b1, const BodyState& b2);
  std::string_view type() const override { return "rack_and_pinion"; }
  int maxRows() const override { return 1; }
  int fill(const JointContext& ctx, std::span<Row> rows) const override;
  JointCoordinates coordinates(const BodyState& b1, const BodyState& b2) const override;
  void track(const BodyState& b1, const BodyState& b2) override;

 protected:
  void persistTracked(state::Archive& archive) override;

 private:
  /// The pinion's turn about its axle since creation, unwrapped, and the rack's travel along its
  /// direction; `rate1`: the direction of the turn's rate.
  Eigen::Vector2d travel(const BodyState& b1, const BodyState& b2, Vec3* rate1 = nullptr) const;

  Vec3 axis1_, axis2_;  // world frame at creation
  Quat start1_;
  Vec3 start2_;
  double last_ = 0.0;  // the pinion's last angle
};

}  // namespace linx::joints
