// Gear joint: body 2 turns about its axle a2 at `ratio` times the rate body 1 turns about its
// axle a1 (a pair of gears, a belt, bevel gears at any angle). Each axle is taken as fixed in the
// world, as when both gears turn in bearings on the ground or on a slow carrier: the joint couples
// the two bodies' rotations, their bearings are other joints. 1 row.
//   theta_i: twist of q_i q_i0^-1 about a_i (the axle at creation), counting turns;
//            its rate is j_i . w_i, j_i = (a_i' + a_i) / (1 + a_i' . a_i), a_i' the axle now
//            (the swing-twist decomposition's twist, exact)
//   C = ratio theta1 - theta2 = 0          J = [ 0, ratio j1 | 0, -j2 ]
// Coordinates (reported, not driven): theta1, theta2.
#include "joints/gear_joint.hpp"

#include "world/state_archive.hpp"

#include "math/rotation.hpp"

namespace linx::joints {

GearJoint::GearJoint(const JointDef& def, const BodyState& b1, const BodyState& b2)
    : Joint(def),
      axis1_(def.axis.normalized()),
      axis2_(def.axis2.normalized()),
      start1_(b1.pose.orientation),
      start2_(b2.pose.orientation) {}

Eigen::Vector2d GearJoint::angles(const BodyState& b1, const BodyState& b2, Vec3* rate1,
                                  Vec3* rate2) const {
  const Quat turn1 = (b1.pose.orientation * start1_.conjugate()).normalized();
  const Quat turn2 = (b2.pose.orientation * start2_.conjugate()).normalized();
  if (rate1) {
    const Vec3 now1 = turn1 * axis1_, now2 = turn2 * axis2_;
    *rate1 = (now1 + axis1_) / (1.0 + now1.dot(axis1_));
    *rate2 = (now2 + axis2_) / (1.0 + now2.dot(axis2_));
  }
  return {unwrap(math::twistAngle(turn1, axis1_), last_[0]),
          unwrap(math::twistAngle(turn2, axis2_), last_[1])};
}

JointCoordinates GearJoint::coordinates(const BodyState& b1, const BodyState& b2) const {
  return angles(b1, b2);
}

void GearJoint::track(const BodyState& b1, const BodyState& b2) {
  last_ = angles(b1, b2);
}

void GearJoint::persistTracked(state::Archive& a) {
  a(last_);
}

int GearJoint::fill(const JointContext& ctx, std::span<Row> rows) const {
  Vec3 j1, j2;
  const Eigen::Vector2d theta = angles(ctx.b1, ctx.b2, &j1, &j2);
  const double ratio = def().ratio;
  Row& row = rows[0];
  row.Ja << Vec3::Zero(), ratio * j1;
  row.Jb << Vec3::Zero(), -j2;
  row.phi = ratio * theta[0] - theta[1];
  row.key = 0;
  return 1;
}

}  // namespace linx::joints
