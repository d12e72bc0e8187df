// Universal (Cardan, Hooke) joint: a common anchor, and a cross whose two arms turn in body 1
// (along a1) and in body 2 (along a2), perpendicular: body 1 may turn about a1 and about a2, not
// about a1 x a2. 4 rows, plus the rows of what acts on the two angles.
//   point:  C = (p1 + r1) - (p2 + r2) = 0               J = [ E, -[r1]x | -E, [r2]x ]
//   cross:  C = a1 . a2 = 0                             J = [ 0, n | 0, -n ],  n = a1 x a2
//           (d/dt a1 . a2 = (w1 x a1) . a2 + a1 . (w2 x a2) = n . (w1 - w2))
// Coordinates (zero at creation, counting turns): the cross turns in body 2 about a2 by angle2,
// body 1 turns on the cross about a1 by angle1, so w1 - w2 = angle1' a1 + angle2' a2:
//   angle1: J = [ 0, a1 | 0, -a1 ], the arm a2 seen from body 1 turning by -angle1 about a1
//   angle2: J = [ 0, a2 | 0, -a2 ], the arm a1 seen from body 2 turning by angle2 about a2
//   limits, motor, spring, friction on each: joints/row_parts.hpp, coordinateRows
#include "joints/universal_joint.hpp"

#include "world/state_archive.hpp"

namespace linx::joints {

UniversalJoint::UniversalJoint(const JointDef& def, const BodyState& b1, const BodyState& b2)
    : Joint(def),
      frames_(JointFrames::capture(def, b1, b2)),
      cross_(Cross::capture(def.axis, def.axis2, b1, b2)) {}

Eigen::Vector2d UniversalJoint::angles(const BodyState& b1, const BodyState& b2) const {
  const Eigen::Vector2d raw = cross_.angles(b1, b2);
  return {unwrap(raw[0], last_[0]), unwrap(raw[1], last_[1])};
}

JointCoordinates UniversalJoint::coordinates(const BodyState& b1, const BodyState& b2) const {
  return angles(b1, b2);
}

void UniversalJoint::track(const BodyState& b1, const BodyState& b2) {
  last_ = angles(b1, b2);
}

void UniversalJoint::persistTracked(state::Archive& a) {
  a(last_);
}

int UniversalJoint::fill(const JointContext& ctx, std::span<Row> rows) const {
  pointRows(Arms::of(frames_, ctx.b1, ctx.b2), rows.first<3>());
  cross_.row(ctx.b1, ctx.b2, rows[3]);
  for (int k = 0; k < 4; ++k) rows[k].key = k;
  if (def().coordinates[0].empty() && def().coordinates[1].empty()) return 4;

  const Eigen::Vector2d theta = angles(ctx.b1, ctx.b2);
  const Vec3 axes[2] = {cross_.a1(ctx.b1), cross_.a2(ctx.b2)};
  constexpr double kMargins[] = {kAngularLimitMargin, kAngularLimitMargin};
  return freeCoordinateRows(
      ctx, def(), kMargins,
      [&](std::size_t i, Row& row) {
        angularRow(axes[i], theta[static_cast<Eigen::Index>(i)], row);
      },
      rows, 4);
}

void UniversalJoint::curvature(const JointContext& ctx, std::span<const Row> rows,
                               std::span<double> out) const {
  const Vec3 point = pointCurvature(Arms::of(frames_, ctx.b1, ctx.b2), ctx.b1, ctx.b2);
  curvatureBySlot(rows, out, [&](int slot) {
    return slot < 3    ? point[slot]
           : slot == 3 ? cross_.curvature(ctx.b1, ctx.b2)
                       : kMeasuredCurvature;  // the angles' rows
  });
}

Mat12 UniversalJoint::stiffness(const JointContext& ctx, std::span<const Row> rows,
                                std::span<const double> lambda) const {
  Mat12 k = Mat12::Zero();
  addPointStiffness(Arms::of(frames_, ctx.b1, ctx.b2), pointImpulse(rows, lambda), k);
  // The cross row (slot 3), and the coordinates' rows: torques along a1 (turning with body 1)
  // and a2 (with body 2).
  double l = 0.0;
  Vec3 torque1 = Vec3::Zero(), torque2 = Vec3::Zero();
  for (std::size_t m = 0; m < rows.size(); ++m) {
    const int slot = rows[m].key & 0xff;
    if (slot == 3) l += lambda[m];
    if (slot >= coordinateSlot(0, 0) && slot < coordinateSlot(1, 0))
      torque1 += lambda[m] * rows[m].Ja.tail<3>();
    if (slot >= coordinateSlot(1, 0)) torque2 += lambda[m] * rows[m].Ja.tail<3>();
  }
  cross_.addStiffness(ctx.b1, ctx.b2, l, k);
  addBody1AxisStiffness(torque1, k);
  addBody2AxisStiffness(torque2, k);
  return k;
}

}  // namespace linx::joints
