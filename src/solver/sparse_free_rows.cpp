// The exact solver's free rows of a large loop, sparse (solver/free_rows.hpp).
#include "solver/dense_ldlt.hpp"
#include "solver/free_rows.hpp"

#include <algorithm>
#include <stdexcept>
#include <utility>

namespace linx::solver {

namespace {

using Triplet = Eigen::Triplet<double>;

const Vec6& jacobianBlock(const Row& r, int block) {
  switch (block) {
    case 0:
      return r.Ja;
    case 1:
      return r.Jb;
    case 2:
      return r.Jc;
    default:
      return r.Jd;
  }
}

const Vec6& weightBlock(const RowSystem& sys, std::size_t k, int block) {
  switch (block) {
    case 0:
      return sys.Wa[k];
    case 1:
      return sys.Wb[k];
    case 2:
      return sys.Wc[k];
    default:
      return sys.Wd[k];
  }
}

std::array<int, 4> bodiesOf(const Row& r) {
  return {r.body_a, r.body_b, r.body_c, r.body_d};
}

}  // namespace

bool SparseFreeRows::samePattern(const Problem& p) const {
  if (bodies_.size() != p.rows.size() || touch_start_.size() != p.bodies.size() + 1) return false;
  for (std::size_t k = 0; k < p.rows.size(); ++k)
    if (bodies_[k] != bodiesOf(p.rows[k])) return false;
  return true;
}

void SparseFreeRows::findPattern(const Problem& p) {
  const std::size_t n = p.rows.size();
  bodies_.resize(n);
  for (std::size_t k = 0; k < n; ++k) bodies_[k] = bodiesOf(p.rows[k]);

  // The rows' blocks, by body (a counting sort: the rows in order within each body).
  touch_start_.assign(p.bodies.size() + 1, 0);
  for (const auto& b : bodies_)
    for (int body : b)
      if (body >= 0) ++touch_start_[static_cast<std::size_t>(body) + 1];
  for (std::size_t i = 0; i < p.bodies.size(); ++i) touch_start_[i + 1] += touch_start_[i];
  touches_.resize(static_cast<std::size_t>(touch_start_.back()));
  std::vector<int> next(touch_start_.begin(), touch_start_.end() - 1);
  for (std::size_t k = 0; k < n; ++k)
    for (int block = 0; block < 4; ++block)
      if (const int body = bodies_[k][static_cast<std::size_t>(block)]; body >= 0)
        touches_[static_cast<std::size_t>(next[static_cast<std::size_t>(body)]++)] = {int(k),
                                                                                      block};

  // A_kl is structurally non-zero where rows k and l share a body, and on the diagonal.
  std::vector<Triplet> pattern;
  for (std::size_t k = 0; k < n; ++k) pattern.emplace_back(int(k), int(k), 0.0);
  for (std::size_t i = 0; i < p.bodies.size(); ++i)
    for (int t = touch_start_[i]; t < touch_start_[i + 1]; ++t)
      for (int u = touch_start_[i]; u < touch_start_[i + 1]; ++u)
        pattern.emplace_back(touches_[std::size_t(t)].row, touches_[std::size_t(u)].row, 0.0);
  a_.resize(int(n), int(n));
  a_.setFromTriplets(pattern.begin(), pattern.end());
  a_.makeCompressed();

  const auto place = [&](int row, int col) {
    const int* begin = a_.innerIndexPtr() + a_.outerIndexPtr()[col];
    const int* end = a_.innerIndexPtr() + a_.outerIndexPtr()[col + 1];
    return static_cast<int>(std::lower_bound(begin, end, row) - a_.innerIndexPtr());
  };
  diagonal_.resize(n);
  for (std::size_t k = 0; k < n; ++k) diagonal_[k] = place(int(k), int(k));
  products_.clear();
  for (std::size_t k = n; k < pattern.size(); ++k)
    products_.push_back(place(pattern[k].row(), pattern[k].col()));
  shifted_ = a_;
}

void SparseFreeRows::assemble(const Problem& p, const RowSystem& sys) {
  // A_kl = sum over shared bodies of J_k,body . (M^-1 J_l,body^T): the pattern is found once for
  // the rows' bodies (a mechanism keeps it from one solve to the next), the values added in place.
  if (!samePattern(p)) findPattern(p);
  double* values = a_.valuePtr();
  std::fill(values, values + a_.nonZeros(), 0.0);
  for (std::size_t k = 0; k < p.rows.size(); ++k) values[diagonal_[k]] += p.rows[k].cfm;
  std::size_t product = 0;
  for (std::size_t i = 0; i < p.bodies.size(); ++i)
    for (int t = touch_start_[i]; t < touch_start_[i + 1]; ++t) {
      const Touch& k = touches_[std::size_t(t)];
      const Vec6& j = jacobianBlock(p.rows[std::size_t(k.row)], k.block);
      for (int u = touch_start_[i]; u < touch_start_[i + 1]; ++u) {
        const Touch& l = touches_[std::size_t(u)];
        values[products_[product++]] += j.dot(weightBlock(sys, std::size_t(l.row), l.block));
      }
    }
}

void SparseFreeRows::analyze(const SpMat& m) {
  // The fill-reducing ordering depends on the pattern alone: a mechanism keeps its pattern from one
  // solve to the next (the accurate integrator solves it seven times a step), so it is found once.
  const auto outer = std::span<const int>(m.outerIndexPtr(), std::size_t(m.outerSize()) + 1);
  const auto inner = std::span<const int>(m.innerIndexPtr(), std::size_t(m.nonZeros()));
  if (std::equal(outer.begin(), outer.end(), outer_.begin(), outer_.end()) &&
      std::equal(inner.begin(), inner.end(), inner_.begin(), inner_.end()))
    return;
  ldlt_.analyzePattern(m);
  outer_.assign(outer.begin(), outer.end());
  inner_.assign(inner.begin(), inner.end());
}

int SparseFreeRows::solve(const Problem& p, std::span<const std::uint8_t> free,
                          const Eigen::VectorXd& b, std::span<double> lambda) {
  const int n = int(p.rows.size());
  free_index_.assign(std::size_t(n), -1);
  int nf = 0;
  for (int k = 0; k < n; ++k)
    if (free[std::size_t(k)]) free_index_[std::size_t(k)] = nf++;
  if (nf == 0) return 0;
  all_free_ = nf == n;

  // A_FF x = -(b_F + A_FC lambda_C)
  rhs_.resize(nf);
  for (int k = 0; k < n; ++k)
    if (free_index_[std::size_t(k)] >= 0) rhs_[free_index_[std::size_t(k)]] = -b[k];
  double max_diag = 0.0;
  if (all_free_) {
    for (int k = 0; k < n; ++k) max_diag = std::max(max_diag, a_.valuePtr()[diagonal_[k]]);
  } else {
    std::vector<Triplet> triplets;
    for (int col = 0; col < n; ++col) {
      const int fc = free_index_[std::size_t(col)];
      for (SpMat::InnerIterator it(a_, col); it; ++it) {
        const int fr = free_index_[std::size_t(it.row())];
        if (fr < 0) continue;
        if (fc >= 0) {
          triplets.emplace_back(fr, fc, it.value());
          if (fr == fc) max_diag = std::max(max_diag, it.value());
        } else {
          rhs_[fr] -= it.value() * lambda[std::size_t(col)];
        }
      }
    }
    aff_.resize(nf, nf);
    aff_.setFromTriplets(triplets.begin(), triplets.end());
  }
  const SpMat& aff = all_free_ ? a_ : aff_;

  // A tiny shift keeps the factorization finite when A_FF is singular (redundant rows);
  // refinement against the unshifted matrix then removes its effect on every consistent equation.
  const double shift = 1e-13 * std::max(max_diag, 1e-300);
  if (all_free_) {
    std::copy(a_.valuePtr(), a_.valuePtr() + a_.nonZeros(), shifted_.valuePtr());
    for (int k = 0; k < n; ++k) shifted_.valuePtr()[diagonal_[k]] += shift;
  } else {
    shifted_ = aff_;
    for (int i = 0; i < nf; ++i) shifted_.coeffRef(i, i) += shift;
    shifted_.makeCompressed();
  }
  analyze(shifted_);
  ldlt_.factorize(shifted_);
  if (ldlt_.info() != Eigen::Success)
    throw std::domain_error("exact solver: the factorization failed (non-finite rows?)");
  const auto residual = [&](const Eigen::VectorXd& x, Eigen::VectorXd& r) {
    r.noalias() = aff * x;
    r = rhs_ - r;
    return r.lpNorm<Eigen::Infinity>();
  };
  x_ = ldlt_.solve(rhs_);
  const double res = residual(x_, r_);
  refine(x_, r_, res, rhs_.lpNorm<Eigen::Infinity>(), residual, [&](Eigen::VectorXd& v) {
    correction_ = ldlt_.solve(v);
    v.swap(correction_);
  });
  for (int k = 0; k < n; ++k)
    if (free_index_[std::size_t(k)] >= 0) lambda[std::size_t(k)] = x_[free_index_[std::size_t(k)]];

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
    const double diagonal = all_free_ ? a_.valuePtr()[diagonal_[std::size_t(k)]] : aff.coeff(j, j);
    if (isRedundantPivot(d[perm[j]], diagonal, cfm, shift)) ++redundant;
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
