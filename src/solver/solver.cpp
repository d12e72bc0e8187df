#include <linx/solver.hpp>

#include "solver/auto_solver.hpp"
#include "solver/exact_solver.hpp"
#include "solver/pgs_solver.hpp"

namespace linx {

std::string_view solverTypeName(SolverType type) {
  switch (type) {
    case SolverType::Auto:
      return "auto";
    case SolverType::Exact:
      return "exact";
    case SolverType::Pgs:
      return "pgs";
    case SolverType::Soft:
      return "soft";
  }
  return "unknown";
}

SoftRow springDamper(double stiffness, double damping, double h) {
  const double d = h * stiffness + damping;
  return SoftRow{h * stiffness / d, 1.0 / (h * d)};
}

namespace solver {
std::unique_ptr<ConstraintSolver> makeSolver(SolverType type) {
  switch (type) {
    case SolverType::Pgs:
    case SolverType::Soft:  // the soft step sweeps its own rows; its islands' solver is PGS
      return std::make_unique<PgsSolver>();
    case SolverType::Exact:
      return std::make_unique<ExactSolver>();
    case SolverType::Auto:
      break;
  }
  return std::make_unique<AutoSolver>();
}
}  // namespace solver

}  // namespace linx
