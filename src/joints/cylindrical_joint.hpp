#pragma once

#include "joints/row_parts.hpp"

namespace linx::joints {

class CylindricalJoint final : public Joint {
 public:
  CylindricalJoint(const JointDef& def, const BodyState& b1, const BodyState& b2);
  std::string_view type() const override { return "cylindrical"; }
  int maxRows() const override { return 4 + 2 * kCoordinateRows; }  // + position's, angle's rows
  int fill(const JointContext& ctx, std::span<Row> rows) const override;
  JointCoordinates coordinates(const BodyState& b1, const BodyState& b2) const override;
  void track(const BodyState& b1, const BodyState& b2) override;

 protected:
  void persistTracked(state::Archive& archive) override;

 private:
  double angle(const BodyState& b1, const BodyState& b2) const;

  JointFrames frames_;
  double last_angle_ = 0.0;  // the angle at the last track(): the branch to unwrap onto
};

}  // namespace linx::joints
