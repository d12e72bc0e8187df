#pragma once

#include "solver/free_rows.hpp"
#include "solver/pgs_solver.hpp"
#include "solver/problem.hpp"
#include "solver/row_system.hpp"

#include <Eigen/Dense>

namespace linx::solver {

/// Exact solver for mechanisms. Rows with free impulses are solved together, to round-off; rows at
/// a bound hold their bound. The linear algebra is a back-end's (solver/free_rows.hpp): mechanisms
/// without loops (chains, trees) are factored in O(n) along their tree; closed loops by an LDL^T
/// of A_FF, dense up to 64 rows, sparse with a fill-reducing ordering above. An active-set outer
/// loop (block principal pivoting, falling back to single pivots when the number of infeasible rows
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

  enum class Backend : unsigned char { Tree, Dense, Sparse };

  /// Solves the free rows for the current states; returns the number of redundant pivots.
  int solveFree(const Problem& p);
  /// This solve's back-end (a choice, not a pointer: the solver stays movable).
  FreeRows& freeRows();

  RowSystem sys_;
  Eigen::VectorXd b_;  // J u* - xi
  std::vector<State> state_;
  std::vector<std::uint8_t> free_;  // state_ == Free, for the back-end
  std::vector<double> guess_;       // the initial impulses of the current solve
  bool factored_ = false;           // the back-end's factorization matches the last solve
  TreeFreeRows tree_rows_;
  DenseFreeRows dense_rows_;
  SparseFreeRows sparse_rows_;
  Backend backend_ = Backend::Tree;
  PgsSolver pgs_;  // finishes a solve whose active set did not settle within the iteration cap
};

}  // namespace linx::solver
