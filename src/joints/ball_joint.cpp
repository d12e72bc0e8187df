// Ball-and-socket (point) joint: the anchor points of both bodies coincide. 3 rows.
//   C = (p1 + r1) - (p2 + r2) = 0
//   J = [ E, -[r1]x | -E, [r2]x ]  (row k: [ e_k, r1 x e_k | -e_k, -(r2 x e_k) ])
// Coordinate: the angle of the relative rotation since creation (rad, >= 0).
#include "joints/ball_joint.hpp"

#include "math/rotation.hpp"

namespace linx::joints {

BallJoint::BallJoint(const JointDef& def, const BodyState& b1, const BodyState& b2)
    : Joint(def), frames_(JointFrames::capture(def, b1, b2)) {}

int BallJoint::fill(const JointContext& ctx, std::span<Row> rows) const {
  pointRows(Arms::of(frames_, ctx.b1, ctx.b2), rows.first<3>());
  for (int k = 0; k < 3; ++k) rows[k].key = k;
  return 3;
}

JointCoordinates BallJoint::coordinates(const BodyState& b1, const BodyState& b2) const {
  return JointCoordinates::Constant(1, math::logMap(relativeRotation(frames_, b1, b2)).norm());
}

Mat12 BallJoint::stiffness(const JointContext& ctx, std::span<const Row> rows,
                           std::span<const double> lambda) const {
  Mat12 k = Mat12::Zero();
  addPointStiffness(Arms::of(frames_, ctx.b1, ctx.b2), pointImpulse(rows, lambda), k);
  return k;
}

}  // namespace linx::joints
