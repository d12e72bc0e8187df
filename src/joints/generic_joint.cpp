// Generic (6-dof) joint: a frame of axes x, y, z at the anchor, fixed in each body, and six
// coordinates of body 1's frame relative to body 2's, each free (the default), locked, limited,
// driven, sprung or braked (CoordinateDef). Rows only for what acts on a coordinate.
// Translations, along the axes e_k fixed in body 2 (exact, as the slider's rows):
//   x, y, z:    C = e_k . d, d = (p1 + r1) - (p2 + r2)
//               J = [ e_k, r1 x e_k | -e_k, -(r2 + d) x e_k ]
// Rotations: M = F2^T F1 (F_i the axes in the world, M = I at creation) = Rx(rx) Ry(ry) Rz(rz),
// intrinsic x-y-z (Cardan) angles. With W = F2^T (w1 - w2), M' M^T = [W]x and
//   W = G (rx', ry', rz')^T,  G = [ e_x, Rx(rx) e_y, Rx(rx) Ry(ry) e_z ]
// so angle k's row is J = [ 0, j_k | 0, -j_k ], j_k = F2 G^-T e_k (exact). G is singular at
// ry = +-pi/2 (gimbal lock): a free ry must stay away from it; rx and rz count turns.
#include "joints/generic_joint.hpp"

#include "world/state_archive.hpp"

#include "math/rotation.hpp"

#include <cmath>
#include <stdexcept>

namespace linx::joints {

namespace {
Mat3 frameOf(const Vec3& x_world, const Vec3& y_world) {
  const Vec3 x = x_world.normalized();
  const Vec3 y = (y_world - x * x.dot(y_world)).normalized();
  Mat3 f;
  f << x, y, x.cross(y);
  return f;
}
}  // namespace

GenericJoint::GenericJoint(const JointDef& def, const BodyState& b1, const BodyState& b2)
    : Joint(def), frames_(JointFrames::capture(def, b1, b2)) {
  const Mat3 f = frameOf(def.axis, def.axis2);
  axes1_ = b1.pose.orientation.conjugate().toRotationMatrix() * f;
  axes2_ = b2.pose.orientation.conjugate().toRotationMatrix() * f;
}

Vec3 GenericJoint::angles(const BodyState& b1, const BodyState& b2, Mat3* rates) const {
  const Mat3 f1 = b1.pose.orientation.toRotationMatrix() * axes1_;
  const Mat3 f2 = b2.pose.orientation.toRotationMatrix() * axes2_;
  const Mat3 m = f2.transpose() * f1;
  const double rx = unwrap(std::atan2(-m(1, 2), m(2, 2)), last_.x());
  const double ry = std::asin(std::clamp(m(0, 2), -1.0, 1.0));
  const double rz = unwrap(std::atan2(-m(0, 1), m(0, 0)), last_.z());
  if (rates) {
    const double cx = std::cos(rx), sx = std::sin(rx), cy = std::cos(ry), sy = std::sin(ry);
    Mat3 g;  // columns: e_x, Rx e_y, Rx Ry e_z
    g.col(0) = Vec3::UnitX();
    g.col(1) = Vec3(0, cx, sx);
    g.col(2) = Vec3(sy, -sx * cy, cx * cy);
    *rates = f2 * g.inverse().transpose();  // column k: j_k
  }
  return {rx, ry, rz};
}

JointCoordinates GenericJoint::coordinates(const BodyState& b1, const BodyState& b2) const {
  const Mat3 f2 = b2.pose.orientation.toRotationMatrix() * axes2_;
  JointCoordinates q(6);
  q << f2.transpose() * Arms::of(frames_, b1, b2).d, angles(b1, b2);
  return q;
}

void GenericJoint::track(const BodyState& b1, const BodyState& b2) {
  last_ = angles(b1, b2);
}

void GenericJoint::persistTracked(state::Archive& a) {
  a(last_);
}

int GenericJoint::fill(const JointContext& ctx, std::span<Row> rows) const {
  const auto& c = def().coordinates;
  const bool any_angle = !c[3].empty() || !c[4].empty() || !c[5].empty();
  const Arms arms = Arms::of(frames_, ctx.b1, ctx.b2);
  const Mat3 f2 = ctx.b2.pose.orientation.toRotationMatrix() * axes2_;
  Mat3 rates = Mat3::Zero();
  const Vec3 theta = any_angle ? angles(ctx.b1, ctx.b2, &rates) : Vec3::Zero();
  constexpr double kMargins[] = {kLinearLimitMargin,  kLinearLimitMargin,  kLinearLimitMargin,
                                 kAngularLimitMargin, kAngularLimitMargin, kAngularLimitMargin};
  return freeCoordinateRows(
      ctx, def(), kMargins,
      [&](std::size_t i, Row& row) {
        const auto k = static_cast<Eigen::Index>(i % 3);
        if (i < 3)
          linearRow(arms, f2.col(k), row);
        else
          angularRow(rates.col(k), theta[k], row);
      },
      rows, 0);
}

}  // namespace linx::joints
