// Per-row quantities both solvers share: W = M^-1 J^T for each row's two bodies, the diagonal of
// A, the targets xi, and the bounds (friction bounds follow their normal row's impulse).
#pragma once

#include "solver/problem.hpp"

namespace linx::solver {

struct RowSystem {
  std::vector<Vec6> Wa, Wb;  ///< M^-1 J^T blocks of each row's bodies
  /// Of the coupled rows' bodies c and d (Row::coupled): empty when no row is.
  std::vector<Vec6> Wc, Wd;
  std::vector<double> diag;    ///< A_kk = J_k M^-1 J_k^T + cfm_k
  std::vector<double> target;  ///< xi_k

  void build(const Problem& p);
  /// W of row k's block on body `body` (Wa, Wb, Wc or Wd), zero if the row does not act on it.
  Vec6 blockOn(const Row& row, std::size_t k, int body) const;
  /// g(body, W block) for each body row k acts on.
  template <class G>
  void forEachW(const Row& row, std::size_t k, G&& g) const {
    if (row.body_a >= 0) g(row.body_a, Wa[k]);
    if (row.body_b >= 0) g(row.body_b, Wb[k]);
    if (row.body_c >= 0) g(row.body_c, Wc[k]);
    if (row.body_d >= 0) g(row.body_d, Wd[k]);
  }

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
