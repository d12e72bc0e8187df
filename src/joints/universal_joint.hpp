#pragma once

#include "joints/row_parts.hpp"

namespace linx::joints {

class UniversalJoint final : public Joint {
 public:
  UniversalJoint(const JointDef& def, const BodyState& b1, const BodyState& b2);
  std::string_view type() const override { return "universal"; }
  int maxRows() const override { return 4; }
  int fill(const JointContext& ctx, std::span<Row> rows) const override;
  Mat12 stiffness(const JointContext& ctx, std::span<const Row> rows,
                  std::span<const double> lambda) const override;
  /// Two free coordinates: none is reported yet (docs/joints.md).
  std::optional<double> coordinate(const BodyState&, const BodyState&) const override {
    return std::nullopt;
  }

 private:
  JointFrames frames_;
  Vec3 cross1_ = Vec3::UnitZ();  // the cross's arm along body 1's axis, body 1's frame
  Vec3 cross2_ = Vec3::UnitY();  // the arm along body 2's axis, body 2's frame
};

}  // namespace linx::joints
