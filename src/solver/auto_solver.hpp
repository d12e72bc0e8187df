// The default solver: per island, the exact solver for mechanisms and projected Gauss-Seidel where
// friction is involved. The exact solver solves joints to round-off, but friction bounds that
// follow the normal impulses make its active set cycle on redundant contact points (a box on four
// corners), and each of its iterations is a sparse factorization; PGS is robust and cheap there.
// The choice is made on the rows alone (any friction row with mu > 0 -> PGS), so it is the same for
// any ordering of the problem; World solves each island separately, so a pendulum next to a pile of
// boxes is still solved exactly.
#pragma once

#include "solver/exact_solver.hpp"
#include "solver/pgs_solver.hpp"
#include "solver/problem.hpp"

namespace linx::solver {

class AutoSolver final : public ConstraintSolver {
 public:
  SolverReport solve(Problem& p, const SolverSettings& settings) override;
  std::unique_ptr<ConstraintSolver> another() const override {
    return std::make_unique<AutoSolver>();
  }

 private:
  ExactSolver exact_;
  PgsSolver pgs_;
};

}  // namespace linx::solver
