// Distance joint: a massless rod between a point on body 1 and a point on body 2, or a rope that
// only keeps them within its length. 1 row (a rope's only while taut or about to be).
//   C = |d| - L, d = (p1 + r1) - (p2 + r2), n = d / |d|
//   J = [ n, r1 x n | -n, -(r2 x n) ]               (d/dt |d| = n . d', exact)
//   rod: bilateral; rope: |d| <= L, a limit row (joints/row_parts.hpp, limitRow)
// Coordinate (reported, not driven): the distance |d| (m).
#include "joints/distance_joint.hpp"

#include <fmt/format.h>

#include <stdexcept>

namespace linx::joints {

DistanceJoint::DistanceJoint(const JointDef& def, const BodyState& b1, const BodyState& b2)
    : Joint(def) {
  const Vec3 p1 = def.anchor.value_or(b1.pose.position);
  const Vec3 p2 = def.anchor2.value_or(b2.pose.position);
  const double apart = (p1 - p2).norm();
  if (!(apart > 1e-9))
    throw std::invalid_argument(
        fmt::format("anchor2: must be apart from the point on body 1 at the start ({} m apart; a "
                    "ball joint joins two points)",
                    apart));
  point1_ = b1.pose.toLocal(p1);
  point2_ = b2.pose.toLocal(p2);
  length_ = def.length.value_or(apart);
}

JointCoordinates DistanceJoint::coordinates(const BodyState& b1, const BodyState& b2) const {
  return JointCoordinates::Constant(1,
                                    (b1.pose.toWorld(point1_) - b2.pose.toWorld(point2_)).norm());
}

int DistanceJoint::fill(const JointContext& ctx, std::span<Row> rows) const {
  const Vec3 r1 = ctx.b1.pose.orientation * point1_, r2 = ctx.b2.pose.orientation * point2_;
  const Vec3 d = (ctx.b1.pose.position + r1) - (ctx.b2.pose.position + r2);
  const double distance = d.norm();
  // Points that meet have no direction between them: any will do, C is at its extreme there.
  const Vec3 n = distance > 1e-12 ? Vec3(d / distance) : Vec3::UnitX();
  Row& row = rows[0];
  row.Ja << n, r1.cross(n);
  row.Jb << -n, -r2.cross(n);
  row.key = 0;
  if (!def().rope) {
    row.phi = distance - length_;
    return 1;
  }
  row.phi = distance;
  return limitRow(ctx, length_, false, kLinearLimitMargin, row) ? 1 : 0;
}

}  // namespace linx::joints
