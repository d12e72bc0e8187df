// Ball-and-socket (point) joint: the anchor points of both bodies coincide. 3 rows, and a limit
// row while its angle is at or near its upper bound.
//   C = (p1 + r1) - (p2 + r2) = 0
//   J = [ E, -[r1]x | -E, [r2]x ]  (row k: [ e_k, r1 x e_k | -e_k, -(r2 x e_k) ])
//   limit: theta = |r|, r = R2 log(q2^-1 q1 q0^-1) = theta n (world frame), theta <= bound,
//          J = [ 0, n | 0, -n ]: theta' = n . (w1 - w2), exact, since n is an eigenvector (of
//          eigenvalue 1) of the map from the relative angular velocity to r' (MuJoCo's ball range).
// Coordinate: the angle of the relative rotation since creation (rad, >= 0).
#include "joints/ball_joint.hpp"

#include "math/rotation.hpp"

namespace linx::joints {

BallJoint::BallJoint(const JointDef& def, const BodyState& b1, const BodyState& b2)
    : Joint(def), frames_(JointFrames::capture(def, b1, b2)) {}

int BallJoint::fill(const JointContext& ctx, std::span<Row> rows) const {
  pointRows(Arms::of(frames_, ctx.b1, ctx.b2), rows.first<3>());
  for (int k = 0; k < 3; ++k) rows[k].key = k;
  const auto& limits = def().coordinates[0].limits;
  if (!limits || limits->upper == kInfinity) return 3;
  const Vec3 r = ctx.b2.pose.orientation * math::logMap(relativeRotation(frames_, ctx.b1, ctx.b2));
  const double theta = r.norm();
  // Near the start the axis is undefined, and a bound of a useful size is far.
  if (theta < 1e-9) return 3;
  const Vec3 n = r / theta;
  Row& row = rows[3];
  row.Ja << Vec3::Zero(), n;
  row.Jb << Vec3::Zero(), -n;
  row.phi = theta;
  row.key = 3;
  return limitRow(ctx, limits->upper, false, kAngularLimitMargin, row) ? 4 : 3;
}

void BallJoint::curvature(const JointContext& ctx, std::span<const Row> rows,
                          std::span<double> out) const {
  const Vec3 point = pointCurvature(Arms::of(frames_, ctx.b1, ctx.b2), ctx.b1, ctx.b2);
  curvatureBySlot(rows, out, [&](int slot) {
    return slot < 3 ? point[slot] : kMeasuredCurvature;  // the cone's limit row
  });
}

JointCoordinates BallJoint::coordinates(const BodyState& b1, const BodyState& b2) const {
  return JointCoordinates::Constant(1, math::logMap(relativeRotation(frames_, b1, b2)).norm());
}

Mat12 BallJoint::stiffness(const JointContext& ctx, std::span<const Row> rows,
                           std::span<const double> lambda) const {
  // The limit row turns with the rotation's axis: differentiated numerically (rarely active).
  if (rows.size() > 3) return Joint::stiffness(ctx, rows, lambda);
  Mat12 k = Mat12::Zero();
  addPointStiffness(Arms::of(frames_, ctx.b1, ctx.b2), pointImpulse(rows, lambda), k);
  return k;
}

}  // namespace linx::joints
