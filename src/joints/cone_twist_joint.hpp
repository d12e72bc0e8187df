#pragma once

#include "joints/row_parts.hpp"

namespace linx::joints {

class ConeTwistJoint final : public Joint {
 public:
  ConeTwistJoint(const JointDef& def, const BodyState& b1, const BodyState& b2);
  std::string_view type() const override { return "cone_twist"; }
  int maxRows() const override { return 3 + 1 + kCoordinateRows; }  // + cone, twist's rows
  int fill(const JointContext& ctx, std::span<Row> rows) const override;
  JointCoordinates coordinates(const BodyState& b1, const BodyState& b2) const override;
  void track(const BodyState& b1, const BodyState& b2) override;

 protected:
  void persistTracked(state::Archive& archive) override;

 private:
  double twist(const BodyState& b1, const BodyState& b2) const;
  /// The cone row: C = swing - its bound in the swing's direction (<= 0 inside), exact J.
  void coneRow(const BodyState& b1, const BodyState& b2, Row& row) const;

  JointFrames frames_;  // anchor, twist axis in each body, tangent1 along axis2 in body 2
  double last_twist_ = 0.0;
};

}  // namespace linx::joints
