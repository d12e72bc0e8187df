// Every row's Jacobian against the time derivative of its own position error, by central finite
// differences along the motion u: dphi/dt must equal J u. Rows that are exact (point, linear,
// the slider's position) must match off the creation pose too; rows exact only at C = 0 (lock,
// align) are checked there.
#include "random_state.hpp"
#include "support.hpp"

#include "joints/row_parts.hpp"
#include "math/rotation.hpp"

#include <gtest/gtest.h>

#include <random>

namespace linx {
namespace {

BodyState advance(const BodyState& s, double dt) {
  return BodyState{Pose{s.pose.position + dt * s.v, math::integrate(s.pose.orientation, s.w, dt)},
                   s.v, s.w};
}

using test::randomState;
using test::randomVec;

// Largest |dphi/dt - J u| over the rows a fill function writes.
template <class Fill>
double mismatch(const BodyState& b1, const BodyState& b2, Fill&& fill) {
  constexpr double eps = 1e-6;
  std::vector<Row> now(8), ahead(8), behind(8);
  const int n = fill(b1, b2, now);
  fill(advance(b1, eps), advance(b2, eps), ahead);
  fill(advance(b1, -eps), advance(b2, -eps), behind);
  double worst = 0.0;
  for (int k = 0; k < n; ++k) {
    const double dphi = (ahead[k].phi - behind[k].phi) / (2 * eps);
    worst = std::max(worst, std::abs(dphi - joints::rowRate(now[k], b1, b2)));
  }
  return worst;
}

TEST(RowParts, PointAndLinearRowsAreExactDerivativesAnywhere) {
  std::mt19937 rng(7);
  for (int trial = 0; trial < 50; ++trial) {
    const BodyState c1 = randomState(rng), c2 = randomState(rng);
    const JointDef def{.name = "j", .anchor = randomVec(rng, 1.0), .axis = randomVec(rng, 1.0)};
    const joints::JointFrames f = joints::JointFrames::capture(def, c1, c2);
    // Then the bodies move away from the pose of creation, off the constraint.
    const BodyState b1 = randomState(rng), b2 = randomState(rng);
    const double point =
        mismatch(b1, b2, [&](const BodyState& s1, const BodyState& s2, auto& rows) {
          joints::pointRows(joints::Arms::of(f, s1, s2), std::span<Row, 3>(rows.data(), 3));
          return 3;
        });
    // The slider's two linear rows (tangents fixed in body 2) and its position along the axis.
    const double linear =
        mismatch(b1, b2, [&](const BodyState& s1, const BodyState& s2, auto& rows) {
          const joints::Arms arms = joints::Arms::of(f, s1, s2);
          Vec3 t1, t2;
          f.tangents(s2, t1, t2);
          joints::linearRow(arms, t1, rows[0]);
          joints::linearRow(arms, t2, rows[1]);
          joints::linearRow(arms, s2.pose.orientation * f.axis2, rows[2]);
          return 3;
        });
    ASSERT_LT(point, 1e-7) << "trial " << trial;
    ASSERT_LT(linear, 1e-7) << "trial " << trial;
  }
}

TEST(RowParts, LockAndAlignRowsAreExactAtZeroError) {
  std::mt19937 rng(11);
  for (int trial = 0; trial < 50; ++trial) {
    const BodyState c1 = randomState(rng), c2 = randomState(rng);
    const JointDef def{.name = "j", .anchor = randomVec(rng, 1.0), .axis = randomVec(rng, 1.0)};
    const joints::JointFrames f = joints::JointFrames::capture(def, c1, c2);
    // At the pose of creation (C = 0), with any velocities.
    const double lock = mismatch(c1, c2, [&](const BodyState& s1, const BodyState& s2, auto& rows) {
      joints::lockRows(f, s1, s2, std::span<Row, 3>(rows.data(), 3));
      return 3;
    });
    const double align =
        mismatch(c1, c2, [&](const BodyState& s1, const BodyState& s2, auto& rows) {
          joints::alignRows(f, s1, s2, std::span<Row, 2>(rows.data(), 2));
          return 2;
        });
    ASSERT_LT(lock, 1e-7) << "trial " << trial;
    ASSERT_LT(align, 1e-7) << "trial " << trial;
  }
}

}  // namespace
}  // namespace linx
