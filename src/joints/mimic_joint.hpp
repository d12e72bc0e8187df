#pragma once

#include "joints/row_parts.hpp"

namespace linx::joints {

class MimicJoint final : public Joint {
 public:
  /// `def` names `leader` and `follower`; `leader` and `follower` are those joints, which outlive
  /// it (World::removeJoint removes the mimic joints of a joint it removes).
  MimicJoint(const JointDef& def, const Joint& leader, const Joint& follower);
  std::string_view type() const override { return "mimic"; }
  int maxRows() const override { return 1; }
  int fill(const JointContext& ctx, std::span<Row> rows) const override;
  JointCoordinates coordinates(const BodyState&, const BodyState&) const override { return {}; }
  std::array<BodyId, 2> coupledBodies() const override {
    return {leader_->body1(), leader_->body2()};
  }

 private:
  const Joint* leader_;
  const Joint* follower_;
};

}  // namespace linx::joints
