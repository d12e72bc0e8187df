// Fixed (weld) joint: the two bodies keep their relative pose of creation. 6 rows.
//   point: C = (p1 + r1) - (p2 + r2) = 0           J = [ E, -[r1]x | -E, [r2]x ]
//   lock:  C = R2 log(q2^-1 q1 q0^-1) = 0           J = [ 0, E | 0, -E ]
// No free coordinate.
#include "joints/fixed_joint.hpp"

namespace linx::joints {

FixedJoint::FixedJoint(const JointDef& def, const BodyState& b1, const BodyState& b2)
    : Joint(def), frames_(JointFrames::capture(def, b1, b2)) {}

int FixedJoint::fill(const JointContext& ctx, std::span<Row> rows) const {
  pointRows(Arms::of(frames_, ctx.b1, ctx.b2), rows.subspan<0, 3>());
  lockRows(frames_, ctx.b1, ctx.b2, rows.subspan<3, 3>());
  for (int k = 0; k < 6; ++k) rows[k].key = k;
  return 6;
}

void FixedJoint::curvature(const JointContext& ctx, std::span<const Row> rows,
                           std::span<double> out) const {
  const Vec3 point = pointCurvature(Arms::of(frames_, ctx.b1, ctx.b2), ctx.b1, ctx.b2);
  curvatureBySlot(rows, out, [&](int slot) {
    return slot < 3 ? point[slot] : 0.0;  // the lock rows' axes are the world's
  });
}

Mat12 FixedJoint::stiffness(const JointContext& ctx, std::span<const Row> rows,
                            std::span<const double> lambda) const {
  // The lock rows' axes are the world's: they do not turn.
  Mat12 k = Mat12::Zero();
  addPointStiffness(Arms::of(frames_, ctx.b1, ctx.b2), pointImpulse(rows, lambda), k);
  return k;
}

}  // namespace linx::joints
