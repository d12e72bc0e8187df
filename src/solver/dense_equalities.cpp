#include "solver/dense_equalities.hpp"

#include "solver/dense_ldlt.hpp"
#include "solver/free_rows.hpp"
#include "solver/row_system.hpp"

#include <algorithm>
#include <cmath>

namespace linx::solver {

namespace {

/// Row r's blocks as (body, J) pairs, a to d (body -1: none).
std::array<std::pair<int, const Vec6*>, 4> blocksOf(const Row& r) {
  return {{{r.body_a, &r.Ja}, {r.body_b, &r.Jb}, {r.body_c, &r.Jc}, {r.body_d, &r.Jd}}};
}

}  // namespace

bool DenseEqualities::solve(Problem& p, bool redundant_rows) {
  const auto n = static_cast<int>(p.rows.size());
  if (n == 0 || n > kMaxRows) return false;
  // W = M^-1 J^T, block by block.
  for (int k = 0; k < n; ++k) {
    const auto blocks = blocksOf(p.rows[static_cast<std::size_t>(k)]);
    for (std::size_t s = 0; s < blocks.size(); ++s) {
      const auto [body, j] = blocks[s];
      if (body < 0) continue;  // (its block is never read)
      Vec6& w = w_[static_cast<std::size_t>(k)][s];
      const SolverBody& b = p.bodies[static_cast<std::size_t>(body)];
      w.head<3>() = b.inv_mass * j->head<3>();
      w.tail<3>() = b.inv_inertia * j->tail<3>();
    }
  }
  // A_kl = sum over the bodies rows k and l share of J_k W_l; the right-hand side xi - J u*.
  rhs_.resize(n);
  for (int k = 0; k < n; ++k) {
    const Row& rk = p.rows[static_cast<std::size_t>(k)];
    const auto bk = blocksOf(rk);
    for (int l = k; l < n; ++l) {
      const auto bl = blocksOf(p.rows[static_cast<std::size_t>(l)]);
      double v = k == l ? rk.cfm : 0.0;
      for (const auto& [body, j] : bk) {
        if (body < 0) continue;
        for (std::size_t s = 0; s < bl.size(); ++s)
          if (bl[s].first == body) v += j->dot(w_[static_cast<std::size_t>(l)][s]);
      }
      a_[static_cast<std::size_t>(l + k * n)] = a_[static_cast<std::size_t>(k + l * n)] = v;
    }
    rhs_[k] = rk.target(p.h) - RowSystem::rate(rk, p.bodies);
  }
  // L D L^T of A with every pivot shifted by 1e-13 of A's largest diagonal entry, as the exact
  // solver's back-ends factor (solver/free_rows.hpp): the rows' regularization, cfm, is relative
  // to each row, and on a loop whose rows differ by orders of magnitude (a hinge's turning rows on
  // a body light about its axis) the shift damps the near-null directions more evenly; the
  // refinement below is against A unshifted.
  n_ = 0;
  const auto entries = static_cast<std::size_t>(n) * static_cast<std::size_t>(n);
  for (std::size_t e = 0; e < entries; ++e) factor_[e] = a_[e];
  double largest = 0.0;
  for (int k = 0; k < n; ++k) largest = std::max(largest, a_[static_cast<std::size_t>(k + k * n)]);
  const double shift = 1e-13 * std::max(largest, 1e-300);
  for (int k = 0; k < n; ++k) factor_[static_cast<std::size_t>(k + k * n)] += shift;
  if (!factorLdlt(factor_.data(), n)) return false;
  // A pivot that is nothing but regularization (as the exact solver counts them): a redundant row.
  for (int k = 0; k < n && !redundant_rows; ++k) {
    const auto kk = static_cast<std::size_t>(k + k * n);
    const double cfm = p.rows[static_cast<std::size_t>(k)].cfm;
    if (isRedundantPivot(factor_[kk], a_[kk], cfm, shift)) return false;
  }
  // The solve, refined against A as the exact solver's back-ends refine (solver/free_rows.hpp).
  const auto correct = [&](Vector& r) { solveLdlt(factor_.data(), n, r.data()); };
  const auto residual = [&](const Vector& x, Vector& r) {
    for (int k = 0; k < n; ++k) {
      double v = rhs_[k];
      for (int l = 0; l < n; ++l) v -= a_[static_cast<std::size_t>(k + l * n)] * x[l];
      r[k] = v;
    }
    return r.lpNorm<Eigen::Infinity>();
  };
  x_ = rhs_;
  correct(x_);
  r_.resize(n);
  const double res = residual(x_, r_);
  refine(x_, r_, res, rhs_.lpNorm<Eigen::Infinity>(), residual, correct);
  if (!x_.allFinite()) return false;
  n_ = n;
  for (int k = 0; k < n; ++k) {
    const double l = x_[k];
    p.lambda[static_cast<std::size_t>(k)] = l;
    const auto blocks = blocksOf(p.rows[static_cast<std::size_t>(k)]);
    for (std::size_t s = 0; s < blocks.size(); ++s) {
      const int body = blocks[s].first;
      if (body < 0) continue;
      SolverBody& b = p.bodies[static_cast<std::size_t>(body)];
      const Vec6& w = w_[static_cast<std::size_t>(k)][s];
      b.v += l * w.head<3>();
      b.w += l * w.tail<3>();
    }
  }
  return true;
}

void DenseEqualities::backSolve(std::span<double> x) const {
  if (static_cast<int>(x.size()) == n_) solveLdlt(factor_.data(), n_, x.data());
}

}  // namespace linx::solver
