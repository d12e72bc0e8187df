#pragma once

#include "joints/row_parts.hpp"

namespace linx::joints {

class HingeJoint final : public Joint {
 public:
  HingeJoint(const JointDef& def, const BodyState& b1, const BodyState& b2);
  std::string_view type() const override { return "hinge"; }
  int maxRows() const override { return 5 + kCoordinateRows; }  // + the angle's rows
  int fill(const JointContext& ctx, std::span<Row> rows) const override;
  void curvature(const JointContext& ctx, std::span<const Row> rows,
                 std::span<double> out) const override;
  Mat12 stiffness(const JointContext& ctx, std::span<const Row> rows,
                  std::span<const double> lambda) const override;
  JointCoordinates coordinates(const BodyState& b1, const BodyState& b2) const override;
  bool coordinateRow(const JointContext& ctx, int index, Row& row) const override;
  void track(const BodyState& b1, const BodyState& b2) override;

 protected:
  void persistTracked(state::Archive& archive) override;

 private:
  double angle(const BodyState& b1, const BodyState& b2) const;

  JointFrames frames_;
  double last_angle_ = 0.0;  // the angle at the last track(): the branch to unwrap onto
};

}  // namespace linx::joints
