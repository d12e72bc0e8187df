// Every row's Jacobian against the time derivative of its own position error, by central finite
// differences along the motion u: dphi/dt must equal J u. Rows that are exact (point, linear,
// the slider's position) must match off the creation pose too; rows exact only at C = 0 (lock,
// align) are checked there. And each joint type's closed-form curvature (dJ/dt) u against the
// same differences of its own rows, and against the centripetal acceleration of a turning bob.
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

// (J(+eps) - J(-eps)) u / (2 eps), the bodies moved along u: the curvature by differences, as the
// accurate integrator measures it for a joint type without a closed form.
double rowsRateChange(const Joint& j, const BodyState& b1, const BodyState& b2, std::size_t k) {
  constexpr double eps = 1e-5;
  const auto fillAt = [&](double dt) {
    std::vector<Row> rows(static_cast<std::size_t>(j.maxRows()));
    rows.resize(static_cast<std::size_t>(
        j.fill(JointContext{advance(b1, dt), advance(b2, dt), 0.01, 0.2, 0.0}, rows)));
    return rows;
  };
  const std::vector<Row> after = fillAt(eps), before = fillAt(-eps);
  const Vec6 u1 = (Vec6() << b1.v, b1.w).finished(), u2 = (Vec6() << b2.v, b2.w).finished();
  return ((after[k].Ja - before[k].Ja).dot(u1) + (after[k].Jb - before[k].Jb).dot(u2)) /
         (2.0 * eps);
}

TEST(RowParts, ClosedFormCurvaturesMatchTheRowsDifferences) {
  std::mt19937 rng(5);
  int compared = 0;
  for (const char* type : {"hinge", "ball", "fixed", "distance", "slider", "universal"}) {
    for (int trial = 0; trial < 20; ++trial) {
      const BodyState c1 = randomState(rng), c2 = randomState(rng);
      JointDef def{.name = "j", .anchor = randomVec(rng, 1.0), .axis = randomVec(rng, 1.0)};
      if (std::string(type) == "distance") def.anchor2 = c2.pose.position + randomVec(rng, 0.3);
      if (std::string(type) == "universal") def.axis2 = def.axis.cross(randomVec(rng, 1.0));
      const std::unique_ptr<Joint> j = makeJoint(type, def, c1, c2);
      // Off the pose of creation: the joint open, every body moving and turning.
      const BodyState b1 = randomState(rng), b2 = randomState(rng);
      std::vector<Row> rows(static_cast<std::size_t>(j->maxRows()));
      rows.resize(static_cast<std::size_t>(j->fill(JointContext{b1, b2, 0.01, 0.2, 0.0}, rows)));
      std::vector<double> closed(rows.size());
      j->curvature(JointContext{b1, b2, 0.01, 0.2, 0.0}, rows, closed);
      for (std::size_t k = 0; k < rows.size(); ++k) {
        ASSERT_TRUE(std::isfinite(closed[k])) << type << " row " << k;
        const double numeric = rowsRateChange(*j, b1, b2, k);
        EXPECT_NEAR(closed[k], numeric, 1e-7 * (1.0 + std::abs(numeric)))
            << type << " trial " << trial << " row " << k;
        ++compared;
      }
    }
  }
  EXPECT_EQ(compared, 20 * (5 + 3 + 6 + 1 + 5 + 4));
}

// The limits the accurate integrator holds as equalities (a hinge's angle and a slider's position,
// both bounds, the upper's row the coordinate's negated; a rope at its length) have closed-form
// curvatures too, checked the same way, each joint with both bounds at its coordinate.
TEST(RowParts, LimitRowsClosedFormCurvaturesMatchTheRowsDifferences) {
  std::mt19937 rng(11);
  int compared = 0;
  for (const char* type : {"hinge", "slider", "distance"}) {
    for (int trial = 0; trial < 20; ++trial) {
      const BodyState c1 = randomState(rng), c2 = randomState(rng);
      JointDef def{.name = "j", .anchor = randomVec(rng, 1.0), .axis = randomVec(rng, 1.0)};
      if (std::string(type) == "distance") {
        def.anchor2 = c2.pose.position + randomVec(rng, 0.3);
        def.rope = true;
        def.length = 1e-3;  // taut: shorter than any distance the trials reach
      }
      const BodyState b1 = randomState(rng), b2 = randomState(rng);
      if (def.rope == false) {  // both bounds at the coordinate there: both rows on their bound
        const double x = makeJoint(type, def, c1, c2)->coordinates(b1, b2)[0];
        def.coordinates[0].limits = JointLimits{.lower = x, .upper = x};
      }
      const std::unique_ptr<Joint> j = makeJoint(type, def, c1, c2);
      std::vector<Row> rows(static_cast<std::size_t>(j->maxRows()));
      rows.resize(static_cast<std::size_t>(j->fill(JointContext{b1, b2, 0.01, 0.2, 0.0}, rows)));
      std::vector<double> closed(rows.size());
      j->curvature(JointContext{b1, b2, 0.01, 0.2, 0.0}, rows, closed);
      for (std::size_t k = 0; k < rows.size(); ++k) {
        if (rows[k].kind != RowKind::Unilateral) continue;
        ASSERT_TRUE(std::isfinite(closed[k])) << type << " row " << k;
        const double numeric = rowsRateChange(*j, b1, b2, k);
        EXPECT_NEAR(closed[k], numeric, 1e-7 * (1.0 + std::abs(numeric)))
            << type << " trial " << trial << " row " << k;
        ++compared;
      }
    }
  }
  EXPECT_EQ(compared, 20 * (2 + 2 + 1));
}

// A bob L from a hinge at the origin, turning about z at w: its point rows' curvature is w^2 L
// along the arm, so that J a = -(dJ/dt) u asks the bob for the centripetal acceleration -w^2 L;
// the align rows' is zero (the axis does not turn).
TEST(RowParts, TurningBobsCurvatureIsItsCentripetalAcceleration) {
  constexpr double L = 0.7, w = 3.0;
  const BodyState bob{Pose{Vec3(L, 0.0, 0.0), Quat::Identity()}, Vec3(0.0, w * L, 0.0),
                      Vec3(0.0, 0.0, w)};
  const BodyState world{};
  const std::unique_ptr<Joint> j =
      makeJoint("hinge", JointDef{.name = "pivot", .anchor = Vec3::Zero(), .axis = Vec3::UnitZ()},
                bob, world);
  const JointContext ctx{bob, world, 0.01, 0.2, 0.0};
  std::vector<Row> rows(static_cast<std::size_t>(j->maxRows()));
  rows.resize(static_cast<std::size_t>(j->fill(ctx, rows)));
  std::vector<double> closed(rows.size());
  j->curvature(ctx, rows, closed);
  ASSERT_EQ(rows.size(), 5u);
  // Row k holds e_k . (arm's acceleration); the bob's centre sits at the anchor: r1 = -L x.
  EXPECT_NEAR(closed[0], w * w * L, 1e-12);
  EXPECT_NEAR(closed[1], 0.0, 1e-12);
  EXPECT_NEAR(closed[2], 0.0, 1e-12);
  EXPECT_NEAR(closed[3], 0.0, 1e-12);
  EXPECT_NEAR(closed[4], 0.0, 1e-12);
}

}  // namespace
}  // namespace linx
