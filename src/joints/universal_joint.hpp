#pragma once

#include "joints/row_parts.hpp"

namespace linx::joints {

class UniversalJoint final : public Joint {
 public:
  UniversalJoint(const JointDef& def, const BodyState& b1, const BodyState& b2);
  std::string_view type() const override { return "universal"; }
  int maxRows() const override { return 4 + 2 * kCoordinateRows; }  // + the two angles' rows
  int fill(const JointContext& ctx, std::span<Row> rows) const override;
  void curvature(const JointContext& ctx, std::span<const Row> rows,
                 std::span<double> out) const override;
  Mat12 stiffness(const JointContext& ctx, std::span<const Row> rows,
                  std::span<const double> lambda) const override;
  JointCoordinates coordinates(const BodyState& b1, const BodyState& b2) const override;
  void track(const BodyState& b1, const BodyState& b2) override;

 protected:
  void persistTracked(state::Archive& archive) override;

 private:
  Eigen::Vector2d angles(const BodyState& b1, const BodyState& b2) const;

  JointFrames frames_;
  Cross cross_;
  Eigen::Vector2d last_ = Eigen::Vector2d::Zero();  // the angles at the last track()
};

}  // namespace linx::joints
