// Per-row quantities both solvers share: W = M^-1 J^T for each row's two bodies, the diagonal of
// A, the targets xi, and the bounds (friction bounds follow their normal row's impulse).
#pragma once

#include "solver/problem.hpp"

namespace linx::solver {

struct RowSystem {
  std::vector<Vec6> Wa, Wb;    ///< M^-1 J^T blocks of each row's bodies
  std::vector<double> diag;    ///< A_kk = J_k M^-1 J_k^T + cfm_k
  std::vector<double> target;  ///< xi_k

  void build(const Problem& p);

  /// J_k u for the bodies' current velocities.
  static double rate(const Row& row, std::span<const SolverBody> bodies);
  /// u += (M^-1 J_k^T) delta.
  void apply(const Row& row, std::size_t k, double delta, std::span<SolverBody> bodies) const;
  /// Bounds of row k given the current impulses (friction rows scale with their normal row).
  static void bounds(std::span<const Row> rows, std::span<const double> lambda, std::size_t k,
                     double& lo, double& hi);
  /// w_k = J_k u - xi_k + cfm_k lambda_k for the bodies' current velocities.
  double slack(const Problem& p, std::size_t k) const;
  /// Complementarity violation of one row with impulse l in [lo, hi] and slack w.
  static double violation(double l, double lo, double hi, double w);
  /// The largest complementarity violation of (lambda, w) over all rows, with the bodies holding
  /// the velocities that lambda produces.
  double residual(const Problem& p) const;
};

}  // namespace linx::solver
