#include "solver/auto_solver.hpp"

#include <algorithm>

namespace linx::solver {

SolverReport AutoSolver::solve(Problem& p, const SolverSettings& settings) {
  const bool friction = std::any_of(p.rows.begin(), p.rows.end(), [](const Row& r) {
    return r.kind == RowKind::Friction && r.mu > 0.0;  // frictionless contacts stay exact
  });
  return friction ? pgs_.solve(p, settings) : exact_.solve(p, settings);
}

}  // namespace linx::solver
