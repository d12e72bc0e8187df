#pragma once

#include "joints/row_parts.hpp"

namespace linx::joints {

class GearJoint final : public Joint {
 public:
  GearJoint(const JointDef& def, const BodyState& b1, const BodyState& b2);
  std::string_view type() const override { return "gear"; }
  int maxRows() const override { return 1; }
  int fill(const JointContext& ctx, std::span<Row> rows) const override;
  JointCoordinates coordinates(const BodyState& b1, const BodyState& b2) const override;
  void track(const BodyState& b1, const BodyState& b2) override;

 protected:
  void persistTracked(state::Archive& archive) override;

 private:
  /// Each body's turn about its axis since creation, unwrapped, and its rate's direction.
  Eigen::Vector2d angles(const BodyState& b1, const BodyState& b2, Vec3* rate1 = nullptr,
                         Vec3* rate2 = nullptr) const;

  Vec3 axis1_, axis2_;  // world frame at creation
  Quat start1_, start2_;
  Eigen::Vector2d last_ = Eigen::Vector2d::Zero();
};

}  // namespace linx::joints
