// The linear-time factorization of A = J M^-1 J^T + C for mechanisms without loops, against a
// dense LDL^T of the same matrix (independent truth), and its refusal of loops.
#include "solver/problem.hpp"
#include "solver/tree_factorization.hpp"

#include <gtest/gtest.h>
#include <Eigen/Dense>

#include <random>

namespace linx::solver {
namespace {

struct Mechanism {
  std::vector<Row> rows;
  std::vector<SolverBody> bodies;
};

// Random bodies (mass 0.1 to 1000 kg, full inertia), then random rows: `links` gives each group
// of rows its two bodies (-1: the world, or a static body when `static_body` is set).
Mechanism randomMechanism(std::mt19937& rng, int bodies,
                          const std::vector<std::pair<int, int>>& links, int rows_per_link,
                          int static_body = -1) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Mechanism m;
  for (int i = 0; i < bodies; ++i) {
    SolverBody b;
    if (i == static_body) {
      m.bodies.push_back(b);  // inverse mass and inertia zero
      continue;
    }
    const double mass = std::pow(10.0, 2.0 * u(rng) + 1.0);
    Mat3 r = Mat3::Random();
    const Mat3 inertia = mass * (r * r.transpose() + 0.1 * Mat3::Identity());
    b.inv_mass = 1.0 / mass;
    b.inv_inertia = inertia.inverse();
    m.bodies.push_back(b);
  }
  for (const auto& [a, b] : links) {
    for (int k = 0; k < rows_per_link; ++k) {
      Row row;
      row.body_a = a;
      row.body_b = b;
      for (int c = 0; c < 6; ++c) {
        row.Ja[c] = a >= 0 ? u(rng) : 0.0;
        row.Jb[c] = b >= 0 ? u(rng) : 0.0;
      }
      row.cfm = k % 2 == 0 ? 1e-10 : 0.0;
      m.rows.push_back(row);
    }
  }
  return m;
}

Eigen::MatrixXd denseA(const Mechanism& m) {
  const int n = static_cast<int>(m.rows.size());
  Eigen::MatrixXd J = Eigen::MatrixXd::Zero(n, 6 * static_cast<int>(m.bodies.size()));
  Eigen::MatrixXd Minv = Eigen::MatrixXd::Zero(J.cols(), J.cols());
  for (std::size_t i = 0; i < m.bodies.size(); ++i) {
    const int o = 6 * static_cast<int>(i);
    Minv.block(o, o, 3, 3) = m.bodies[i].inv_mass * Mat3::Identity();
    Minv.block(o + 3, o + 3, 3, 3) = m.bodies[i].inv_inertia;
  }
  for (int k = 0; k < n; ++k) {
    const Row& r = m.rows[static_cast<std::size_t>(k)];
    if (r.body_a >= 0) J.block(k, 6 * r.body_a, 1, 6) += r.Ja.transpose();
    if (r.body_b >= 0) J.block(k, 6 * r.body_b, 1, 6) += r.Jb.transpose();
  }
  Eigen::MatrixXd A = J * Minv * J.transpose();
  for (int k = 0; k < n; ++k) A(k, k) += m.rows[static_cast<std::size_t>(k)].cfm;
  return A;
}

// Solves A_FF x = b with both the tree factorization and a dense LDL^T; returns the largest
// difference relative to the solution's size.
double compare(Mechanism& m, const std::vector<std::uint8_t>& free, std::mt19937& rng,
               int* redundant) {
  std::vector<double> lambda(m.rows.size(), 0.0);
  Problem p{m.rows, m.bodies, lambda, 1e-3};
  TreeFactorization tree;
  EXPECT_TRUE(tree.analyse(p));
  *redundant = tree.factorize(p, free);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<double> x(m.rows.size());
  std::vector<int> index;
  for (std::size_t k = 0; k < x.size(); ++k) {
    x[k] = u(rng);
    if (free[k]) index.push_back(static_cast<int>(k));
  }
  const Eigen::MatrixXd A = denseA(m);
  Eigen::MatrixXd Aff(index.size(), index.size());
  Eigen::VectorXd b(index.size());
  for (std::size_t i = 0; i < index.size(); ++i) {
    b[static_cast<int>(i)] = x[static_cast<std::size_t>(index[i])];
    for (std::size_t j = 0; j < index.size(); ++j)
      Aff(static_cast<int>(i), static_cast<int>(j)) = A(index[i], index[j]);
  }
  const Eigen::VectorXd expected = Aff.ldlt().solve(b);
  tree.solve(x);
  double worst = 0.0;
  for (std::size_t i = 0; i < index.size(); ++i)
    worst = std::max(
        worst, std::abs(x[static_cast<std::size_t>(index[i])] - expected[static_cast<int>(i)]));
  for (std::size_t k = 0; k < x.size(); ++k) {
    if (!free[k]) {
      EXPECT_EQ(x[k], 0.0) << "a held row must come back zero";
    }
  }
  return worst / expected.lpNorm<Eigen::Infinity>();
}

TEST(TreeFactorization, ChainHangingFromTheWorldMatchesDenseLdlt) {
  std::mt19937 rng(1);
  std::vector<std::pair<int, int>> links{{0, -1}};
  for (int i = 1; i < 30; ++i) links.push_back({i, i - 1});
  Mechanism m = randomMechanism(rng, 30, links, 5);
  int redundant = -1;
  const double err = compare(m, std::vector<std::uint8_t>(m.rows.size(), 1), rng, &redundant);
  std::printf("30-link chain, 150 rows: relative difference to dense LDL^T %.2e\n", err);
  EXPECT_LT(err, 1e-9);
  EXPECT_EQ(redundant, 0);
}

TEST(TreeFactorization, BranchedTreeWithHeldRowsAndAStaticBodyMatchesDenseLdlt) {
  std::mt19937 rng(2);
  // Body 0 is the root (grounded through a static body 9); 1..8 branch off it and each other;
  // rows per link vary; some rows are held at a bound (not free).
  const std::vector<std::pair<int, int>> links{{0, 9}, {1, 0}, {2, 0}, {3, 0}, {4, 1},
                                               {5, 1}, {6, 2}, {7, 6}, {8, 6}};
  Mechanism m = randomMechanism(rng, 10, links, 4, 9);
  std::vector<std::uint8_t> free(m.rows.size(), 1);
  for (std::size_t k = 0; k < free.size(); k += 3) free[k] = 0;
  int redundant = -1;
  const double err = compare(m, free, rng, &redundant);
  std::printf("branched tree, %zu rows: relative difference to dense LDL^T %.2e\n", m.rows.size(),
              err);
  EXPECT_LT(err, 1e-9);
  EXPECT_EQ(redundant, 0);
}

TEST(TreeFactorization, FloatingTreeAndSeveralTreesMatchDenseLdlt) {
  std::mt19937 rng(3);
  const std::vector<std::pair<int, int>> links{{1, 0}, {2, 1}, {4, 3}, {5, 3}, {3, -1}};
  Mechanism m = randomMechanism(rng, 6, links, 3);
  int redundant = -1;
  const double err = compare(m, std::vector<std::uint8_t>(m.rows.size(), 1), rng, &redundant);
  EXPECT_LT(err, 1e-9);
}

TEST(TreeFactorization, CountsADuplicatedRowAsRedundant) {
  std::mt19937 rng(4);
  Mechanism m = randomMechanism(rng, 3, {{0, -1}, {1, 0}, {2, 1}}, 4);
  Row copy = m.rows[5];
  m.rows.push_back(copy);  // the same constraint twice, between bodies 1 and 0
  m.rows.back().cfm = 1e-10;
  m.rows[5].cfm = 1e-10;
  std::vector<double> lambda(m.rows.size(), 0.0);
  Problem p{m.rows, m.bodies, lambda, 1e-3};
  TreeFactorization tree;
  ASSERT_TRUE(tree.analyse(p));
  EXPECT_EQ(tree.factorize(p, std::vector<std::uint8_t>(m.rows.size(), 1)), 1);
}

TEST(TreeFactorization, RefusesLoopsIncludingLoopsThroughTheWorld) {
  std::mt19937 rng(5);
  for (const auto& links : {std::vector<std::pair<int, int>>{{1, 0}, {2, 1}, {0, 2}},
                            std::vector<std::pair<int, int>>{{0, -1}, {1, 0}, {1, -1}}}) {
    Mechanism m = randomMechanism(rng, 3, links, 2);
    std::vector<double> lambda(m.rows.size(), 0.0);
    Problem p{m.rows, m.bodies, lambda, 1e-3};
    TreeFactorization tree;
    EXPECT_FALSE(tree.analyse(p));
  }
}

}  // namespace
}  // namespace linx::solver
