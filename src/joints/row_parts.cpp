#include "joints/row_parts.hpp"

#include "math/rotation.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace linx::joints {

namespace {
Vec6 block(const Vec3& lin, const Vec3& ang) {
  Vec6 v;
  v << lin, ang;
  return v;
}
}  // namespace

JointFrames JointFrames::capture(const JointDef& def, const BodyState& b1, const BodyState& b2) {
  JointFrames f;
  const Vec3 anchor = def.anchor.value_or(b1.pose.position);
  f.anchor1 = b1.pose.toLocal(anchor);
  f.anchor2 = b2.pose.toLocal(anchor);
  const Vec3 axis = def.axis.normalized();
  f.axis1 = b1.pose.orientation.conjugate() * axis;
  f.axis2 = b2.pose.orientation.conjugate() * axis;
  math::orthonormalBasis(f.axis2, f.tangent1, f.tangent2);
  f.rest = (b2.pose.orientation.conjugate() * b1.pose.orientation).normalized();
  return f;
}

Cross Cross::capture(const Vec3& a1_world, const Vec3& a2_world, const BodyState& b1,
                     const BodyState& b2) {
  const Vec3 a1 = a1_world.normalized(), a2 = a2_world.normalized();
  Cross c;
  c.arm1 = b1.pose.orientation.conjugate() * a1;
  c.arm2 = b2.pose.orientation.conjugate() * a2;
  c.start1 = b1.pose.orientation.conjugate() * a2;
  c.start2 = b2.pose.orientation.conjugate() * a1;
  return c;
}

void Cross::row(const BodyState& b1, const BodyState& b2, Row& r) const {
  const Vec3 u1 = a1(b1), u2 = a2(b2);
  const Vec3 n = u1.cross(u2);
  r.Ja = block(Vec3::Zero(), n);
  r.Jb = block(Vec3::Zero(), -n);
  r.phi = u1.dot(u2);
}

Eigen::Vector2d Cross::angles(const BodyState& b1, const BodyState& b2) const {
  const Vec3 seen1 = b1.pose.orientation.conjugate() * a2(b2);  // turns by -angle1 about arm1
  const Vec3 seen2 = b2.pose.orientation.conjugate() * a1(b1);  // turns by angle2 about arm2
  return {-std::atan2(arm1.dot(start1.cross(seen1)), start1.dot(seen1)),
          std::atan2(arm2.dot(start2.cross(seen2)), start2.dot(seen2))};
}

void Cross::addStiffness(const BodyState& b1, const BodyState& b2, double l, Mat12& k) const {
  const Vec3 u1 = a1(b1), u2 = a2(b2);
  const Mat3 d1 = l * math::skew(u2) * math::skew(u1), d2 = -l * math::skew(u1) * math::skew(u2);
  k.block<3, 3>(3, 3) += d1;
  k.block<3, 3>(3, 9) += d2;
  k.block<3, 3>(9, 3) -= d1;
  k.block<3, 3>(9, 9) -= d2;
}

PointPair PointPair::capture(const JointDef& def, const BodyState& b1, const BodyState& b2) {
  const Vec3 p1 = def.anchor.value_or(b1.pose.position);
  const Vec3 p2 = def.anchor2.value_or(b2.pose.position);
  const double apart = (p1 - p2).norm();
  if (!(apart > 1e-9))
    throw std::invalid_argument(
        fmt::format("anchor2: must be apart from the point on body 1 at the start ({} m apart; a "
                    "ball joint joins two points)",
                    apart));
  return PointPair{b1.pose.toLocal(p1), b2.pose.toLocal(p2)};
}

void PointPair::row(const BodyState& b1, const BodyState& b2, Row& r) const {
  const Vec3 r1 = b1.pose.orientation * point1, r2 = b2.pose.orientation * point2;
  const Vec3 d = (b1.pose.position + r1) - (b2.pose.position + r2);
  const double distance = d.norm();
  const Vec3 n = distance > 1e-12 ? Vec3(d / distance) : Vec3::UnitX();
  r.Ja << n, r1.cross(n);
  r.Jb << -n, -r2.cross(n);
  r.phi = distance;
}

double PointPair::curvature(const BodyState& b1, const BodyState& b2) const {
  const Vec3 r1 = b1.pose.orientation * point1, r2 = b2.pose.orientation * point2;
  const Vec3 d = (b1.pose.position + r1) - (b2.pose.position + r2);
  const double distance = d.norm();
  if (!(distance > 1e-12)) return 0.0;  // row(): a fixed direction where the points meet
  const Vec3 n = d / distance;
  const Vec3 turn1 = b1.w.cross(r1), turn2 = b2.w.cross(r2);
  const Vec3 rate = b1.v + turn1 - b2.v - turn2;  // d'
  const Vec3 n_rate = (rate - n * n.dot(rate)) / distance;
  return n_rate.dot(b1.v - b2.v) + (turn1.cross(n) + r1.cross(n_rate)).dot(b1.w) -
         (turn2.cross(n) + r2.cross(n_rate)).dot(b2.w);
}

Arms Arms::of(const JointFrames& f, const BodyState& b1, const BodyState& b2) {
  Arms a;
  a.r1 = b1.pose.orientation * f.anchor1;
  a.r2 = b2.pose.orientation * f.anchor2;
  a.d = (b1.pose.position + a.r1) - (b2.pose.position + a.r2);
  return a;
}

Quat relativeRotation(const JointFrames& f, const BodyState& b1, const BodyState& b2) {
  return (b2.pose.orientation.conjugate() * b1.pose.orientation * f.rest.conjugate()).normalized();
}

double axisAngle(const JointFrames& f, const BodyState& b1, const BodyState& b2, double last) {
  return unwrap(math::twistAngle(relativeRotation(f, b1, b2), f.axis2), last);
}

void pointRows(const Arms& arms, std::span<Row, 3> rows) {
  for (int k = 0; k < 3; ++k) {
    const Vec3 e = Vec3::Unit(k);
    rows[k].Ja = block(e, arms.r1.cross(e));
    rows[k].Jb = block(-e, -arms.r2.cross(e));
    rows[k].phi = arms.d[k];
  }
}

Vec3 pointCurvature(const Arms& arms, const BodyState& b1, const BodyState& b2) {
  return b1.w.cross(b1.w.cross(arms.r1)) - b2.w.cross(b2.w.cross(arms.r2));
}

void lockRows(const JointFrames& f, const BodyState& b1, const BodyState& b2,
              std::span<Row, 3> rows) {
  const Vec3 c = b2.pose.orientation * math::logMap(relativeRotation(f, b1, b2));
  for (int k = 0; k < 3; ++k) {
    const Vec3 e = Vec3::Unit(k);
    rows[k].Ja = block(Vec3::Zero(), e);
    rows[k].Jb = block(Vec3::Zero(), -e);
    rows[k].phi = c[k];
  }
}

void alignRows(const JointFrames& f, const BodyState& b1, const BodyState& b2,
               std::span<Row, 2> rows) {
  const Vec3 a1 = b1.pose.orientation * f.axis1;
  const Vec3 a2 = b2.pose.orientation * f.axis2;
  Vec3 t[2];
  f.tangents(b2, t[0], t[1]);
  const Vec3 c = a2.cross(a1);
  for (int j = 0; j < 2; ++j) {
    rows[j].Ja = block(Vec3::Zero(), t[j]);
    rows[j].Jb = block(Vec3::Zero(), -t[j]);
    rows[j].phi = t[j].dot(c);
  }
}

void linearRow(const Arms& arms, const Vec3& n, Row& row) {
  row.Ja = block(n, arms.r1.cross(n));
  row.Jb = block(-n, -(arms.r2 + arms.d).cross(n));
  row.phi = n.dot(arms.d);
}

double linearCurvature(const Arms& arms, const Vec3& n, const BodyState& b1, const BodyState& b2) {
  const Vec3 turn1 = b1.w.cross(arms.r1), turn2 = b2.w.cross(arms.r2);
  const Vec3 d_rate = b1.v + turn1 - b2.v - turn2;
  const Vec3 n_rate = b2.w.cross(n);
  return n_rate.dot(b1.v - b2.v) + (turn1.cross(n) + arms.r1.cross(n_rate)).dot(b1.w) -
         ((turn2 + d_rate).cross(n) + (arms.r2 + arms.d).cross(n_rate)).dot(b2.w);
}

void angularRow(const Vec3& a, double theta, Row& row) {
  row.Ja = block(Vec3::Zero(), a);
  row.Jb = block(Vec3::Zero(), -a);
  row.phi = theta;
}

void addPointStiffness(const Arms& arms, const Vec3& impulse, Mat12& k) {
  k.block<3, 3>(3, 3) += math::skew(impulse) * math::skew(arms.r1);
  k.block<3, 3>(9, 9) -= math::skew(impulse) * math::skew(arms.r2);
}

Vec3 pointImpulse(std::span<const Row> rows, std::span<const double> lambda) {
  Vec3 l = Vec3::Zero();
  for (std::size_t m = 0; m < rows.size(); ++m)
    if ((rows[m].key & 0xff) < 3) l += lambda[m] * rows[m].Ja.head<3>();
  return l;
}

void addBody2AxisStiffness(const Vec3& torque, Mat12& k) {
  k.block<3, 3>(3, 9) -= math::skew(torque);
  k.block<3, 3>(9, 9) += math::skew(torque);
}

void addBody1AxisStiffness(const Vec3& torque, Mat12& k) {
  k.block<3, 3>(3, 3) -= math::skew(torque);
  k.block<3, 3>(9, 3) += math::skew(torque);
}

double rowRate(const Row& row, const BodyState& b1, const BodyState& b2) {
  return row.Ja.head<3>().dot(b1.v) + row.Ja.tail<3>().dot(b1.w) + row.Jb.head<3>().dot(b2.v) +
         row.Jb.tail<3>().dot(b2.w);
}

bool limitRow(const JointContext& ctx, double bound, bool lower, double margin, Row& row) {
  if (!lower) {  // coordinate <= bound  <=>  -coordinate >= -bound
    row.Ja = -row.Ja;
    row.Jb = -row.Jb;
    row.phi = -row.phi;
    bound = -bound;
  }
  const double gap = row.phi - bound;  // >= 0 when admissible
  const double rate = rowRate(row, ctx.b1, ctx.b2);
  if (gap > margin && gap + ctx.h * rate >= 0.0) return false;
  row.phi = gap;
  row.kind = RowKind::Unilateral;
  row.lo = 0.0;
  row.hi = kInfinity;
  if (gap > 0.0) row.erp = 1.0;  // speculative: arrive exactly at the bound, never past it
  return true;
}

void motorRow(const JointContext& ctx, double target, double max_force, Row& row) {
  row.kind = RowKind::Motor;
  row.phi = 0.0;
  row.speed = target;
  row.lo = -ctx.h * max_force;
  row.hi = ctx.h * max_force;
}

void prescribedRow(const JointContext& ctx, const Signal& target, Row& row) {
  row.kind = RowKind::Bilateral;
  row.phi -= target.at(ctx.time);
  row.speed = target.rate(ctx.time);
  row.erp = 1.0;
  row.lo = -kInfinity;
  row.hi = kInfinity;
}

void frictionRow(const JointContext& ctx, double friction, Row& row) {
  motorRow(ctx, 0.0, friction, row);
  row.cfm = kFrictionSoftness * inverseMassAlong(row, ctx.m1, ctx.m2);
}

double inverseMassAlong(const Row& row, const BodyInertia& m1, const BodyInertia& m2) {
  const auto part = [](const Vec6& j, const BodyInertia& m) {
    return m.inv_mass * j.head<3>().squaredNorm() + j.tail<3>().dot(m.inv_inertia * j.tail<3>());
  };
  return part(row.Ja, m1) + part(row.Jb, m2);
}

double implicitShare(double stiffness, double inverse_mass, double h) {
  if (!(stiffness > 0.0) || !(inverse_mass > 0.0)) return kMinImplicitShare;
  // (h omega)^2 with omega^2 = k / m of the row alone.
  const double h2_omega2 = h * h * stiffness * inverse_mass;
  return std::max(kMinImplicitShare, 1.0 - 1.0 / h2_omega2);
}

void driveRow(const JointContext& ctx, double stiffness, double damping, double target_rate,
              double max_force, Row& row) {
  const double h = ctx.h;
  const double beta = implicitShare(stiffness, inverseMassAlong(row, ctx.m1, ctx.m2), h);
  const double d = damping + beta * h * stiffness;  // the force's part in the new rate
  row.kind = RowKind::Drive;
  // J u+ + lambda / (h d) = v_t - k phi / d, i.e. lambda = h (-k phi + d (v_t - J u+)): the
  // implicit share of the spring acts on the error's change, (J u+ - v_t) h, so a target moving at
  // v_t is followed without lag.
  row.cfm = 1.0 / (h * d);
  row.erp = h * stiffness / d;
  row.speed = target_rate;
  row.lo = -h * max_force;
  row.hi = h * max_force;
}

void forceRow(const JointContext& ctx, double force, Row& row) {
  row.kind = RowKind::Motor;
  row.phi = 0.0;
  row.speed = 0.0;
  row.lo = row.hi = ctx.h * force;
}

void armatureRow(const JointContext& ctx, double armature, Row& row) {
  const double rate =
      ctx.start ? rowRate(row, ctx.start->first, ctx.start->second) : rowRate(row, ctx.b1, ctx.b2);
  row.phi = 0.0;
  driveRow(ctx, 0.0, armature / ctx.h, rate, kInfinity, row);
}

}  // namespace linx::joints
