// The exact solver's linear algebra (solver/exact_solver.hpp), one back-end per kind of
// mechanism behind one interface. With A = J M^-1 J^T + diag(cfm) and b = J u* - xi, a back-end
// solves the free rows F with the others C held at their impulses,
//     A_FF x = -(b_F + A_FC lambda_C),
// by a factorization with a tiny diagonal shift (so that redundant rows, A_FF singular, stay
// finite) and refinement against the unshifted matrix (refine below), counts the redundant
// pivots, gives the rows' rates w = A lambda + b for the active-set loop, and back-substitutes
// with its last factorization (the post-stabilization's projections).
//
//   TreeFreeRows   mechanisms without loops: O(n) along the tree (solver/tree_factorization),
//                  A never formed (A x from the rows and M^-1 J^T alone)
//   DenseFreeRows  small loops (at most 64 rows): A dense, an LDL^T without pivoting
//   SparseFreeRows larger loops: A sparse, Eigen's simplicial LDL^T with a fill-reducing order
#pragma once

#include "solver/problem.hpp"
#include "solver/row_system.hpp"
#include "solver/tree_factorization.hpp"

#include <Eigen/Dense>
#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>

#include <array>
#include <cmath>
#include <cstdint>
#include <span>
#include <vector>

namespace linx::solver {

class FreeRows {
 public:
  virtual ~FreeRows() = default;
  /// Takes a new problem's rows (their W = M^-1 J^T in `sys`), before any solve.
  virtual void assemble(const Problem& p, const RowSystem& sys) = 0;
  /// Rows with free[k] != 0 are free, the others held at lambda[k]; b = J u* - xi. Writes the
  /// free rows' impulses into lambda and returns the number of redundant pivots.
  virtual int solve(const Problem& p, std::span<const std::uint8_t> free, const Eigen::VectorXd& b,
                    std::span<double> lambda) = 0;
  /// w = A lambda + b.
  virtual void rates(const Problem& p, std::span<const double> lambda, const Eigen::VectorXd& b,
                     Eigen::VectorXd& w) = 0;
  /// x (one entry per row) <- A_FF^-1 x on the last solve's free rows, 0 on the others.
  virtual void backSolve(std::span<double> x) = 0;
};

/// Refinement of x against the unshifted matrix: with r = rhs - A x (`residual(x, r)` fills r
/// and returns its largest entry, `res` for the x given), x += F^-1 r (`correct(r)` applies the
/// shifted factorization in place), at most three times and only while the residual at least
/// halves: with inconsistent redundant rows (cfm = 0) further steps would only grow the impulses
/// along the null space. `scale`: the largest entry of rhs. Vector: an Eigen vector (of fixed
/// capacity for small systems: no allocation).
template <class Vector, class Residual, class Correct>
void refine(Vector& x, Vector& r, double res, double scale, Residual&& residual,
            Correct&& correct) {
  Vector candidate;
  for (int k = 0; k < 3 && res > 1e-15 * (1.0 + scale); ++k) {
    correct(r);
    candidate = r + x;
    const double next = residual(candidate, r);
    if (!(next < 0.5 * res)) break;
    x.swap(candidate);
    res = next;
  }
}

class TreeFreeRows final : public FreeRows {
 public:
  /// Whether the problem's rows form a tree this back-end can factor (TreeFactorization::analyse).
  bool fits(const Problem& p) { return factor_.analyse(p); }
  void assemble(const Problem& p, const RowSystem& sys) override;
  int solve(const Problem& p, std::span<const std::uint8_t> free, const Eigen::VectorXd& b,
            std::span<double> lambda) override;
  void rates(const Problem& p, std::span<const double> lambda, const Eigen::VectorXd& b,
             Eigen::VectorXd& w) override;
  void backSolve(std::span<double> x) override { factor_.solve(x); }

 private:
  /// out = A x (all rows), from the rows and M^-1 J^T alone: O(rows), no matrix.
  void multiply(const Problem& p, std::span<const double> x, std::span<double> out);
  const RowSystem* sys_ = nullptr;
  TreeFactorization factor_;
  std::vector<Vec6> body_work_;
  Eigen::VectorXd x_, y_, rhs_, r_;
};

class DenseFreeRows final : public FreeRows {
 public:
  /// Loops of at most this many rows are factored dense: cheaper than a sparse analysis.
  static constexpr std::size_t kMaxRows = 64;
  void assemble(const Problem& p, const RowSystem& sys) override;
  int solve(const Problem& p, std::span<const std::uint8_t> free, const Eigen::VectorXd& b,
            std::span<double> lambda) override;
  void rates(const Problem& p, std::span<const double> lambda, const Eigen::VectorXd& b,
             Eigen::VectorXd& w) override;
  void backSolve(std::span<double> x) override;

 private:
  Eigen::MatrixXd a_, ff_, factor_;  // A; A_FF; its L D L^T (solver/dense_ldlt.hpp)
  std::vector<int> free_index_;      // the free rows, in order
};

class SparseFreeRows final : public FreeRows {
 public:
  void assemble(const Problem& p, const RowSystem& sys) override;
  int solve(const Problem& p, std::span<const std::uint8_t> free, const Eigen::VectorXd& b,
            std::span<double> lambda) override;
  void rates(const Problem& p, std::span<const double> lambda, const Eigen::VectorXd& b,
             Eigen::VectorXd& w) override;
  void backSolve(std::span<double> x) override;

 private:
  using SpMat = Eigen::SparseMatrix<double>;
  /// A row's block on one body: the row and which of its bodies (0 to 3: a, b, c, d).
  struct Touch {
    int row;
    int block;
  };
  /// Whether the rows act on the bodies the pattern was found for (the rows' bodies, in order).
  bool samePattern(const Problem& p) const;
  /// The pattern of A and, for each product of two rows' blocks on a shared body, its place
  /// among A's values.
  void findPattern(const Problem& p);
  /// Analyzes the pattern of `m` for ldlt_, unless it is the one analyzed last.
  void analyze(const SpMat& m);

  SpMat a_;                                 // A, full symmetric
  std::vector<std::array<int, 4>> bodies_;  // the rows' bodies the pattern is for
  std::vector<int> touch_start_;            // body -> its first touch in touches_
  std::vector<Touch> touches_;              // the rows' blocks, by body
  std::vector<int> diagonal_, products_;    // places among A's values (of the rows' cfm, products)
  std::vector<int> free_index_;  // row -> its place among the free rows, -1 for a held row
  SpMat aff_, shifted_;          // A_FF; A_FF with the diagonal shift
  Eigen::SimplicialLDLT<SpMat, Eigen::Lower> ldlt_;
  std::vector<int> outer_, inner_;  // the pattern ldlt_ analyzed last
  Eigen::VectorXd rhs_, x_, r_, correction_;
  bool all_free_ = false;  // the last solve's A_FF is A
};

}  // namespace linx::solver
