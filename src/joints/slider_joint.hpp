#pragma once

#include "joints/row_parts.hpp"

namespace linx::joints {

class SliderJoint final : public Joint {
 public:
  SliderJoint(const JointDef& def, const BodyState& b1, const BodyState& b2);
  std::string_view type() const override { return "slider"; }
  int maxRows() const override { return 5 + kCoordinateRows; }  // + the position's rows
  int fill(const JointContext& ctx, std::span<Row> rows) const override;
  void curvature(const JointContext& ctx, std::span<const Row> rows,
                 std::span<double> out) const override;
  JointCoordinates coordinates(const BodyState& b1, const BodyState& b2) const override;
  bool coordinateRow(const JointContext& ctx, int index, Row& row) const override;

 private:
  JointFrames frames_;
};

}  // namespace linx::joints
