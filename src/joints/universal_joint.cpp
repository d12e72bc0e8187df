// Universal (Cardan, Hooke) joint: a common anchor, and a cross whose two arms turn in body 1
// (along a1) and in body 2 (along a2), perpendicular: body 1 may turn about a1 and about a2, not
// about a1 x a2. 4 rows.
//   point:  C = (p1 + r1) - (p2 + r2) = 0               J = [ E, -[r1]x | -E, [r2]x ]
//   cross:  C = a1 . a2 = 0                             J = [ 0, n | 0, -n ],  n = a1 x a2
//           (d/dt a1 . a2 = (w1 x a1) . a2 + a1 . (w2 x a2) = n . (w1 - w2))
#include "joints/universal_joint.hpp"

#include "math/rotation.hpp"

#include <cmath>
#include <stdexcept>

namespace linx::joints {

UniversalJoint::UniversalJoint(const JointDef& def, const BodyState& b1, const BodyState& b2)
    : Joint(def), frames_(JointFrames::capture(def, b1, b2)) {
  const Vec3 a1 = def.axis.normalized(), a2 = def.axis2.normalized();
  if (std::abs(a1.dot(a2)) > 1e-6)
    throw std::invalid_argument("axis2: must be perpendicular to axis1 (the cross's two arms)");
  cross1_ = b1.pose.orientation.conjugate() * a1;
  cross2_ = b2.pose.orientation.conjugate() * a2;
}

int UniversalJoint::fill(const JointContext& ctx, std::span<Row> rows) const {
  pointRows(Arms::of(frames_, ctx.b1, ctx.b2), rows.first<3>());
  const Vec3 a1 = ctx.b1.pose.orientation * cross1_;
  const Vec3 a2 = ctx.b2.pose.orientation * cross2_;
  const Vec3 n = a1.cross(a2);
  rows[3].Ja << Vec3::Zero(), n;
  rows[3].Jb << Vec3::Zero(), -n;
  rows[3].phi = a1.dot(a2);
  for (int k = 0; k < 4; ++k) rows[k].key = k;
  return 4;
}

Mat12 UniversalJoint::stiffness(const JointContext& ctx, std::span<const Row> rows,
                                std::span<const double> lambda) const {
  Mat12 k = Mat12::Zero();
  addPointStiffness(Arms::of(frames_, ctx.b1, ctx.b2), pointImpulse(rows, lambda), k);
  // The cross row's torque l (a1 x a2) on body 1 and its opposite on body 2 turn with both arms:
  // d(a1 x a2) = [a2]x [a1]x dtheta1 - [a1]x [a2]x dtheta2.
  double l = 0.0;
  for (std::size_t m = 0; m < rows.size(); ++m)
    if ((rows[m].key & 0xff) == 3) l += lambda[m];
  const Vec3 a1 = ctx.b1.pose.orientation * cross1_;
  const Vec3 a2 = ctx.b2.pose.orientation * cross2_;
  const Mat3 d1 = l * math::skew(a2) * math::skew(a1), d2 = -l * math::skew(a1) * math::skew(a2);
  k.block<3, 3>(3, 3) += d1;
  k.block<3, 3>(3, 9) += d2;
  k.block<3, 3>(9, 3) -= d1;
  k.block<3, 3>(9, 9) -= d2;
  return k;
}

}  // namespace linx::joints
