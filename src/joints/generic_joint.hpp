#pragma once

#include "joints/row_parts.hpp"

namespace linx::joints {

class GenericJoint final : public Joint {
 public:
  GenericJoint(const JointDef& def, const BodyState& b1, const BodyState& b2);
  std::string_view type() const override { return "generic"; }
  int maxRows() const override { return 6 * kCoordinateRows; }
  int fill(const JointContext& ctx, std::span<Row> rows) const override;
  JointCoordinates coordinates(const BodyState& b1, const BodyState& b2) const override;
  void track(const BodyState& b1, const BodyState& b2) override;

 protected:
  void persistTracked(state::Archive& archive) override;

 private:
  /// The three angles (rx, ry, rz), unwrapped, and the world-frame rows whose J u are their rates.
  Vec3 angles(const BodyState& b1, const BodyState& b2, Mat3* rates = nullptr) const;

  JointFrames frames_;  // the anchor in each body
  Mat3 axes1_, axes2_;  // the joint's axes (x, y, z as columns) in body 1's and body 2's frame
  Vec3 last_ = Vec3::Zero();  // the angles at the last track()
};

}  // namespace linx::joints
