#pragma once

#include "joints/row_parts.hpp"

namespace linx::joints {

class Hinge2Joint final : public Joint {
 public:
  Hinge2Joint(const JointDef& def, const BodyState& b1, const BodyState& b2);
  std::string_view type() const override { return "hinge2"; }
  int maxRows() const override { return 3 + 3 * kCoordinateRows; }  // + the coordinates' rows
  int fill(const JointContext& ctx, std::span<Row> rows) const override;
  JointCoordinates coordinates(const BodyState& b1, const BodyState& b2) const override;
  void track(const BodyState& b1, const BodyState& b2) override;

 protected:
  void persistTracked(state::Archive& archive) override;

 private:
  Eigen::Vector2d angles(const BodyState& b1, const BodyState& b2) const;

  JointFrames frames_;  // the steering axis as the frames' axis: the tangents lie across it
  Cross cross_;
  Eigen::Vector2d last_ = Eigen::Vector2d::Zero();  // the angles at the last track()
};

}  // namespace linx::joints
