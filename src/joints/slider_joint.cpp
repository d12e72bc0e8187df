// Slider (prismatic) joint: relative rotation locked, relative translation only along the axis n
// (fixed in body 2). 5 rows, plus the rows of what acts on the position.
// The anchor points, coincident at creation, separate by d = (p1 + r1) - (p2 + r2):
//   lock:    C = R2 log(q2^-1 q1 q0^-1) = 0                   J_k = [ 0, e_k | 0, -e_k ]
//   linear:  C_j = t_j . d = 0, t_1, t_2 _|_ n, fixed in body 2
//            J_j = [ t_j, r1 x t_j | -t_j, -(r2 + d) x t_j ]   (exact: the rows stay right when
//            both bodies rotate together, because t_j turns with body 2)
//   position s = n . d (body 1 relative to body 2 along n, m, zero at creation), same J form
//   limits, motor, spring, friction on s: joints/row_parts.hpp, coordinateRows
#include "joints/slider_joint.hpp"

namespace linx::joints {

SliderJoint::SliderJoint(const JointDef& def, const BodyState& b1, const BodyState& b2)
    : Joint(def), frames_(JointFrames::capture(def, b1, b2)) {}

JointCoordinates SliderJoint::coordinates(const BodyState& b1, const BodyState& b2) const {
  const Arms arms = Arms::of(frames_, b1, b2);
  return JointCoordinates::Constant(1, (b2.pose.orientation * frames_.axis2).dot(arms.d));
}

bool SliderJoint::coordinateRow(const JointContext& ctx, int index, Row& row) const {
  if (index != 0) return false;
  linearRow(Arms::of(frames_, ctx.b1, ctx.b2), ctx.b2.pose.orientation * frames_.axis2, row);
  return true;
}

int SliderJoint::fill(const JointContext& ctx, std::span<Row> rows) const {
  lockRows(frames_, ctx.b1, ctx.b2, rows.subspan<0, 3>());
  const Arms arms = Arms::of(frames_, ctx.b1, ctx.b2);
  Vec3 t1, t2;
  frames_.tangents(ctx.b2, t1, t2);
  linearRow(arms, t1, rows[3]);
  linearRow(arms, t2, rows[4]);
  for (int k = 0; k < 5; ++k) rows[k].key = k;

  const Vec3 n = ctx.b2.pose.orientation * frames_.axis2;
  constexpr double kMargins[] = {kLinearLimitMargin};
  return freeCoordinateRows(
      ctx, def(), kMargins, [&](std::size_t, Row& row) { linearRow(arms, n, row); }, rows, 5);
}

void SliderJoint::curvature(const JointContext& ctx, std::span<const Row> rows,
                            std::span<double> out) const {
  const Arms arms = Arms::of(frames_, ctx.b1, ctx.b2);
  Vec3 t[2];
  frames_.tangents(ctx.b2, t[0], t[1]);
  // The position's rows (its limits, lock, prescribed motion) run along body 2's axis.
  const double position =
      linearCurvature(arms, ctx.b2.pose.orientation * frames_.axis2, ctx.b1, ctx.b2);
  curvatureBySlot(rows, out, [&](int slot) {
    return slot < 3   ? 0.0  // the lock rows' axes are the world's
           : slot < 5 ? linearCurvature(arms, t[slot - 3], ctx.b1, ctx.b2)
                      : coordinateRowSign(slot) * position;
  });
}

}  // namespace linx::joints
