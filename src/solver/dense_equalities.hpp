// Small systems of equality rows, solved dense: the accurate integrator's acceleration solve on an
// island of a few bodies (a pendulum, a top, a short chain or a small loop), and its projections.
// At that size the exact solver's machinery (the row system it builds, its active set, the tree
// analysis, the block factorization of bodies and rows together) costs more than the solve: here
// A = J M^-1 J^T + diag(cfm) is formed entry by entry and factored by L D L^T
// (solver/dense_ldlt.hpp) in fixed-capacity storage, with the exact solver's pivot shift and
// refinement, so that the two give the same impulses to round-off.
#pragma once

#include "solver/problem.hpp"

#include <Eigen/Dense>

#include <array>
#include <cstddef>
#include <span>

namespace linx::solver {

class DenseEqualities {
 public:
  /// The most rows solved here: beyond it the tree and sparse factorizations are cheaper
  /// (measured on chains of hinges with the accurate integrator, 2 s: 25 rows dense 0.22 s, by
  /// the tree 0.23 s; 45 rows, before the refinement, already 0.67 s against the tree's 0.58 s).
  static constexpr int kMaxRows = 32;

  /// Solves A lambda = xi - J u* for rows that are all equalities (their bounds are not looked
  /// at), A = J M^-1 J^T + diag(cfm), as the exact solver would; the bodies then hold
  /// u* + M^-1 J^T lambda, and lambda the impulses. Returns false, having changed nothing, when
  /// there are more than kMaxRows rows, A is not positive definite, or, unless `redundant_rows`,
  /// rows are redundant (a pivot that is nothing but cfm and the shift, as the exact solver counts
  /// them: without cfm only its regularized solve keeps their impulses finite): the caller solves
  /// otherwise.
  bool solve(Problem& p, bool redundant_rows);
  /// x (one entry per row) <- A^-1 x with the last successful solve's factorization.
  void backSolve(std::span<double> x) const;

 private:
  using Vector = Eigen::Matrix<double, Eigen::Dynamic, 1, Eigen::ColMajor, kMaxRows, 1>;

  std::array<std::array<Vec6, 4>, kMaxRows> w_;  // M^-1 J^T of each row's blocks a, b, c, d
  std::array<double, kMaxRows * kMaxRows> a_{}, factor_{};  // A; its L D L^T (column-major, n x n)
  Vector rhs_, x_, r_;
  int n_ = 0;  // the rows of the last successful solve
};

}  // namespace linx::solver
