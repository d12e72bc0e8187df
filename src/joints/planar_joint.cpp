// Planar joint: body 1 slides in a plane of body 2 (x along axis1, y along axis2, normal
// n = x cross y, all fixed in body 2) and turns about its normal. 3 rows, plus the rows of what
// acts on the three coordinates.
//   normal:  C = n . d = 0, d = (p1 + r1) - (p2 + r2)   J = [ n, r1 x n | -n, -(r2 + d) x n ]
//   align:   C_j = t_j . (n2 x n1) = 0, t = x, y         J_j = [ 0, t_j | 0, -t_j ]
// Coordinates (zero at creation):
//   x, y:    C = t . d (m), J = [ t, r1 x t | -t, -(r2 + d) x t ]
//   angle:   twist of body 1 relative to body 2 about n (rad, counting turns), J = [ 0, n | 0, -n ]
//   limits, motor, spring, friction on each: joints/row_parts.hpp, coordinateRows
#include "joints/planar_joint.hpp"

#include "world/state_archive.hpp"

#include <cmath>
#include <stdexcept>

namespace linx::joints {

namespace {
JointDef normalFrames(JointDef def) {
  def.axis = def.axis.normalized().cross(def.axis2.normalized());
  return def;
}
}  // namespace

PlanarJoint::PlanarJoint(const JointDef& def, const BodyState& b1, const BodyState& b2)
    : Joint(def) {
  frames_ = JointFrames::capture(normalFrames(def), b1, b2);
  frames_.tangent1 = b2.pose.orientation.conjugate() * def.axis.normalized();
  frames_.tangent2 = frames_.axis2.cross(frames_.tangent1);
}

double PlanarJoint::angle(const BodyState& b1, const BodyState& b2) const {
  return axisAngle(frames_, b1, b2, last_angle_);
}

JointCoordinates PlanarJoint::coordinates(const BodyState& b1, const BodyState& b2) const {
  Vec3 t1, t2;
  frames_.tangents(b2, t1, t2);
  const Vec3 d = Arms::of(frames_, b1, b2).d;
  return Vec3(t1.dot(d), t2.dot(d), angle(b1, b2));
}

void PlanarJoint::track(const BodyState& b1, const BodyState& b2) {
  last_angle_ = angle(b1, b2);
}

void PlanarJoint::persistTracked(state::Archive& a) {
  a(last_angle_);
}

int PlanarJoint::fill(const JointContext& ctx, std::span<Row> rows) const {
  const Arms arms = Arms::of(frames_, ctx.b1, ctx.b2);
  const Vec3 n = ctx.b2.pose.orientation * frames_.axis2;
  linearRow(arms, n, rows[0]);
  alignRows(frames_, ctx.b1, ctx.b2, rows.subspan<1, 2>());
  for (int k = 0; k < 3; ++k) rows[k].key = k;
  const auto& c = def().coordinates;
  if (c[0].empty() && c[1].empty() && c[2].empty()) return 3;

  Vec3 t[2];
  frames_.tangents(ctx.b2, t[0], t[1]);
  const double theta = c[2].empty() ? 0.0 : angle(ctx.b1, ctx.b2);
  constexpr double kMargins[] = {kLinearLimitMargin, kLinearLimitMargin, kAngularLimitMargin};
  return freeCoordinateRows(
      ctx, def(), kMargins,
      [&](std::size_t i, Row& row) {
        if (i < 2)
          linearRow(arms, t[i], row);
        else
          angularRow(n, theta, row);
      },
      rows, 3);
}

}  // namespace linx::joints
