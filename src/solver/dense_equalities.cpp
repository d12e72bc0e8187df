#include "solver/dense_equalities.hpp"

#include "solver/dense_ldlt.hpp"
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

bool DenseEqualities::solve(Problem& p, double min_pivot) {
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
      a_[static_cast<std::size_t>(l + k * n)] = v;  // the lower triangle
    }
    x_[static_cast<std::size_t>(k)] = rk.target(p.h) - RowSystem::rate(rk, p.bodies);
  }
  n_ = 0;
  if (!(factorLdlt(a_.data(), n) > min_pivot)) return false;
  solveLdlt(a_.data(), n, x_.data());
  if (!std::all_of(x_.begin(), x_.begin() + n, [](double x) { return std::isfinite(x); }))
    return false;
  n_ = n;
  for (int k = 0; k < n; ++k) {
    const double l = x_[static_cast<std::size_t>(k)];
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
  if (static_cast<int>(x.size()) == n_) solveLdlt(a_.data(), n_, x.data());
}

}  // namespace linx::solver
