// Cylindrical (piston) joint: body 1 slides along the axis a (fixed in body 2) and turns about it.
// 4 rows, plus the rows of what acts on the two coordinates.
//   align:    C_j = t_j . (a2 x a1) = 0, t_1, t_2 _|_ a2, fixed in body 2
//             J_j = [ 0, t_j | 0, -t_j ]
//   linear:   C_j = t_j . d = 0, d = (p1 + r1) - (p2 + r2)
//             J_j = [ t_j, r1 x t_j | -t_j, -(r2 + d) x t_j ]
// Coordinates (zero at creation):
//   position: s = a . d (m), J = [ a, r1 x a | -a, -(r2 + d) x a ]
//   angle:    twist of body 1 relative to body 2 about a (rad, counting turns)
//             J = [ 0, a | 0, -a ]
//   limits, motor, spring, friction on each: joints/row_parts.hpp, coordinateRows
#include "joints/cylindrical_joint.hpp"

#include "world/state_archive.hpp"

namespace linx::joints {

CylindricalJoint::CylindricalJoint(const JointDef& def, const BodyState& b1, const BodyState& b2)
    : Joint(def), frames_(JointFrames::capture(def, b1, b2)) {}

double CylindricalJoint::angle(const BodyState& b1, const BodyState& b2) const {
  return axisAngle(frames_, b1, b2, last_angle_);
}

JointCoordinates CylindricalJoint::coordinates(const BodyState& b1, const BodyState& b2) const {
  const Vec3 a = b2.pose.orientation * frames_.axis2;
  return Eigen::Vector2d(a.dot(Arms::of(frames_, b1, b2).d), angle(b1, b2));
}

void CylindricalJoint::track(const BodyState& b1, const BodyState& b2) {
  last_angle_ = angle(b1, b2);
}

void CylindricalJoint::persistTracked(state::Archive& a) {
  a(last_angle_);
}

int CylindricalJoint::fill(const JointContext& ctx, std::span<Row> rows) const {
  const Arms arms = Arms::of(frames_, ctx.b1, ctx.b2);
  alignRows(frames_, ctx.b1, ctx.b2, rows.subspan<0, 2>());
  Vec3 t1, t2;
  frames_.tangents(ctx.b2, t1, t2);
  linearRow(arms, t1, rows[2]);
  linearRow(arms, t2, rows[3]);
  for (int k = 0; k < 4; ++k) rows[k].key = k;
  if (def().coordinates[0].empty() && def().coordinates[1].empty()) return 4;

  const Vec3 a = ctx.b2.pose.orientation * frames_.axis2;
  const double theta = def().coordinates[1].empty() ? 0.0 : angle(ctx.b1, ctx.b2);
  constexpr double kMargins[] = {kLinearLimitMargin, kAngularLimitMargin};
  return freeCoordinateRows(
      ctx, def(), kMargins,
      [&](std::size_t i, Row& row) {
        if (i == 0)
          linearRow(arms, a, row);
        else
          angularRow(a, theta, row);
      },
      rows, 4);
}

}  // namespace linx::joints
