#pragma once

#include "solver/problem.hpp"
#include "solver/row_system.hpp"

namespace linx::solver {

/// Projected Gauss-Seidel (sequential impulses): sweep the rows, update each impulse from its
/// slack, clamp it to its bounds and apply the change to both bodies at once. Starts from the
/// given lambda (warm start); stops on the iteration cap or when the largest complementarity
/// violation falls below the tolerance.
class PgsSolver final : public ConstraintSolver {
 public:
  SolverReport solve(Problem& p, const SolverSettings& settings) override;

 private:
  RowSystem sys_;
};

}  // namespace linx::solver
