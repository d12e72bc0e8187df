// Distance joint: a massless rod between a point on body 1 and a point on body 2, or a rope that
// only keeps them within its length. 1 row (a rope's only while taut or about to be), on the
// distance |d| between the points (joints/row_parts.hpp, PointPair):
//   rod: C = |d| - L, bilateral; rope: |d| <= L, a limit row (limitRow)
// Coordinate (reported, not driven): the distance |d| (m).
#include "joints/distance_joint.hpp"

namespace linx::joints {

DistanceJoint::DistanceJoint(const JointDef& def, const BodyState& b1, const BodyState& b2)
    : Joint(def), points_(PointPair::capture(def, b1, b2)) {
  length_ = def.length.value_or(points_.distance(b1, b2));
}

JointCoordinates DistanceJoint::coordinates(const BodyState& b1, const BodyState& b2) const {
  return JointCoordinates::Constant(1, points_.distance(b1, b2));
}

int DistanceJoint::fill(const JointContext& ctx, std::span<Row> rows) const {
  Row& row = rows[0];
  points_.row(ctx.b1, ctx.b2, row);
  row.key = 0;
  if (!def().rope) {
    row.phi -= length_;
    return 1;
  }
  return limitRow(ctx, length_, false, kLinearLimitMargin, row) ? 1 : 0;
}

void DistanceJoint::curvature(const JointContext& ctx, std::span<const Row> rows,
                              std::span<double> out) const {
  // A rope's row is the limit's, |d| <= L as -|d| >= -L: its rate and curvature change sign.
  if (!rows.empty()) out[0] = (def().rope ? -1.0 : 1.0) * points_.curvature(ctx.b1, ctx.b2);
}

}  // namespace linx::joints
