// Hinge-2 joint (a car's wheel): body 1 (the wheel) spins about its axle a1, fixed in it; the
// axle steers about a2, fixed in body 2 (the chassis), and the wheel's centre may move along a2
// (the suspension, usually sprung). A universal joint whose anchor is free along a2. 3 rows, plus
// the rows of what acts on the three coordinates.
//   linear:   C_j = t_j . d = 0, t_1, t_2 _|_ a2 fixed in body 2, d = (p1 + r1) - (p2 + r2)
//             J_j = [ t_j, r1 x t_j | -t_j, -(r2 + d) x t_j ]
//   cross:    C = a1 . a2 = 0, J = [ 0, n | 0, -n ], n = a1 x a2 (joints/row_parts.hpp, Cross)
// Coordinates (zero at creation):
//   wheel:      body 1 turning about a1 (rad, counting turns), J = [ 0, a1 | 0, -a1 ]
//   steering:   the axle turning about a2 (rad, counting turns), J = [ 0, a2 | 0, -a2 ]
//   suspension: s = a2 . d (m), J = [ a2, r1 x a2 | -a2, -(r2 + d) x a2 ]
//   limits, motor, spring, friction on each: joints/row_parts.hpp, coordinateRows
#include "joints/hinge2_joint.hpp"

#include "world/state_archive.hpp"

namespace linx::joints {

namespace {
JointDef steeringFrames(JointDef def) {
  def.axis = def.axis2;
  return def;
}
}  // namespace

Hinge2Joint::Hinge2Joint(const JointDef& def, const BodyState& b1, const BodyState& b2)
    : Joint(def),
      frames_(JointFrames::capture(steeringFrames(def), b1, b2)),
      cross_(Cross::capture(def.axis, def.axis2, b1, b2)) {}

Eigen::Vector2d Hinge2Joint::angles(const BodyState& b1, const BodyState& b2) const {
  const Eigen::Vector2d raw = cross_.angles(b1, b2);
  return {unwrap(raw[0], last_[0]), unwrap(raw[1], last_[1])};
}

JointCoordinates Hinge2Joint::coordinates(const BodyState& b1, const BodyState& b2) const {
  const Eigen::Vector2d theta = angles(b1, b2);
  return Vec3(theta[0], theta[1], cross_.a2(b2).dot(Arms::of(frames_, b1, b2).d));
}

void Hinge2Joint::track(const BodyState& b1, const BodyState& b2) {
  last_ = angles(b1, b2);
}

void Hinge2Joint::persistTracked(state::Archive& a) {
  a(last_);
}

int Hinge2Joint::fill(const JointContext& ctx, std::span<Row> rows) const {
  const Arms arms = Arms::of(frames_, ctx.b1, ctx.b2);
  Vec3 t1, t2;
  frames_.tangents(ctx.b2, t1, t2);
  linearRow(arms, t1, rows[0]);
  linearRow(arms, t2, rows[1]);
  cross_.row(ctx.b1, ctx.b2, rows[2]);
  for (int k = 0; k < 3; ++k) rows[k].key = k;
  const auto& c = def().coordinates;
  if (c[0].empty() && c[1].empty() && c[2].empty()) return 3;

  const Eigen::Vector2d theta = angles(ctx.b1, ctx.b2);
  const Vec3 a1 = cross_.a1(ctx.b1), a2 = cross_.a2(ctx.b2);
  constexpr double kMargins[] = {kAngularLimitMargin, kAngularLimitMargin, kLinearLimitMargin};
  return freeCoordinateRows(
      ctx, def(), kMargins,
      [&](std::size_t i, Row& row) {
        if (i == 0) angularRow(a1, theta[0], row);
        if (i == 1) angularRow(a2, theta[1], row);
        if (i == 2) linearRow(arms, a2, row);
      },
      rows, 3);
}

}  // namespace linx::joints
