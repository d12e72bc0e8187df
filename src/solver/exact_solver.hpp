#pragma once

#include "solver/pgs_solver.hpp"
#include "solver/problem.hpp"
#include "solver/row_system.hpp"
#include "solver/tree_factorization.hpp"

#include <Eigen/Dense>
#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>

namespace linx::solver {

/// Exact solver for mechanisms. Rows with free impulses are solved together, to round-off; rows at
/// a bound hold their bound. Mechanisms without loops (chains, trees) are factored in O(n) along
/// their tree (TreeFactorization); closed loops by an LDL^T of A_FF, dense up to kDenseRows rows,
/// sparse with a fill-reducing ordering above. An active-set outer loop
/// (block principal pivoting, falling back to single pivots when the number of infeasible rows
/// stops falling) moves rows between free and bound until every row is complementary.
/// Redundant rows (A singular, an over-constrained mechanism) are survived through a tiny
/// diagonal shift of the factorization and iterative refinement, and counted in the report.
class ExactSolver final : public ConstraintSolver {
 public:
  SolverReport solve(Problem& p, const SolverSettings& settings) override;
  std::unique_ptr<ConstraintSolver> another() const override {
    return std::make_unique<ExactSolver>();
  }
  /// Overwrites x (one entry per row of the last solve) with A_FF^-1 x on the rows that were free
  /// at the end of that solve, by the factorization it made (back-substitution only); the other
  /// entries become 0. Returns false, x untouched, when the last solve kept no factorization (it
  /// fell back to PGS, or no row was free).
  bool backSolve(std::span<double> x);

 private:
  enum class State : unsigned char { Free, Lower, Upper };
  using SpMat = Eigen::SparseMatrix<double>;

  void buildMatrix(const Problem& p);
  /// out = A x (all rows), from the rows and M^-1 J^T alone: O(rows), no matrix.
  void multiply(const Problem& p, std::span<const double> x, std::span<double> out);
  /// Solves the free rows for the current states; returns the number of redundant pivots.
  int solveFree(const Problem& p);
  int solveFreeTree(const Problem& p);
  int solveFreeDense(const Problem& p);
  /// Loops of at most this many rows are factored dense: cheaper than a sparse analysis.
  static constexpr std::size_t kDenseRows = 64;

  RowSystem sys_;
  SpMat a_;            // A = J M^-1 J^T + diag(cfm), full symmetric
  Eigen::VectorXd b_;  // J u* - xi
  std::vector<State> state_;
  std::vector<int> free_index_;
  Eigen::SimplicialLDLT<SpMat, Eigen::Lower> ldlt_;
  std::vector<double> guess_;  // the initial impulses of the current solve
  bool tree_ = false;          // this solve goes through tree_factor_
  bool dense_ = false;         // this solve factors A dense (a small loop)
  bool factored_ = false;      // the factorization matches the last solve's free rows
  Eigen::MatrixXd dense_a_, dense_ff_, dense_factor_;
  TreeFactorization tree_factor_;
  std::vector<std::uint8_t> free_;
  std::vector<double> x_, y_, rhs_, w_, candidate_;
  std::vector<Vec6> body_work_;
  PgsSolver pgs_;  // finishes a solve whose active set did not settle within the iteration cap
};

}  // namespace linx::solver
