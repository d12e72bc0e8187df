#include <linx/solver.hpp>

#include "solver/exact_solver.hpp"
#include "solver/pgs_solver.hpp"

namespace linx {

std::string_view solverTypeName(SolverType type) {
  return type == SolverType::Exact ? "exact" : "pgs";
}

SoftRow springDamper(double stiffness, double damping, double h) {
  const double d = h * stiffness + damping;
  return SoftRow{h * stiffness / d, 1.0 / (h * d)};
}

namespace solver {
std::unique_ptr<ConstraintSolver> makeSolver(SolverType type) {
  if (type == SolverType::Pgs) return std::make_unique<PgsSolver>();
  return std::make_unique<ExactSolver>();
}
}  // namespace solver

}  // namespace linx
