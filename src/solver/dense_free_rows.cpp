// The exact solver's free rows of a small loop, dense (solver/free_rows.hpp).
#include "solver/free_rows.hpp"

#include "solver/dense_ldlt.hpp"

#include <algorithm>

namespace linx::solver {

void DenseFreeRows::assemble(const Problem& p, const RowSystem& sys) {
  // A = J M^-1 J^T + diag(cfm), entry by entry over the bodies two rows share.
  const std::size_t n = p.rows.size();
  a_.resize(static_cast<Eigen::Index>(n), static_cast<Eigen::Index>(n));
  for (std::size_t k = 0; k < n; ++k) {
    const Row& rk = p.rows[k];
    for (std::size_t l = k; l < n; ++l) {
      const Row& rl = p.rows[l];
      double v = k == l ? rk.cfm : 0.0;
      if (rk.coupled() || rl.coupled()) {
        rk.forEachBlock([&](int body, const Vec6& j) { v += j.dot(sys.blockOn(rl, l, body)); });
      } else {
        if (rk.body_a >= 0 && rk.body_a == rl.body_a) v += rk.Ja.dot(sys.Wa[l]);
        if (rk.body_a >= 0 && rk.body_a == rl.body_b) v += rk.Ja.dot(sys.Wb[l]);
        if (rk.body_b >= 0 && rk.body_b == rl.body_a) v += rk.Jb.dot(sys.Wa[l]);
        if (rk.body_b >= 0 && rk.body_b == rl.body_b) v += rk.Jb.dot(sys.Wb[l]);
      }
      a_(static_cast<Eigen::Index>(k), static_cast<Eigen::Index>(l)) =
          a_(static_cast<Eigen::Index>(l), static_cast<Eigen::Index>(k)) = v;
    }
  }
}

int DenseFreeRows::solve(const Problem& p, std::span<const std::uint8_t> free,
                         const Eigen::VectorXd& b, std::span<double> lambda) {
  const int n = static_cast<int>(p.rows.size());
  free_index_.clear();
  for (int k = 0; k < n; ++k)
    if (free[static_cast<std::size_t>(k)]) free_index_.push_back(k);
  const int nf = static_cast<int>(free_index_.size());
  if (nf == 0) return 0;
  // A_FF x = -(b_F + A_FC lambda_C), with a shift of 1e-13 of the largest diagonal (as the sparse
  // back-end), an LDL^T without pivoting.
  Eigen::VectorXd rhs(nf);
  double max_diag = 0.0;
  ff_.resize(nf, nf);
  for (int i = 0; i < nf; ++i) {
    const int k = free_index_[static_cast<std::size_t>(i)];
    double r = -b[k];
    for (int l = 0; l < n; ++l)
      if (!free[static_cast<std::size_t>(l)]) r -= a_(k, l) * lambda[static_cast<std::size_t>(l)];
    rhs[i] = r;
    for (int j = 0; j < nf; ++j) ff_(i, j) = a_(k, free_index_[static_cast<std::size_t>(j)]);
    max_diag = std::max(max_diag, ff_(i, i));
  }
  const double shift = 1e-13 * std::max(max_diag, 1e-300);
  Eigen::MatrixXd& f = factor_;
  f = ff_;
  int redundant = 0;
  for (int j = 0; j < nf; ++j) {
    double d = f(j, j) + shift;
    for (int k = 0; k < j; ++k) d -= f(j, k) * f(j, k) * f(k, k);
    const double cfm =
        p.rows[static_cast<std::size_t>(free_index_[static_cast<std::size_t>(j)])].cfm;
    if (isRedundantPivot(d, ff_(j, j), cfm, shift)) ++redundant;
    f(j, j) = d;
    eliminateBelow(f.data(), nf, j);
  }
  const auto correct = [&](Eigen::VectorXd& r) { solveLdlt(f.data(), nf, r.data()); };
  const auto residual = [&](const Eigen::VectorXd& x, Eigen::VectorXd& r) {
    r = rhs - ff_ * x;
    return r.lpNorm<Eigen::Infinity>();
  };
  Eigen::VectorXd x = rhs, r;
  correct(x);
  const double res = residual(x, r);
  refine(x, r, res, rhs.lpNorm<Eigen::Infinity>(), residual, correct);
  for (int i = 0; i < nf; ++i)
    lambda[static_cast<std::size_t>(free_index_[static_cast<std::size_t>(i)])] = x[i];
  return redundant;
}

void DenseFreeRows::rates(const Problem& p, std::span<const double> lambda,
                          const Eigen::VectorXd& b, Eigen::VectorXd& w) {
  const Eigen::Map<const Eigen::VectorXd> lam(lambda.data(),
                                              static_cast<Eigen::Index>(p.rows.size()));
  w = a_ * lam + b;
}

void DenseFreeRows::backSolve(std::span<double> x) {
  const int nf = static_cast<int>(free_index_.size());
  Eigen::VectorXd z(nf);
  for (int i = 0; i < nf; ++i)
    z[i] = x[static_cast<std::size_t>(free_index_[static_cast<std::size_t>(i)])];
  solveLdlt(factor_.data(), nf, z.data());
  std::fill(x.begin(), x.end(), 0.0);
  for (int i = 0; i < nf; ++i)
    x[static_cast<std::size_t>(free_index_[static_cast<std::size_t>(i)])] = z[i];
}

}  // namespace linx::solver
