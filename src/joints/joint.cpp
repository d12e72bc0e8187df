#include <linx/joint.hpp>

#include "joints/validation.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

namespace linx {

void Joint::setMotor(std::optional<JointMotor> motor) {
  JointDef next = def_;
  next.motor = motor;
  joints::validate(*findJointType(type()), next);
  def_ = next;
}

void Joint::setLimits(std::optional<JointLimits> limits) {
  JointDef next = def_;
  next.limits = limits;
  joints::validate(*findJointType(type()), next);
  def_ = next;
}

double Joint::error(const BodyState& b1, const BodyState& b2) const {
  // The rows' own phi is the error: equality rows count fully, limits only when overshot. Zero
  // velocities keep not-yet-reached limits out; h only scales the (unused) bias.
  const BodyState s1{b1.pose, Vec3::Zero(), Vec3::Zero()};
  const BodyState s2{b2.pose, Vec3::Zero(), Vec3::Zero()};
  std::vector<Row> rows(static_cast<std::size_t>(maxRows()));
  const int n = fill(JointContext{s1, s2, 1.0, 0.0, 0.0}, rows);
  double err = 0.0;
  for (int k = 0; k < n; ++k) {
    const Row& r = rows[static_cast<std::size_t>(k)];
    if (r.kind == RowKind::Bilateral) err = std::max(err, std::abs(r.phi));
    if (r.kind == RowKind::Unilateral) err = std::max(err, -r.phi);
  }
  return err;
}

}  // namespace linx
