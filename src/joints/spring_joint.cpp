// Spring joint: nothing held, one free coordinate, the distance |d| (m) between a point on body 1
// and a point on body 2 (joints/row_parts.hpp, PointPair). What acts on it makes the element: a
// spring and damper (a point-to-point spring, a scene's top-level "springs"), limits (a shortest
// and a longest length: a strut's stops, a rope), a motor or servo (a linear actuator between two
// points), friction.
#include "joints/spring_joint.hpp"

namespace linx::joints {

SpringJoint::SpringJoint(const JointDef& def, const BodyState& b1, const BodyState& b2)
    : Joint(def), points_(PointPair::capture(def, b1, b2)) {}

JointCoordinates SpringJoint::coordinates(const BodyState& b1, const BodyState& b2) const {
  return JointCoordinates::Constant(1, points_.distance(b1, b2));
}

int SpringJoint::fill(const JointContext& ctx, std::span<Row> rows) const {
  const double margins[] = {kLinearLimitMargin};
  return freeCoordinateRows(
      ctx, def(), margins, [&](std::size_t, Row& row) { points_.row(ctx.b1, ctx.b2, row); }, rows,
      0);
}

}  // namespace linx::joints
