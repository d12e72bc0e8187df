#pragma once

#include "joints/row_parts.hpp"

namespace linx::joints {

class DistanceJoint final : public Joint {
 public:
  DistanceJoint(const JointDef& def, const BodyState& b1, const BodyState& b2);
  std::string_view type() const override { return "distance"; }
  int maxRows() const override { return 1; }
  int fill(const JointContext& ctx, std::span<Row> rows) const override;
  void curvature(const JointContext& ctx, std::span<const Row> rows,
                 std::span<double> out) const override;
  JointCoordinates coordinates(const BodyState& b1, const BodyState& b2) const override;

 private:
  PointPair points_;
  double length_ = 0.0;
};

}  // namespace linx::joints
