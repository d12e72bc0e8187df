#pragma once

#include "solver/pgs_solver.hpp"
#include "solver/problem.hpp"
#include "solver/row_system.hpp"

#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>

namespace linx::solver {

/// Exact solver for mechanisms. Rows with free impulses are solved together, to round-off, by a
/// sparse LDL^T factorization of A_FF (fill-reducing ordering, so chains and trees cost O(n)
/// and closed loops are handled alike); rows at a bound hold their bound. An active-set outer loop
/// (block principal pivoting, falling back to single pivots when the number of infeasible rows
/// stops falling) moves rows between free and bound until every row is complementary.
/// Redundant rows (A singular, an over-constrained mechanism) are survived through a tiny
/// diagonal shift of the factorization and iterative refinement, and counted in the report.
class ExactSolver final : public ConstraintSolver {
 public:
  SolverReport solve(Problem& p, const SolverSettings& settings) override;

 private:
  enum class State : unsigned char { Free, Lower, Upper };
  using SpMat = Eigen::SparseMatrix<double>;

  void buildMatrix(const Problem& p);
  /// Solves the free rows for the current states; returns the number of redundant pivots.
  int solveFree(const Problem& p);

  RowSystem sys_;
  SpMat a_;            // A = J M^-1 J^T + diag(cfm), full symmetric
  Eigen::VectorXd b_;  // J u* - xi
  std::vector<State> state_;
  std::vector<int> free_index_;
  Eigen::SimplicialLDLT<SpMat, Eigen::Lower> ldlt_;
  std::vector<double> guess_;  // the initial impulses of the current solve
  PgsSolver pgs_;  // finishes a solve whose active set did not settle within the iteration cap
};

}  // namespace linx::solver
