// The exact solver's free rows of a large loop, sparse (solver/free_rows.hpp).
#include "solver/free_rows.hpp"

#include <algorithm>
#include <stdexcept>
#include <utility>

namespace linx::solver {

namespace {
using Triplet = Eigen::Triplet<double>;
}

void SparseFreeRows::assemble(const Problem& p, const RowSystem& sys) {
  const std::size_t n = p.rows.size();
  // Rows touching each body; A_kl = sum over shared bodies of J_k,body . (M^-1 J_l,body^T).
  // (row, its J block on the body, its W block on the body)
  struct Touch {
    int row;
    const Vec6* j;
    const Vec6* w;
  };
  std::vector<std::vector<Touch>> by_body(p.bodies.size());
  for (std::size_t k = 0; k < n; ++k) {
    const Row& r = p.rows[k];
    const auto touch = [&](int body, const Vec6& j, const Vec6& w) {
      if (body >= 0) by_body[static_cast<std::size_t>(body)].push_back({int(k), &j, &w});
    };
    touch(r.body_a, r.Ja, sys.Wa[k]);
    touch(r.body_b, r.Jb, sys.Wb[k]);
    if (r.body_c >= 0) touch(r.body_c, r.Jc, sys.Wc[k]);
    if (r.body_d >= 0) touch(r.body_d, r.Jd, sys.Wd[k]);
  }
  std::vector<Triplet> triplets;
  for (std::size_t k = 0; k < n; ++k) triplets.emplace_back(int(k), int(k), p.rows[k].cfm);
  for (const auto& list : by_body)
    for (const Touch& k : list)
      for (const Touch& l : list) triplets.emplace_back(k.row, l.row, k.j->dot(*l.w));
  a_.resize(int(n), int(n));
  a_.setFromTriplets(triplets.begin(), triplets.end());
}

int SparseFreeRows::solve(const Problem& p, std::span<const std::uint8_t> free,
                          const Eigen::VectorXd& b, std::span<double> lambda) {
  const int n = int(p.rows.size());
  free_index_.assign(std::size_t(n), -1);
  int nf = 0;
  for (int k = 0; k < n; ++k)
    if (free[std::size_t(k)]) free_index_[std::size_t(k)] = nf++;
  if (nf == 0) return 0;

  // A_FF x = -(b_F + A_FC lambda_C)
  Eigen::VectorXd rhs(nf);
  for (int k = 0; k < n; ++k)
    if (free_index_[std::size_t(k)] >= 0) rhs[free_index_[std::size_t(k)]] = -b[k];
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
        rhs[fr] -= it.value() * lambda[std::size_t(col)];
      }
    }
  }
  SpMat aff(nf, nf);
  aff.setFromTriplets(triplets.begin(), triplets.end());

  // A tiny shift keeps the factorization finite when A_FF is singular (redundant rows);
  // refinement against the unshifted matrix then removes its effect on every consistent equation.
  const double shift = 1e-13 * std::max(max_diag, 1e-300);
  SpMat shifted = aff;
  for (int i = 0; i < nf; ++i) shifted.coeffRef(i, i) += shift;
  // The fill-reducing ordering depends on the pattern alone: a mechanism keeps its pattern from one
  // solve to the next (the accurate integrator solves it seven times a step), so it is found once.
  shifted.makeCompressed();
  const auto outer = std::span<const int>(shifted.outerIndexPtr(), std::size_t(nf) + 1);
  const auto inner = std::span<const int>(shifted.innerIndexPtr(), std::size_t(shifted.nonZeros()));
  if (!std::equal(outer.begin(), outer.end(), outer_.begin(), outer_.end()) ||
      !std::equal(inner.begin(), inner.end(), inner_.begin(), inner_.end())) {
    ldlt_.analyzePattern(shifted);
    outer_.assign(outer.begin(), outer.end());
    inner_.assign(inner.begin(), inner.end());
  }
  ldlt_.factorize(shifted);
  if (ldlt_.info() != Eigen::Success)
    throw std::domain_error("exact solver: the factorization failed (non-finite rows?)");
  const auto residual = [&](const Eigen::VectorXd& x, Eigen::VectorXd& r) {
    r = rhs - aff * x;
    return r.lpNorm<Eigen::Infinity>();
  };
  Eigen::VectorXd x = ldlt_.solve(rhs), r;
  const double res = residual(x, r);
  refine(x, r, res, rhs.lpNorm<Eigen::Infinity>(), residual, [&](Eigen::VectorXd& v) {
    Eigen::VectorXd solved = ldlt_.solve(v);
    v.swap(solved);
  });
  for (int k = 0; k < n; ++k)
    if (free_index_[std::size_t(k)] >= 0) lambda[std::size_t(k)] = x[free_index_[std::size_t(k)]];

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

void SparseFreeRows::rates(const Problem& p, std::span<const double> lambda,
                           const Eigen::VectorXd& b, Eigen::VectorXd& w) {
  const Eigen::Map<const Eigen::VectorXd> lam(lambda.data(), int(p.rows.size()));
  w = a_ * lam + b;
}

void SparseFreeRows::backSolve(std::span<double> x) {
  Eigen::VectorXd z(ldlt_.rows());
  for (std::size_t k = 0; k < x.size(); ++k)
    if (free_index_[k] >= 0) z[free_index_[k]] = x[k];
  z = ldlt_.solve(z);
  for (std::size_t k = 0; k < x.size(); ++k) x[k] = free_index_[k] >= 0 ? z[free_index_[k]] : 0.0;
}

}  // namespace linx::solver
