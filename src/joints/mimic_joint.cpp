// Mimic joint: the follower joint's coordinate is held at `ratio` times the leader joint's plus
// `offset` (URDF's <mimic>: two fingers of a gripper, a gear train written as joints). Each
// coordinate is its joint's own (Joint::coordinateRow, with its reference), between that joint's
// two bodies, so the row acts on up to four bodies: the follower's body 1 and 2 (a, b) and the
// leader's (c, d); assembly folds a body the two joints share (the palm both fingers hang on)
// into one block. 1 row:
//   C = q_f - ratio q_l - offset = 0        J = [ J_f | -ratio J_l ]
// q's rate is its coordinate row's J u, exactly: the row holds the coupling whatever the bodies
// the two joints hang on do (a gripper on a moving arm).
#include "joints/mimic_joint.hpp"

#include <fmt/format.h>

#include <stdexcept>

namespace linx::joints {

namespace {
/// Whether `j` has a coordinate row to tie (the answer does not depend on the states).
bool hasCoordinateRow(const Joint& j) {
  Row probe;
  return j.freeCoordinates() > 0 && j.coordinateRow(JointContext{}, 0, probe);
}
}  // namespace

MimicJoint::MimicJoint(const JointDef& def, const Joint& leader, const Joint& follower)
    : Joint(def), leader_(&leader), follower_(&follower) {
  if (&leader == &follower) throw std::invalid_argument("leader and follower: the same joint");
  for (const auto& [field, j] : {std::pair{"leader", &leader}, std::pair{"follower", &follower}})
    if (!hasCoordinateRow(*j))
      throw std::invalid_argument(
          fmt::format("{}: joint '{}' is a {} joint; a mimic joint ties hinges and sliders", field,
                      j->name(), j->type()));
}

int MimicJoint::fill(const JointContext& ctx, std::span<Row> rows) const {
  // The follower's bodies are this joint's (ctx.b1, ctx.b2); the leader's come in ctx.more.
  JointContext at_leader = ctx;
  at_leader.b1 = ctx.more[0];
  at_leader.b2 = ctx.more[1];
  Row follower, leader;
  follower_->coordinateRow(ctx, 0, follower);
  leader_->coordinateRow(at_leader, 0, leader);
  const double ratio = def().ratio;
  const auto reference = [](const Joint& j) { return j.def().coordinates[0].reference; };
  Row& row = rows[0];
  row.Ja = follower.Ja;
  row.Jb = follower.Jb;
  row.Jc = -ratio * leader.Ja;
  row.Jd = -ratio * leader.Jb;
  row.phi = (follower.phi + reference(*follower_)) - ratio * (leader.phi + reference(*leader_)) -
            def().offset;
  row.kind = RowKind::Bilateral;
  row.key = 0;
  return 1;
}

}  // namespace linx::joints
