#pragma once

#include "joints/row_parts.hpp"

namespace linx::joints {

class SpringJoint final : public Joint {
 public:
  SpringJoint(const JointDef& def, const BodyState& b1, const BodyState& b2);
  std::string_view type() const override { return "spring"; }
  int maxRows() const override { return kCoordinateRows; }
  int fill(const JointContext& ctx, std::span<Row> rows) const override;
  JointCoordinates coordinates(const BodyState& b1, const BodyState& b2) const override;

 private:
  PointPair points_;
};

}  // namespace linx::joints
