// The exact solver's free rows along the mechanism's tree (solver/free_rows.hpp).
#include "solver/free_rows.hpp"

#include <algorithm>

namespace linx::solver {

void TreeFreeRows::assemble(const Problem&, const RowSystem& sys) {
  sys_ = &sys;
}

void TreeFreeRows::multiply(const Problem& p, std::span<const double> x, std::span<double> out) {
  body_work_.assign(p.bodies.size(), Vec6::Zero());
  for (std::size_t k = 0; k < p.rows.size(); ++k) {
    const Row& r = p.rows[k];
    if (x[k] == 0.0) continue;
    sys_->forEachW(r, k, [&](int body, const Vec6& w) {
      body_work_[static_cast<std::size_t>(body)] += x[k] * w;
    });
  }
  for (std::size_t k = 0; k < p.rows.size(); ++k) {
    const Row& r = p.rows[k];
    double v = r.cfm * x[k];
    r.forEachBlock([&](int body, const Vec6& j) {
      if (body >= 0) v += j.dot(body_work_[static_cast<std::size_t>(body)]);
    });
    out[k] = v;
  }
}

int TreeFreeRows::solve(const Problem& p, std::span<const std::uint8_t> free,
                        const Eigen::VectorXd& b, std::span<double> lambda) {
  const std::size_t n = p.rows.size();
  const auto span = [](Eigen::VectorXd& v) {
    return std::span<double>(v.data(), static_cast<std::size_t>(v.size()));
  };
  x_.resize(static_cast<Eigen::Index>(n));
  y_.resize(static_cast<Eigen::Index>(n));
  rhs_.resize(static_cast<Eigen::Index>(n));
  bool any = false;
  for (std::size_t k = 0; k < n; ++k) {
    any = any || free[k];
    x_[static_cast<Eigen::Index>(k)] = free[k] ? 0.0 : lambda[k];  // the held impulses
  }
  if (!any) return 0;
  // A_FF x = -(b_F + A_FC lambda_C), over all rows (the held ones' entries 0)
  multiply(p, span(x_), span(y_));
  for (std::size_t k = 0; k < n; ++k) {
    const auto i = static_cast<Eigen::Index>(k);
    rhs_[i] = free[k] ? -(b[i] + y_[i]) : 0.0;
  }
  const int redundant = factor_.factorize(p, free);
  x_ = rhs_;
  factor_.solve(span(x_));
  const auto residual = [&](const Eigen::VectorXd& x, Eigen::VectorXd& r) {
    multiply(p, std::span<const double>(x.data(), n), span(y_));
    double worst = 0.0;
    r.resize(static_cast<Eigen::Index>(n));
    for (std::size_t k = 0; k < n; ++k) {
      const auto i = static_cast<Eigen::Index>(k);
      r[i] = free[k] ? rhs_[i] - y_[i] : 0.0;
      worst = std::max(worst, std::abs(r[i]));
    }
    return worst;
  };
  // Without redundant rows the tree factorization is exact up to round-off (no fill-in is dropped
  // and the shift is 1e-13 of each pivot): refinement would only confirm it.
  const double res = redundant > 0 ? residual(x_, r_) : 0.0;
  refine(x_, r_, res, rhs_.lpNorm<Eigen::Infinity>(), residual,
         [&](Eigen::VectorXd& r) { factor_.solve(span(r)); });
  for (std::size_t k = 0; k < n; ++k)
    if (free[k]) lambda[k] = x_[static_cast<Eigen::Index>(k)];
  return redundant;
}

void TreeFreeRows::rates(const Problem& p, std::span<const double> lambda, const Eigen::VectorXd& b,
                         Eigen::VectorXd& w) {
  y_.resize(static_cast<Eigen::Index>(p.rows.size()));
  multiply(p, lambda, std::span<double>(y_.data(), p.rows.size()));
  w = y_ + b;
}

}  // namespace linx::solver
