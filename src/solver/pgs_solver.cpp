#include "solver/pgs_solver.hpp"

#include <algorithm>
#include <cmath>

namespace linx::solver {

SolverReport PgsSolver::solve(Problem& p, const SolverSettings& settings) {
  SolverReport report;
  const std::size_t n = p.rows.size();
  report.rows = static_cast<int>(n);
  if (n == 0) return report;
  sys_.build(p);

  // Warm start: apply the initial guess, clamped to the bounds it must respect.
  for (std::size_t k = 0; k < n; ++k) {
    double lo, hi;
    RowSystem::bounds(p.rows, p.lambda, k, lo, hi);
    p.lambda[k] = std::clamp(p.lambda[k], lo, hi);
    if (p.lambda[k] != 0.0) sys_.apply(p.rows[k], k, p.lambda[k], p.bodies);
  }

  const double omega = settings.sor;
  report.converged = false;
  for (int it = 0; it < settings.iterations; ++it) {
    double sweep_violation = 0.0;  // of each row as it is visited, before its update
    // Sweeps alternate direction (symmetric Gauss-Seidel): a one-way sweep leaves a bias
    // towards the rows it visits last, which tilts a symmetric pile of contacts.
    const bool forward = it % 2 == 0;
    for (std::size_t visit = 0; visit < n; ++visit) {
      const std::size_t k = forward ? visit : n - 1 - visit;
      if (sys_.diag[k] <= 0.0) continue;  // a row that touches no movable body
      double lo, hi;
      RowSystem::bounds(p.rows, p.lambda, k, lo, hi);
      const double w = sys_.slack(p, k);
      sweep_violation = std::max(sweep_violation, RowSystem::violation(p.lambda[k], lo, hi, w));
      const double next = std::clamp(p.lambda[k] - omega * w / sys_.diag[k], lo, hi);
      const double delta = next - p.lambda[k];
      if (delta != 0.0) {
        p.lambda[k] = next;
        sys_.apply(p.rows[k], k, delta, p.bodies);
      }
    }
    report.iterations = it + 1;
    if (sweep_violation <= settings.tolerance) {
      report.converged = true;
      break;
    }
  }
  report.residual = sys_.residual(p);
  return report;
}

}  // namespace linx::solver
