#pragma once

#include "joints/row_parts.hpp"

namespace linx::joints {

class PlanarJoint final : public Joint {
 public:
  PlanarJoint(const JointDef& def, const BodyState& b1, const BodyState& b2);
  std::string_view type() const override { return "planar"; }
  int maxRows() const override { return 3 + 3 * kCoordinateRows; }  // + x's, y's, angle's rows
  int fill(const JointContext& ctx, std::span<Row> rows) const override;
  JointCoordinates coordinates(const BodyState& b1, const BodyState& b2) const override;
  void track(const BodyState& b1, const BodyState& b2) override;

 protected:
  void persistTracked(state::Archive& archive) override;

 private:
  double angle(const BodyState& b1, const BodyState& b2) const;

  JointFrames frames_;  // axis: the plane's normal; tangent1, tangent2: its x and y, in body 2
  double last_angle_ = 0.0;
};

}  // namespace linx::joints
