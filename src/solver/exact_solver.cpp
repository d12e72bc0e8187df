#include "solver/exact_solver.hpp"

#include "solver/dense_ldlt.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace linx::solver {

namespace {
using Triplet = Eigen::Triplet<double>;
}

void ExactSolver::buildMatrix(const Problem& p) {
  const std::size_t n = p.rows.size();
  // Rows touching each body; A_kl = sum over shared bodies of J_k,body . (M^-1 J_l,body^T).
  std::vector<std::vector<std::pair<int, bool>>> by_body(p.bodies.size());  // (row, is side a)
  for (std::size_t k = 0; k < n; ++k) {
    const Row& r = p.rows[k];
    if (r.body_a >= 0) by_body[static_cast<std::size_t>(r.body_a)].push_back({int(k), true});
    if (r.body_b >= 0) by_body[static_cast<std::size_t>(r.body_b)].push_back({int(k), false});
  }
  std::vector<Triplet> triplets;
  for (std::size_t k = 0; k < n; ++k) triplets.emplace_back(int(k), int(k), p.rows[k].cfm);
  for (const auto& list : by_body) {
    for (const auto& [k, ka] : list) {
      const Vec6& jk = ka ? p.rows[std::size_t(k)].Ja : p.rows[std::size_t(k)].Jb;
      for (const auto& [l, la] : list) {
        const Vec6& wl = la ? sys_.Wa[std::size_t(l)] : sys_.Wb[std::size_t(l)];
        triplets.emplace_back(k, l, jk.dot(wl));
      }
    }
  }
  a_.resize(int(n), int(n));
  a_.setFromTriplets(triplets.begin(), triplets.end());
}

void ExactSolver::multiply(const Problem& p, std::span<const double> x, std::span<double> out) {
  body_work_.assign(p.bodies.size(), Vec6::Zero());
  for (std::size_t k = 0; k < p.rows.size(); ++k) {
    const Row& r = p.rows[k];
    if (x[k] == 0.0) continue;
    if (r.body_a >= 0) body_work_[static_cast<std::size_t>(r.body_a)] += x[k] * sys_.Wa[k];
    if (r.body_b >= 0) body_work_[static_cast<std::size_t>(r.body_b)] += x[k] * sys_.Wb[k];
  }
  for (std::size_t k = 0; k < p.rows.size(); ++k) {
    const Row& r = p.rows[k];
    double v = r.cfm * x[k];
    if (r.body_a >= 0) v += r.Ja.dot(body_work_[static_cast<std::size_t>(r.body_a)]);
    if (r.body_b >= 0) v += r.Jb.dot(body_work_[static_cast<std::size_t>(r.body_b)]);
    out[k] = v;
  }
}

int ExactSolver::solveFreeTree(const Problem& p) {
  const std::size_t n = p.rows.size();
  free_.resize(n);
  x_.resize(n);
  y_.resize(n);
  rhs_.resize(n);
  bool any = false;
  for (std::size_t k = 0; k < n; ++k) {
    free_[k] = state_[k] == State::Free;
    any = any || free_[k];
    x_[k] = free_[k] ? 0.0 : p.lambda[k];  // the held impulses
  }
  if (!any) return 0;
  // A_FF x = -(b_F + A_FC lambda_C)
  multiply(p, x_, y_);
  for (std::size_t k = 0; k < n; ++k) rhs_[k] = free_[k] ? -(b_[int(k)] + y_[k]) : 0.0;
  const int redundant = tree_factor_.factorize(p, free_);
  std::copy(rhs_.begin(), rhs_.end(), x_.begin());
  tree_factor_.solve(x_);
  // Refinement against the unshifted matrix, while the residual keeps falling (see solveFree).
  const auto residual = [&](std::span<const double> x, std::vector<double>& r) {
    multiply(p, x, y_);
    double worst = 0.0;
    r.resize(n);
    for (std::size_t k = 0; k < n; ++k) {
      r[k] = free_[k] ? rhs_[k] - y_[k] : 0.0;
      worst = std::max(worst, std::abs(r[k]));
    }
    return worst;
  };
  double scale = 0.0;
  for (std::size_t k = 0; k < n; ++k) scale = std::max(scale, std::abs(rhs_[k]));
  std::vector<double>& r = w_;
  // Without redundant rows the tree factorization is exact up to round-off (no fill-in is dropped
  // and the shift is 1e-13 of each pivot): refinement would only confirm it.
  double res = redundant > 0 ? residual(x_, r) : 0.0;
  for (int refine = 0; refine < 3 && res > 1e-15 * (1.0 + scale); ++refine) {
    tree_factor_.solve(r);
    std::vector<double>& candidate = candidate_;
    candidate.resize(n);
    for (std::size_t k = 0; k < n; ++k) candidate[k] = r[k] + x_[k];
    const double next = residual(candidate, r);
    if (!(next < 0.5 * res)) break;
    x_.swap(candidate);
    res = next;
  }
  for (std::size_t k = 0; k < n; ++k)
    if (free_[k]) p.lambda[k] = x_[k];
  return redundant;
}

int ExactSolver::solveFreeDense(const Problem& p) {
  const int n = int(p.rows.size());
  free_index_.clear();
  for (int k = 0; k < n; ++k)
    if (state_[std::size_t(k)] == State::Free) free_index_.push_back(k);
  const int nf = int(free_index_.size());
  if (nf == 0) return 0;
  // A_FF x = -(b_F + A_FC lambda_C), with a shift of 1e-13 of the largest diagonal (as the sparse
  // path), an LDL^T without pivoting and refinement against the unshifted matrix.
  Eigen::VectorXd rhs(nf);
  double max_diag = 0.0;
  dense_ff_.resize(nf, nf);
  for (int i = 0; i < nf; ++i) {
    const int k = free_index_[std::size_t(i)];
    double r = -b_[k];
    for (int l = 0; l < n; ++l)
      if (state_[std::size_t(l)] != State::Free) r -= dense_a_(k, l) * p.lambda[std::size_t(l)];
    rhs[i] = r;
    for (int j = 0; j < nf; ++j) dense_ff_(i, j) = dense_a_(k, free_index_[std::size_t(j)]);
    max_diag = std::max(max_diag, dense_ff_(i, i));
  }
  const double shift = 1e-13 * std::max(max_diag, 1e-300);
  Eigen::MatrixXd& f = dense_factor_;
  f = dense_ff_;
  int redundant = 0;
  for (int j = 0; j < nf; ++j) {
    double d = f(j, j) + shift;
    for (int k = 0; k < j; ++k) d -= f(j, k) * f(j, k) * f(k, k);
    const double cfm = p.rows[std::size_t(free_index_[std::size_t(j)])].cfm;
    if (d <= 1e-8 * (dense_ff_(j, j) - cfm) + 10.0 * (cfm + shift)) ++redundant;
    f(j, j) = d;
    for (int i = j + 1; i < nf; ++i) {
      double v = f(i, j);
      for (int k = 0; k < j; ++k) v -= f(i, k) * f(j, k) * f(k, k);
      f(i, j) = v / d;
    }
  }
  const auto solveWith = [&](Eigen::VectorXd x) {
    solveLdlt(f.data(), nf, x.data());
    return x;
  };
  Eigen::VectorXd x = solveWith(rhs);
  double res = (rhs - dense_ff_ * x).lpNorm<Eigen::Infinity>();
  for (int refine = 0; refine < 3 && res > 1e-15 * (1.0 + rhs.lpNorm<Eigen::Infinity>());
       ++refine) {
    const Eigen::VectorXd next = x + solveWith(rhs - dense_ff_ * x);
    const double next_res = (rhs - dense_ff_ * next).lpNorm<Eigen::Infinity>();
    if (!(next_res < 0.5 * res)) break;
    x = next;
    res = next_res;
  }
  for (int i = 0; i < nf; ++i) p.lambda[std::size_t(free_index_[std::size_t(i)])] = x[i];
  return redundant;
}

int ExactSolver::solveFree(const Problem& p) {
  if (tree_) return solveFreeTree(p);
  if (dense_) return solveFreeDense(p);
  const int n = int(p.rows.size());
  free_index_.assign(std::size_t(n), -1);
  int nf = 0;
  for (int k = 0; k < n; ++k)
    if (state_[std::size_t(k)] == State::Free) free_index_[std::size_t(k)] = nf++;
  if (nf == 0) return 0;

  // A_FF x = -(b_F + A_FC lambda_C)
  Eigen::VectorXd rhs(nf);
  for (int k = 0; k < n; ++k)
    if (free_index_[std::size_t(k)] >= 0) rhs[free_index_[std::size_t(k)]] = -b_[k];
  std::vector<Triplet> triplets;
  double max_diag = 0.0;
  for (int col = 0; col < n; ++col) {
    const int fc = free_index_[std::size_t(col)];
    for (SpMat::InnerIterator it(a_, col); it; ++it) {
      const int fr = free_index_[std::size_t(it.row())];
      if (fr < 0) continue;
      if (fc >= 0) {
        triplets.emplace_back(fr, fc, it.value());
        if (fr == fc) max_diag = std::max(max_diag, it.value());
      } else {
        rhs[fr] -= it.value() * p.lambda[std::size_t(col)];
      }
    }
  }
  SpMat aff(nf, nf);
  aff.setFromTriplets(triplets.begin(), triplets.end());

  // A tiny shift keeps the factorization finite when A_FF is singular (redundant rows); refinement
  // against the unshifted matrix then removes its effect on every consistent equation. It stops
  // when the residual stops falling: with inconsistent redundant rows (cfm = 0) further steps
  // would only grow the impulses along the null space.
  const double shift = 1e-13 * std::max(max_diag, 1e-300);
  SpMat shifted = aff;
  for (int i = 0; i < nf; ++i) shifted.coeffRef(i, i) += shift;
  ldlt_.compute(shifted);
  if (ldlt_.info() != Eigen::Success)
    throw std::domain_error("exact solver: the factorization failed (non-finite rows?)");
  Eigen::VectorXd x = ldlt_.solve(rhs);
  double res = (rhs - aff * x).lpNorm<Eigen::Infinity>();
  for (int refine = 0; refine < 3 && res > 1e-15 * (1.0 + rhs.lpNorm<Eigen::Infinity>());
       ++refine) {
    const Eigen::VectorXd next = x + ldlt_.solve(rhs - aff * x);
    const double next_res = (rhs - aff * next).lpNorm<Eigen::Infinity>();
    if (!(next_res < 0.5 * res)) break;
    x = next;
    res = next_res;
  }
  for (int k = 0; k < n; ++k)
    if (free_index_[std::size_t(k)] >= 0) p.lambda[std::size_t(k)] = x[free_index_[std::size_t(k)]];

  // Redundancy: the pivot of a row that depends on earlier rows is made only of regularization,
  // a small multiple of the rows' cfm and the shift (2 c for a duplicated row with cfm c, 1.5 c for
  // a third copy); an independent row's pivot is of the order of its J M^-1 J^T, whatever the
  // masses. A pivot within 10 times its row's regularization, or below 1e-8 of its diagonal,
  // counts as redundant.
  int redundant = 0;
  const Eigen::VectorXd& d = ldlt_.vectorD();
  const auto& perm = ldlt_.permutationP().indices();
  for (int k = 0; k < n; ++k) {
    const int j = free_index_[std::size_t(k)];
    if (j < 0) continue;
    const double cfm = p.rows[std::size_t(k)].cfm;
    if (d[perm[j]] <= 1e-8 * (aff.coeff(j, j) - cfm) + 10.0 * (cfm + shift)) ++redundant;
  }
  return redundant;
}

SolverReport ExactSolver::solve(Problem& p, const SolverSettings& settings) {
  SolverReport report;
  const std::size_t n = p.rows.size();
  report.rows = int(n);
  factored_ = false;
  if (n == 0) return report;
  sys_.build(p);
  tree_ = tree_factor_.analyse(p);
  dense_ = !tree_ && n <= kDenseRows;
  b_.resize(int(n));  // J u* - xi
  for (std::size_t k = 0; k < n; ++k)
    b_[int(k)] = RowSystem::rate(p.rows[k], p.bodies) - sys_.target[k];
  if (dense_) {  // A = J M^-1 J^T + diag(cfm), entry by entry over the bodies two rows share
    dense_a_.resize(int(n), int(n));
    for (std::size_t k = 0; k < n; ++k) {
      const Row& rk = p.rows[k];
      for (std::size_t l = k; l < n; ++l) {
        const Row& rl = p.rows[l];
        double v = k == l ? rk.cfm : 0.0;
        if (rk.body_a >= 0 && rk.body_a == rl.body_a) v += rk.Ja.dot(sys_.Wa[l]);
        if (rk.body_a >= 0 && rk.body_a == rl.body_b) v += rk.Ja.dot(sys_.Wb[l]);
        if (rk.body_b >= 0 && rk.body_b == rl.body_a) v += rk.Jb.dot(sys_.Wa[l]);
        if (rk.body_b >= 0 && rk.body_b == rl.body_b) v += rk.Jb.dot(sys_.Wb[l]);
        dense_a_(int(k), int(l)) = dense_a_(int(l), int(k)) = v;
      }
    }
  } else if (!tree_) {
    buildMatrix(p);
  }
  guess_.assign(p.lambda.begin(), p.lambda.end());  // the warm start, for the fallback below

  // Initial states from the guess: rows at a finite bound start there.
  state_.assign(n, State::Free);
  for (std::size_t k = 0; k < n; ++k) {
    double lo, hi;
    RowSystem::bounds(p.rows, p.lambda, k, lo, hi);
    if (lo == hi || (std::isfinite(lo) && p.lambda[k] <= lo))
      state_[k] = State::Lower;
    else if (std::isfinite(hi) && p.lambda[k] >= hi)
      state_[k] = State::Upper;
  }

  bool all_bilateral = true;  // every row free with infinite bounds: one solve settles it
  for (std::size_t k = 0; k < n && all_bilateral; ++k) {
    const Row& r = p.rows[k];
    all_bilateral = r.kind != RowKind::Friction && std::isinf(r.lo) && std::isinf(r.hi) &&
                    state_[k] == State::Free;
  }

  std::size_t best_infeasible = n + 1;
  int stalls = 0;
  report.converged = false;
  std::vector<std::size_t> infeasible;
  Eigen::VectorXd w(static_cast<int>(n));
  for (int it = 0; it < std::max(1, settings.iterations); ++it) {
    for (std::size_t k = 0; k < n; ++k) {
      if (state_[k] == State::Free) continue;
      double lo, hi;
      RowSystem::bounds(p.rows, p.lambda, k, lo, hi);
      p.lambda[k] = state_[k] == State::Lower ? lo : hi;
    }
    report.redundant_rows = solveFree(p);
    report.iterations = it + 1;
    if (all_bilateral) {  // nothing can leave its bounds: the free solve is the solution
      report.converged = true;
      break;
    }

    if (tree_) {
      y_.resize(n);
      multiply(p, p.lambda, y_);
      for (std::size_t k = 0; k < n; ++k) w[int(k)] = y_[k] + b_[int(k)];
    } else if (dense_) {
      const Eigen::Map<const Eigen::VectorXd> lam(p.lambda.data(), int(n));
      w = dense_a_ * lam + b_;
    } else {
      const Eigen::Map<const Eigen::VectorXd> lam(p.lambda.data(), int(n));
      w = a_ * lam + b_;
    }
    infeasible.clear();
    bool bounds_moved = false;  // a held row whose bound followed another row (friction)
    for (std::size_t k = 0; k < n; ++k) {
      double lo, hi;
      RowSystem::bounds(p.rows, p.lambda, k, lo, hi);
      const double l = p.lambda[k], tol_l = 1e-12 * (1.0 + std::abs(l));
      const double wk = w[int(k)];
      const bool bad = (state_[k] == State::Free && (l < lo - tol_l || l > hi + tol_l)) ||
                       (state_[k] == State::Lower && lo != hi && wk < -settings.tolerance) ||
                       (state_[k] == State::Upper && lo != hi && wk > settings.tolerance);
      if (bad) infeasible.push_back(k);
      const double held = state_[k] == State::Lower ? lo : hi;
      if (state_[k] != State::Free && std::abs(l - held) > tol_l) bounds_moved = true;
    }
    if (infeasible.empty() && !bounds_moved) {
      report.converged = true;
      break;
    }
    if (infeasible.empty()) continue;  // re-hold the rows at their moved bounds
    // Block pivoting while it makes progress, single pivots (the last infeasible row) otherwise:
    // the single-pivot rule terminates for the P-matrices of well-posed problems.
    if (infeasible.size() < best_infeasible) {
      best_infeasible = infeasible.size();
      stalls = 0;
    } else {
      ++stalls;
    }
    if (stalls >= 3) infeasible.erase(infeasible.begin(), infeasible.end() - 1);
    for (const std::size_t k : infeasible) {
      double lo, hi;
      RowSystem::bounds(p.rows, p.lambda, k, lo, hi);
      if (state_[k] == State::Free)
        state_[k] = p.lambda[k] < lo ? State::Lower : State::Upper;
      else
        state_[k] = State::Free;
    }
  }

  if (!report.converged) {
    // At the iteration cap. This happens with friction: its bounds follow the normal impulses,
    // which are not unique when normal rows are redundant (a box on four contact points), so the
    // active set can cycle, and its iterate may be far from any solution. Solve by projected
    // Gauss-Seidel from the warm start instead: it always returns impulses within their bounds
    // (the report counts both solvers' iterations).
    std::copy(guess_.begin(), guess_.end(), p.lambda.begin());
    const SolverReport polish = pgs_.solve(p, settings);
    report.iterations += polish.iterations;
    report.residual = polish.residual;
    report.converged = polish.converged;
    return report;
  }
  for (std::size_t k = 0; k < n; ++k)
    if (p.lambda[k] != 0.0) sys_.apply(p.rows[k], k, p.lambda[k], p.bodies);
  report.residual = sys_.residual(p);
  factored_ = std::find(state_.begin(), state_.end(), State::Free) != state_.end();
  return report;
}

bool ExactSolver::backSolve(std::span<double> x) {
  if (!factored_ || x.size() != state_.size()) return false;
  if (tree_) {
    tree_factor_.solve(x);
    return true;
  }
  // The dense path lists the free rows in free_index_; the sparse path maps each row to its free
  // index (-1 for a held row).
  if (dense_) {
    const int nf = int(free_index_.size());
    Eigen::VectorXd z(nf);
    for (int i = 0; i < nf; ++i) z[i] = x[std::size_t(free_index_[std::size_t(i)])];
    solveLdlt(dense_factor_.data(), nf, z.data());
    std::fill(x.begin(), x.end(), 0.0);
    for (int i = 0; i < nf; ++i) x[std::size_t(free_index_[std::size_t(i)])] = z[i];
    return true;
  }
  Eigen::VectorXd z(ldlt_.rows());
  for (std::size_t k = 0; k < x.size(); ++k)
    if (free_index_[k] >= 0) z[free_index_[k]] = x[k];
  z = ldlt_.solve(z);
  for (std::size_t k = 0; k < x.size(); ++k) x[k] = free_index_[k] >= 0 ? z[free_index_[k]] : 0.0;
  return true;
}

}  // namespace linx::solver
