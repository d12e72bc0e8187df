// Hinge (revolute) joint: a common anchor and a common axis a. 5 rows, plus the rows of what acts
// on the angle.
//   point:  C = (p1 + r1) - (p2 + r2) = 0                      J = [ E, -[r1]x | -E, [r2]x ]
//   align:  C_j = t_j . (a2 x a1) = 0, t_1, t_2 _|_ a2          J_j = [ 0, t_j | 0, -t_j ]
//   angle:  theta = twist of q2^-1 q1 q0^-1 about a (body 1 relative to body 2, right-hand rule
//           about the axis, zero at creation), J = [ 0, a | 0, -a ]; unwrapped onto the branch
//           nearest the angle of the last step, so it counts turns and limits may lie past +-pi
//   limits, motor, spring, friction on theta: joints/row_parts.hpp, coordinateRows
#include "joints/hinge_joint.hpp"

#include "world/state_archive.hpp"

#include <cmath>

namespace linx::joints {

HingeJoint::HingeJoint(const JointDef& def, const BodyState& b1, const BodyState& b2)
    : Joint(def), frames_(JointFrames::capture(def, b1, b2)) {}

double HingeJoint::angle(const BodyState& b1, const BodyState& b2) const {
  return axisAngle(frames_, b1, b2, last_angle_);
}

JointCoordinates HingeJoint::coordinates(const BodyState& b1, const BodyState& b2) const {
  return JointCoordinates::Constant(1, angle(b1, b2));
}

bool HingeJoint::coordinateRow(const JointContext& ctx, int index, Row& row) const {
  if (index != 0) return false;
  angularRow(ctx.b2.pose.orientation * frames_.axis2, angle(ctx.b1, ctx.b2), row);
  return true;
}

void HingeJoint::track(const BodyState& b1, const BodyState& b2) {
  last_angle_ = angle(b1, b2);
}

void HingeJoint::persistTracked(state::Archive& a) {
  a(last_angle_);
}

int HingeJoint::fill(const JointContext& ctx, std::span<Row> rows) const {
  pointRows(Arms::of(frames_, ctx.b1, ctx.b2), rows.subspan<0, 3>());
  alignRows(frames_, ctx.b1, ctx.b2, rows.subspan<3, 2>());
  for (int k = 0; k < 5; ++k) rows[k].key = k;
  if (def().coordinates[0].empty()) return 5;  // the angle only serves its rows

  const Vec3 axis = ctx.b2.pose.orientation * frames_.axis2;
  const double theta = angle(ctx.b1, ctx.b2);
  constexpr double kMargins[] = {kAngularLimitMargin};
  return freeCoordinateRows(
      ctx, def(), kMargins, [&](std::size_t, Row& row) { angularRow(axis, theta, row); }, rows, 5);
}

void HingeJoint::curvature(const JointContext& ctx, std::span<const Row> rows,
                           std::span<double> out) const {
  const Vec3 point = pointCurvature(Arms::of(frames_, ctx.b1, ctx.b2), ctx.b1, ctx.b2);
  Vec3 t[2];
  frames_.tangents(ctx.b2, t[0], t[1]);
  // The angle's rows (its limits, lock, prescribed motion) turn about body 2's axis.
  const double angle = turningCurvature(ctx.b2.pose.orientation * frames_.axis2, ctx.b1, ctx.b2);
  curvatureBySlot(rows, out, [&](int slot) {
    return slot < 3   ? point[slot]
           : slot < 5 ? turningCurvature(t[slot - 3], ctx.b1, ctx.b2)
                      : coordinateRowSign(slot) * angle;
  });
}

Mat12 HingeJoint::stiffness(const JointContext& ctx, std::span<const Row> rows,
                            std::span<const double> lambda) const {
  // Slots 0-2: the point; the others (align, the limits, the motor) turn with body 2.
  Vec3 impulse = Vec3::Zero(), torque = Vec3::Zero();
  for (std::size_t m = 0; m < rows.size(); ++m) {
    if ((rows[m].key & 0xff) < 3)
      impulse += lambda[m] * rows[m].Ja.head<3>();
    else
      torque += lambda[m] * rows[m].Ja.tail<3>();
  }
  Mat12 k = Mat12::Zero();
  addPointStiffness(Arms::of(frames_, ctx.b1, ctx.b2), impulse, k);
  addBody2AxisStiffness(torque, k);
  return k;
}

}  // namespace linx::joints
