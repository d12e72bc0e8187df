#include <linx/solver.hpp>

#include "solver/exact_solver.hpp"
#include "solver/pgs_solver.hpp"

namespace linx {

std::string_view solverTypeName(SolverType type) {
  return type == SolverType::Exact ? "exact" : "pgs";
}

namespace solver {
std::unique_ptr<ConstraintSolver> makeSolver(const SolverSettings& settings) {
  if (settings.type == SolverType::Pgs) return std::make_unique<PgsSolver>(settings);
  return std::make_unique<ExactSolver>(settings);
}
}  // namespace solver

}  // namespace linx
