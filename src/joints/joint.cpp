#include <linx/joint.hpp>

#include "world/state_archive.hpp"

#include "joints/row_parts.hpp"
#include "joints/validation.hpp"
#include "math/rotation.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <vector>

namespace linx {

namespace {
// A copy of `def` with coordinate `index` changed by `edit`, checked against the joint's type.
template <class Edit>
JointDef edited(const Joint& joint, int index, Edit&& edit) {
  const JointTypeInfo& type = *findJointType(joint.type());
  if (index < 0 || index >= joint.freeCoordinates())
    throw std::invalid_argument(fmt::format("coordinate {}: a {} joint has {} free coordinates",
                                            index, type.name, joint.freeCoordinates()));
  JointDef next = joint.def();
  edit(next.coordinates[static_cast<std::size_t>(index)]);
  joints::validate(type, next);
  return next;
}
}  // namespace

int Joint::freeCoordinates() const {
  const JointTypeInfo* type = findJointType(this->type());
  return type ? type->freeCoordinates(def_) : 0;
}

void Joint::setMotor(std::optional<JointMotor> motor, int coordinate) {
  def_ = edited(*this, coordinate, [&](CoordinateDef& c) { c.motor = std::move(motor); });
}

void Joint::setLimits(std::optional<JointLimits> limits, int coordinate) {
  def_ = edited(*this, coordinate, [&](CoordinateDef& c) { c.limits = limits; });
}

void Joint::setSpring(std::optional<JointSpring> spring, int coordinate) {
  def_ = edited(*this, coordinate, [&](CoordinateDef& c) { c.spring = spring; });
}

void Joint::setForce(std::optional<Signal> force, int coordinate) {
  def_ = edited(*this, coordinate, [&](CoordinateDef& c) { c.force = std::move(force); });
}

void Joint::setFriction(double friction, int coordinate) {
  def_ = edited(*this, coordinate, [&](CoordinateDef& c) { c.friction = friction; });
}

double Joint::error(const BodyState& b1, const BodyState& b2,
                    const std::array<BodyState, 2>& more) const {
  // The rows' own phi is the error: equality rows count fully, limits only when overshot. Zero
  // velocities keep not-yet-reached limits out; h only scales the (unused) bias. A prescribed
  // coordinate's target is taken in time, which this does not know: its row does not count.
  const auto still = [](const BodyState& b) {
    return BodyState{b.pose, Vec3::Zero(), Vec3::Zero()};
  };
  JointContext ctx{still(b1), still(b2), 1.0, 0.0, 0.0};
  ctx.more = {still(more[0]), still(more[1])};
  std::vector<Row> rows(static_cast<std::size_t>(maxRows()));
  const int n = fill(ctx, rows);
  double err = 0.0;
  for (int k = 0; k < n; ++k) {
    const Row& r = rows[static_cast<std::size_t>(k)];
    if (r.kind == RowKind::Bilateral && !joints::isPrescribedSlot(static_cast<int>(r.key & 0xff)))
      err = std::max(err, std::abs(r.phi));
    if (r.kind == RowKind::Unilateral) err = std::max(err, -r.phi);
  }
  return err;
}

namespace {

// A pose moved along one of its 6 coordinates: translation (0-2) or rotation about a world axis
// (3-5).
Pose moved(const Pose& pose, int coordinate, double delta) {
  Pose p = pose;
  if (coordinate < 3)
    p.position[coordinate] += delta;
  else
    p.orientation =
        (math::expMap(delta * Vec3::Unit(coordinate - 3)) * pose.orientation).normalized();
  return p;
}

// J^T lambda of `rows`, the impulses matched to `of` by slot (a limit may come or go between two
// fills).
Eigen::Matrix<double, 12, 1> force(std::span<const Row> rows, std::span<const Row> of,
                                   std::span<const double> lambda) {
  Eigen::Matrix<double, 12, 1> f = Eigen::Matrix<double, 12, 1>::Zero();
  for (std::size_t m = 0; m < of.size(); ++m) {
    for (const Row& r : rows) {
      if (r.key != of[m].key) continue;
      f.head<6>() += lambda[m] * r.Ja;
      f.tail<6>() += lambda[m] * r.Jb;
      break;
    }
  }
  return f;
}

}  // namespace

void Joint::curvature(const JointContext& /*ctx*/, std::span<const Row> rows,
                      std::span<double> out) const {
  joints::curvatureBySlot(rows, out, [](int) { return joints::kMeasuredCurvature; });
}

Mat12 Joint::stiffness(const JointContext& ctx, std::span<const Row> rows,
                       std::span<const double> lambda) const {
  // Central differences: truncation (delta^2) and cancellation (1e-16 / delta) both near 1e-11
  // relative for a step of 1e-5 m or rad on joints of centimetres to metres.
  constexpr double kDelta = 1e-5;
  std::vector<Row> scratch(static_cast<std::size_t>(maxRows()));
  const auto fillAt = [&](const JointContext& c) {
    const int n = fill(c, scratch);
    return std::span<const Row>(scratch).first(static_cast<std::size_t>(n));
  };
  // Slots only: the rows given come from assembly, which added the owner to the key.
  std::vector<Row> own(rows.begin(), rows.end());
  for (Row& r : own) r.key &= 0xff;
  Mat12 k;
  for (int c = 0; c < 12; ++c) {
    // A joint's rows see only where the bodies are relative to each other: moving both along the
    // same vector changes nothing, so body 2's shift columns are body 1's, negated.
    if (c >= 6 && c < 9) {
      k.col(c) = -k.col(c - 6);
      continue;
    }
    JointContext plus = ctx, minus = ctx;
    BodyState& p = c < 6 ? plus.b1 : plus.b2;
    BodyState& m = c < 6 ? minus.b1 : minus.b2;
    p.pose = moved(p.pose, c % 6, kDelta);
    m.pose = moved(m.pose, c % 6, -kDelta);
    const auto f_plus = force(fillAt(plus), own, lambda);
    k.col(c) = (f_plus - force(fillAt(minus), own, lambda)) / (2.0 * kDelta);
  }
  return k;
}

void Joint::persist(state::Archive& a) {
  a(enabled_);
  persistTracked(a);
}

}  // namespace linx
