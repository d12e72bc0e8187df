#include "solver/exact_solver.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace linx::solver {

FreeRows& ExactSolver::freeRows() {
  switch (backend_) {
    case Backend::Tree:
      return tree_rows_;
    case Backend::Dense:
      return dense_rows_;
    case Backend::Sparse:
      break;
  }
  return sparse_rows_;
}

int ExactSolver::solveFree(const Problem& p) {
  free_.resize(state_.size());
  for (std::size_t k = 0; k < state_.size(); ++k) free_[k] = state_[k] == State::Free;
  return freeRows().solve(p, free_, b_, p.lambda);
}

SolverReport ExactSolver::solve(Problem& p, const SolverSettings& settings) {
  SolverReport report;
  const std::size_t n = p.rows.size();
  report.rows = int(n);
  factored_ = false;
  if (n == 0) return report;
  sys_.build(p);
  // The back-end for this problem's rows (solver/free_rows.hpp).
  backend_ = tree_rows_.fits(p)             ? Backend::Tree
             : n <= DenseFreeRows::kMaxRows ? Backend::Dense
                                            : Backend::Sparse;
  b_.resize(int(n));  // J u* - xi
  for (std::size_t k = 0; k < n; ++k)
    b_[int(k)] = RowSystem::rate(p.rows[k], p.bodies) - sys_.target[k];
  freeRows().assemble(p, sys_);
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
    // A nearly singular free set (redundant contact points with friction, in a loop of contacts
    // that only the sparse back-end takes) can give impulses that are not finite, against which
    // every test below is false: such a solve is not a solution. The Gauss-Seidel fallback below
    // takes over (measured: a 6-box pyramid with "type": "exact" went non-finite at its 16th
    // step).
    if (!std::all_of(p.lambda.begin(), p.lambda.end(), [](double l) { return std::isfinite(l); }))
      break;
    if (all_bilateral) {  // nothing can leave its bounds: the free solve is the solution
      report.converged = true;
      break;
    }

    freeRows().rates(p, p.lambda, b_, w);
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
  freeRows().backSolve(x);
  return true;
}

}  // namespace linx::solver
