// Rack and pinion: body 2 (the rack) travels along its direction a2 by `ratio` times the angle body
// 1 (the pinion) turns about its axle a1 (ratio: the pinion's pitch radius, m/rad; its sign is the
// sense). Axle and direction are taken as fixed in the world, as when the pinion turns in bearings
// on the ground and the rack slides in guides: the joint couples the two motions, the bearings and
// guides are other joints (a hinge, a slider). 1 row.
//   theta1: twist of q1 q1_0^-1 about a1, counting turns; its rate is j1 . w1,
//           j1 = (a1' + a1) / (1 + a1' . a1), a1' the axle now (as the gear joint's, exact)
//   s2 = a2 . (p2 - p2_0), its rate a2 . v2
//   C = ratio theta1 - s2 = 0          J = [ 0, ratio j1 | -a2, 0 ]
// Coordinates (reported, not driven): theta1 (rad), s2 (m).
#include "joints/rack_pinion_joint.hpp"

#include "world/state_archive.hpp"

#include "math/rotation.hpp"

#include <stdexcept>

namespace linx::joints {

RackPinionJoint::RackPinionJoint(const JointDef& def, const BodyState& b1, const BodyState& b2)
    : Joint(def),
      axis1_(def.axis.normalized()),
      axis2_(def.axis2.normalized()),
      start1_(b1.pose.orientation),
      start2_(b2.pose.position) {
  if (def.body2.isWorld())
    throw std::invalid_argument(
        "body2: a rack and pinion needs the rack, a body (body1 is the pinion)");
}

Eigen::Vector2d RackPinionJoint::travel(const BodyState& b1, const BodyState& b2,
                                        Vec3* rate1) const {
  const Quat turn1 = (b1.pose.orientation * start1_.conjugate()).normalized();
  if (rate1) {
    const Vec3 now1 = turn1 * axis1_;
    *rate1 = (now1 + axis1_) / (1.0 + now1.dot(axis1_));
  }
  return {unwrap(math::twistAngle(turn1, axis1_), last_), axis2_.dot(b2.pose.position - start2_)};
}

JointCoordinates RackPinionJoint::coordinates(const BodyState& b1, const BodyState& b2) const {
  return travel(b1, b2);
}

void RackPinionJoint::track(const BodyState& b1, const BodyState& b2) {
  last_ = travel(b1, b2)[0];
}

void RackPinionJoint::persistTracked(state::Archive& a) {
  a(last_);
}

int RackPinionJoint::fill(const JointContext& ctx, std::span<Row> rows) const {
  Vec3 j1;
  const Eigen::Vector2d q = travel(ctx.b1, ctx.b2, &j1);
  const double ratio = def().ratio;
  Row& row = rows[0];
  row.Ja << Vec3::Zero(), ratio * j1;
  row.Jb << -axis2_, Vec3::Zero();
  row.phi = ratio * q[0] - q[1];
  row.key = 0;
  return 1;
}

}  // namespace linx::joints
