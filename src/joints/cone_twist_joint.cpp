// Cone-twist joint (a shoulder or a hip): a ball joint whose twist axis a1 (in body 1) may swing
// away from a2 (in body 2) only within an elliptical cone, and whose twist about it is a free
// coordinate (limits, motor, spring, friction). 3 rows, a cone row while at or near the cone, and
// the twist's rows.
//   point:  C = (p1 + r1) - (p2 + r2) = 0              J = [ E, -[r1]x | -E, [r2]x ]
//   cone:   a1 in body 2's frame, b = (x, y, z) on (u, v, a2) with u along axis2: swing
//           theta = atan2(rho, z), rho = sqrt(x^2 + y^2), towards phi = atan2(y, x); bound
//           theta_max(phi) = (cos^2 phi / s1^2 + sin^2 phi / s2^2)^-1/2 (an ellipse of half-angles
//           s1 towards u, s2 towards v). C = theta - theta_max(phi) <= 0, a limit row with
//           J = [ 0, g | 0, -g ], g = R2 (b x grad C(b)): (w1 - w2) turns b as body 2 sees it, so
//           dC/dt = grad C . ((R2^T (w1 - w2)) x b) = (b x grad C) . R2^T (w1 - w2), exact.
//   twist:  the twist of body 1's relative rotation about a (swing-twist: swing applied last),
//           J = [ 0, j | 0, -j ], j = (a1 + a2) / (1 + a1 . a2); counting turns
// Coordinates: twist (free), swing theta (reported).
#include "joints/cone_twist_joint.hpp"

#include "world/state_archive.hpp"

#include <cmath>
#include <stdexcept>

namespace linx::joints {

ConeTwistJoint::ConeTwistJoint(const JointDef& def, const BodyState& b1, const BodyState& b2)
    : Joint(def), frames_(JointFrames::capture(def, b1, b2)) {
  // The cone's u along axis2 (in body 2), v = a x u.
  frames_.tangent1 = b2.pose.orientation.conjugate() * def.axis2.normalized();
  frames_.tangent2 = frames_.axis2.cross(frames_.tangent1);
}

double ConeTwistJoint::twist(const BodyState& b1, const BodyState& b2) const {
  return axisAngle(frames_, b1, b2, last_twist_);
}

JointCoordinates ConeTwistJoint::coordinates(const BodyState& b1, const BodyState& b2) const {
  const Vec3 a1 = b1.pose.orientation * frames_.axis1, a2 = b2.pose.orientation * frames_.axis2;
  return Eigen::Vector2d(twist(b1, b2), std::atan2(a1.cross(a2).norm(), a1.dot(a2)));
}

void ConeTwistJoint::track(const BodyState& b1, const BodyState& b2) {
  last_twist_ = twist(b1, b2);
}

void ConeTwistJoint::persistTracked(state::Archive& a) {
  a(last_twist_);
}

void ConeTwistJoint::coneRow(const BodyState& b1, const BodyState& b2, Row& row) const {
  const ConeLimit& cone = *def().cone;
  const Quat& q2 = b2.pose.orientation;
  const Vec3 a1 = q2.conjugate() * (b1.pose.orientation * frames_.axis1);  // in body 2's frame
  const double x = a1.dot(frames_.tangent1), y = a1.dot(frames_.tangent2),
               z = a1.dot(frames_.axis2);
  const double rho = std::max(std::hypot(x, y), 1e-12), r2 = x * x + y * y + z * z;
  const double theta = std::atan2(rho, z), phi = std::atan2(y, x);
  const double c = std::cos(phi), s = std::sin(phi);
  const double inv1 = 1.0 / (cone.swing1 * cone.swing1), inv2 = 1.0 / (cone.swing2 * cone.swing2);
  const double bound = 1.0 / std::sqrt(c * c * inv1 + s * s * inv2);
  const double bound_rate = bound * bound * bound * c * s * (inv1 - inv2);  // d bound / d phi
  // grad theta and grad phi in (x, y, z), then back on body 2's axes.
  const Vec3 d_theta(x * z / (rho * r2), y * z / (rho * r2), -rho / r2);
  const Vec3 d_phi(-y / (rho * rho), x / (rho * rho), 0.0);
  const Vec3 grad_xyz = d_theta - bound_rate * d_phi;
  const Vec3 grad = grad_xyz.x() * frames_.tangent1 + grad_xyz.y() * frames_.tangent2 +
                    grad_xyz.z() * frames_.axis2;
  const Vec3 g = q2 * a1.cross(grad);
  row.Ja << Vec3::Zero(), g;
  row.Jb << Vec3::Zero(), -g;
  row.phi = theta - bound;
}

int ConeTwistJoint::fill(const JointContext& ctx, std::span<Row> rows) const {
  pointRows(Arms::of(frames_, ctx.b1, ctx.b2), rows.first<3>());
  for (int k = 0; k < 3; ++k) rows[k].key = k;
  int n = 3;
  if (def().cone) {
    Row& row = rows[3];
    coneRow(ctx.b1, ctx.b2, row);
    row.key = 3;
    if (limitRow(ctx, 0.0, false, kAngularLimitMargin, row)) ++n;
  }
  if (def().coordinates[0].empty()) return n;

  const Vec3 a1 = ctx.b1.pose.orientation * frames_.axis1;
  const Vec3 a2 = ctx.b2.pose.orientation * frames_.axis2;
  const Vec3 j = (a1 + a2) / (1.0 + a1.dot(a2));
  const double theta = twist(ctx.b1, ctx.b2);
  constexpr double kMargins[] = {kAngularLimitMargin};
  return freeCoordinateRows(
      ctx, def(), kMargins, [&](std::size_t, Row& row) { angularRow(j, theta, row); }, rows, n);
}

}  // namespace linx::joints
