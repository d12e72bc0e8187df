// The two solvers against each other and against small problems with known solutions.
#include "mechanisms.hpp"

#include "solver/dense_equalities.hpp"
#include "solver/exact_solver.hpp"
#include "solver/pgs_solver.hpp"
#include "solver/row_system.hpp"

#include <gtest/gtest.h>

#include <random>

namespace linx {
namespace {

World doublePendulum(const SolverSettings& solver) {
  World w(WorldSettings{.gravity = Vec3(0, 0, -9.81), .timestep = 1e-3, .solver = solver});
  const BodyId a = w.createBody(test::boxBody("upper", 1.0, Vec3(1, 0.05, 0.05), Vec3(0.5, 0, 0)));
  const BodyId b = w.createBody(test::boxBody("lower", 2.0, Vec3(1, 0.05, 0.05), Vec3(1.5, 0, 0)));
  w.createJoint(
      "hinge",
      JointDef{.name = "shoulder", .body1 = a, .anchor = Vec3::Zero(), .axis = Vec3::UnitY()});
  w.createJoint(
      "hinge",
      JointDef{
          .name = "elbow", .body1 = b, .body2 = a, .anchor = Vec3(1, 0, 0), .axis = Vec3::UnitY()});
  return w;
}

TEST(Solvers, GiveTheSameMotionOnAMechanismWithoutUnilateralRows) {
  // The same LCP: without post-stabilization, which only the exact solver's factorization gives.
  SolverSettings exact, pgs;
  exact.post_stabilization = pgs.post_stabilization = 0;
  pgs.type = SolverType::Pgs;
  pgs.iterations = 2000;
  pgs.tolerance = 1e-13;
  World we = doublePendulum(exact), wp = doublePendulum(pgs);
  double worst = 0.0;
  for (int i = 0; i < 1000; ++i) {
    we.step();
    wp.step();
    for (int k = 0; k < 2; ++k)
      worst =
          std::max(worst, (we.body(BodyId{k}).position() - wp.body(BodyId{k}).position()).norm());
  }
  std::printf("double pendulum, 1 s: largest position difference exact vs PGS %.2e m\n", worst);
  // Both solve the same LCP; a converged PGS differs only by its tolerance, fed through a chaotic
  // mechanism for a second.
  EXPECT_LT(worst, 1e-8);
  EXPECT_LT(we.lastReport().residual, 1e-10);
  EXPECT_TRUE(we.lastReport().converged);
}

// A single free body of mass 2 kg and one row straight down the z axis at its centre.
struct OneRow {
  std::vector<Row> rows{1};
  std::vector<solver::SolverBody> bodies{1};
  std::vector<double> lambda{0.0};
  OneRow(double vz, double lo, double hi) {
    bodies[0] = solver::SolverBody{0.5, Mat3::Identity(), Vec3(0, 0, vz), Vec3::Zero()};
    rows[0].Ja << 0, 0, 1, 0, 0, 0;
    rows[0].body_a = 0;
    rows[0].lo = lo;
    rows[0].hi = hi;
    rows[0].cfm = 0.0;
    rows[0].kind = RowKind::Unilateral;
  }
  solver::Problem problem() { return solver::Problem{rows, bodies, lambda, 1e-3}; }
};

TEST(Solvers, UnilateralRowPushesOnlyWhenApproaching) {
  for (const SolverType type : {SolverType::Exact, SolverType::Pgs}) {
    auto s = solver::makeSolver(type);
    OneRow falling(-0.3, 0.0, kInfinity);
    auto p = falling.problem();
    s->solve(p, SolverSettings{});
    EXPECT_NEAR(falling.lambda[0], 2.0 * 0.3, 1e-12);  // m |v|: stops it exactly
    EXPECT_NEAR(falling.bodies[0].v.z(), 0.0, 1e-12);
    OneRow rising(0.3, 0.0, kInfinity);
    auto q = rising.problem();
    s->solve(q, SolverSettings{});
    EXPECT_EQ(rising.lambda[0], 0.0);  // separating: no pull
    EXPECT_NEAR(rising.bodies[0].v.z(), 0.3, 1e-15);
  }
}

TEST(Solvers, BoxedRowSaturatesAtItsBound) {
  for (const SolverType type : {SolverType::Exact, SolverType::Pgs}) {
    auto s = solver::makeSolver(type);
    OneRow motor(-0.3, -0.1, 0.1);  // would need 0.6 N s, gets 0.1
    auto p = motor.problem();
    const SolverReport r = s->solve(p, SolverSettings{});
    EXPECT_NEAR(motor.lambda[0], 0.1, 1e-15);
    EXPECT_NEAR(motor.bodies[0].v.z(), -0.3 + 0.5 * 0.1, 1e-15);
    EXPECT_LT(r.residual, 1e-12);
  }
}

TEST(Solvers, ExactSolverSurvivesAndReportsRedundantRows) {
  // The same bilateral row three times: A is rank one. Any split of the impulse is a solution;
  // the solver must return one, finite, that stops the body, and count two redundant rows.
  std::vector<Row> rows(3);
  for (Row& r : rows) {
    r.Ja << 0, 0, 1, 0, 0, 0;
    r.body_a = 0;
    r.cfm = 0.0;
  }
  std::vector<solver::SolverBody> bodies{
      solver::SolverBody{0.5, Mat3::Identity(), Vec3(0, 0, -1), Vec3::Zero()}};
  std::vector<double> lambda(3, 0.0);
  solver::Problem p{rows, bodies, lambda, 1e-3};
  solver::ExactSolver s;
  const SolverReport r = s.solve(p, SolverSettings{});
  EXPECT_EQ(r.redundant_rows, 2);
  EXPECT_NEAR(lambda[0] + lambda[1] + lambda[2], 2.0, 1e-9);
  EXPECT_NEAR(bodies[0].v.z(), 0.0, 1e-9);
  EXPECT_LT(r.residual, 1e-9);
}

TEST(Solvers, DenseEqualitiesMatchTheExactSolver) {
  // Random bilateral rows between three bodies and the world (the accurate integrator's small
  // islands): the dense solve must give the exact solver's impulses and velocities, and then
  // J u = xi - cfm lambda on every row.
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int trial = 0; trial < 20; ++trial) {
    const int n = 3 + trial % 10;
    std::vector<Row> rows(static_cast<std::size_t>(n));
    for (int k = 0; k < n; ++k) {
      Row& r = rows[static_cast<std::size_t>(k)];
      r.body_a = k % 3;
      r.body_b = k % 4 == 3 ? -1 : (k + 1) % 3;
      for (int c = 0; c < 6; ++c) {
        r.Ja[c] = u(rng);
        r.Jb[c] = u(rng);
      }
      r.speed = u(rng);
      r.erp = 0.0;
      r.cfm = 1e-6 * (1.0 + u(rng));
    }
    std::vector<solver::SolverBody> start;
    for (int b = 0; b < 3; ++b) {
      const Mat3 root = Mat3::Random() + 2.0 * Mat3::Identity();
      start.push_back({1.0 / (1.0 + b), root * root.transpose(), Vec3::Random(), Vec3::Random()});
    }
    auto dense_bodies = start, exact_bodies = start;
    std::vector<double> dense(static_cast<std::size_t>(n), 0.0), exact = dense;
    solver::Problem dp{rows, dense_bodies, dense, 1.0};
    solver::Problem ep{rows, exact_bodies, exact, 1.0};
    solver::DenseEqualities d;
    ASSERT_TRUE(d.solve(dp, false)) << "trial " << trial;
    solver::ExactSolver().solve(ep, SolverSettings{});
    for (int k = 0; k < n; ++k) {
      const auto i = static_cast<std::size_t>(k);
      EXPECT_NEAR(dense[i], exact[i], 1e-8 * (1.0 + std::abs(exact[i]))) << "trial " << trial;
      const double rate = solver::RowSystem::rate(rows[i], dense_bodies);
      EXPECT_NEAR(rate, rows[i].speed - rows[i].cfm * dense[i], 1e-10) << "trial " << trial;
    }
    for (std::size_t b = 0; b < 3; ++b)
      EXPECT_LT((dense_bodies[b].w - exact_bodies[b].w).norm(), 1e-8) << "trial " << trial;
  }
}

TEST(Solvers, DenseEqualitiesLeaveRedundantRowsWithoutCfmToTheExactSolver) {
  // The same row three times: A is rank one. Asked to refuse redundant rows (as the projection),
  // the dense solve refuses it and leaves the body alone; with cfm the rows share the impulse
  // that stops the body (to cfm's give).
  std::vector<Row> rows(3);
  for (Row& r : rows) {
    r.Ja << 0, 0, 1, 0, 0, 0;
    r.body_a = 0;
    r.erp = 0.0;
    r.cfm = 0.0;
  }
  std::vector<solver::SolverBody> bodies{
      solver::SolverBody{0.5, Mat3::Identity(), Vec3(0, 0, -1), Vec3::Zero()}};
  std::vector<double> lambda(3, 0.0);
  solver::Problem p{rows, bodies, lambda, 1.0};
  solver::DenseEqualities d;
  EXPECT_FALSE(d.solve(p, false));
  EXPECT_EQ(bodies[0].v.z(), -1.0);
  for (Row& r : rows) r.cfm = 1e-9;
  ASSERT_TRUE(d.solve(p, true));
  EXPECT_NEAR(lambda[0] + lambda[1] + lambda[2], 2.0, 1e-7);
  EXPECT_NEAR(lambda[0], lambda[2], 1e-6);  // equal shares, to round-off times A's 2e9 condition
  EXPECT_NEAR(bodies[0].v.z(), 0.0, 1e-8);
}

TEST(Solvers, RedundantRowCountDoesNotDependOnMassScale) {
  // Regression: two identical fixed joints to the world, 12 rows of which 6 are redundant. The
  // count once compared an absolute pivot with a relative threshold and missed them for heavy
  // bodies.
  for (const double mass : {1e-3, 1.0, 1e3, 1e5}) {
    WorldSettings s;
    s.integrator.type = IntegratorType::Step;  // the exact solver's count (not the accurate's)
    World w(s);
    BodyDef d = test::boxBody("b", mass, Vec3(0.3, 0.2, 0.1), Vec3(0.1, 0.2, 0.3));
    const BodyId b = w.createBody(d);
    w.createJoint("fixed", JointDef{.name = "weld1", .body1 = b});
    w.createJoint("fixed", JointDef{.name = "weld2", .body1 = b});
    w.step();
    EXPECT_EQ(w.lastReport().redundant_rows, 6) << "mass " << mass;
    // cfm is a compliance: the pair of welds, each carrying half of m g h, gives way at
    // cfm m g h / 2 (4.9e-8 m/s for 1e5 kg).
    const double give = w.settings().solver.cfm * mass * 9.81 * w.settings().timestep / 2;
    EXPECT_LT(w.body(b).linearVelocity().norm(), 1.01 * give + 1e-12) << "mass " << mass;
  }
}

TEST(Solvers, BothMeetComplementarityWithActiveLimitsAndMotors) {
  // A slider-crank whose crank hinge also has a limit it runs into: bilateral, unilateral and
  // boxed rows together. Both solvers must end every step complementary.
  for (const SolverType type : {SolverType::Exact, SolverType::Pgs}) {
    SolverSettings s;
    s.type = type;
    s.iterations = type == SolverType::Pgs ? 500 : 50;
    s.tolerance = 1e-9;
    test::SliderCrank m(s);
    m.world.joint(m.crank_hinge).setLimits(JointLimits{.lower = -1.0, .upper = 1.0});
    double worst = 0.0, highest = 0.0;
    for (int i = 0; i < 500; ++i) {
      m.world.step();
      worst = std::max(worst, m.world.lastReport().residual);
      highest = std::max(highest, m.world.jointCoordinates(m.crank_hinge)[0]);
    }
    std::printf("%s: largest residual %.1e, highest crank angle %.6f\n",
                std::string(solverTypeName(type)).c_str(), worst, highest);
    EXPECT_LT(highest, 1.0 + 1e-4);  // the limit beats the 100 N m motor
    EXPECT_NEAR(m.world.jointCoordinates(m.crank_hinge)[0], 1.0, 1e-4);
    EXPECT_LT(worst, type == SolverType::Exact ? 1e-9 : 1e-6);
  }
}

}  // namespace
}  // namespace linx
