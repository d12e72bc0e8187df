#pragma once

#include "joints/row_parts.hpp"

namespace linx::joints {

class BallJoint final : public Joint {
 public:
  BallJoint(const JointDef& def, const BodyState& b1, const BodyState& b2);
  std::string_view type() const override { return "ball"; }
  int maxRows() const override { return 4; }
  int fill(const JointContext& ctx, std::span<Row> rows) const override;
  void curvature(const JointContext& ctx, std::span<const Row> rows,
                 std::span<double> out) const override;
  Mat12 stiffness(const JointContext& ctx, std::span<const Row> rows,
                  std::span<const double> lambda) const override;
  JointCoordinates coordinates(const BodyState& b1, const BodyState& b2) const override;

 private:
  JointFrames frames_;
};

}  // namespace linx::joints
