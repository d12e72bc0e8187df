#include "solver/row_system.hpp"

#include <algorithm>
#include <cmath>

namespace linx::solver {

namespace {
Vec6 invMassTimes(const SolverBody& b, const Vec6& j) {
  Vec6 out;
  out << b.inv_mass * j.head<3>(), b.inv_inertia * j.tail<3>();
  return out;
}
double dot(const Vec6& j, const SolverBody& b) {
  return j.head<3>().dot(b.v) + j.tail<3>().dot(b.w);
}
}  // namespace

void RowSystem::build(const Problem& p) {
  const std::size_t n = p.rows.size();
  Wa.assign(n, Vec6::Zero());
  Wb.assign(n, Vec6::Zero());
  const bool coupled =
      std::any_of(p.rows.begin(), p.rows.end(), [](const Row& r) { return r.coupled(); });
  Wc.assign(coupled ? n : 0, Vec6::Zero());
  Wd.assign(coupled ? n : 0, Vec6::Zero());
  diag.resize(n);
  target.resize(n);
  for (std::size_t k = 0; k < n; ++k) {
    const Row& r = p.rows[k];
    double d = r.cfm;
    if (r.body_a >= 0) {
      Wa[k] = invMassTimes(p.bodies[static_cast<std::size_t>(r.body_a)], r.Ja);
      d += r.Ja.dot(Wa[k]);
    }
    if (r.body_b >= 0) {
      Wb[k] = invMassTimes(p.bodies[static_cast<std::size_t>(r.body_b)], r.Jb);
      d += r.Jb.dot(Wb[k]);
    }
    if (r.body_c >= 0) {
      Wc[k] = invMassTimes(p.bodies[static_cast<std::size_t>(r.body_c)], r.Jc);
      d += r.Jc.dot(Wc[k]);
    }
    if (r.body_d >= 0) {
      Wd[k] = invMassTimes(p.bodies[static_cast<std::size_t>(r.body_d)], r.Jd);
      d += r.Jd.dot(Wd[k]);
    }
    diag[k] = d;
    target[k] = r.target(p.h);
  }
}

Vec6 RowSystem::blockOn(const Row& row, std::size_t k, int body) const {
  Vec6 w = Vec6::Zero();
  if (body < 0) return w;
  forEachW(row, k, [&](int b, const Vec6& wb) {
    if (b == body) w = wb;
  });
  return w;
}

double RowSystem::rate(const Row& row, std::span<const SolverBody> bodies) {
  double r = 0.0;
  row.forEachBlock([&](int body, const Vec6& j) {
    if (body >= 0) r += dot(j, bodies[static_cast<std::size_t>(body)]);
  });
  return r;
}

void RowSystem::apply(const Row& row, std::size_t k, double delta,
                      std::span<SolverBody> bodies) const {
  forEachW(row, k, [&](int body, const Vec6& w) {
    SolverBody& b = bodies[static_cast<std::size_t>(body)];
    b.v += delta * w.head<3>();
    b.w += delta * w.tail<3>();
  });
}

void RowSystem::bounds(std::span<const Row> rows, std::span<const double> lambda, std::size_t k,
                       double& lo, double& hi) {
  const Row& r = rows[k];
  if (r.kind == RowKind::Friction && r.normal >= 0) {
    const double limit = r.mu * std::max(0.0, lambda[static_cast<std::size_t>(r.normal)]);
    lo = -limit;
    hi = limit;
  } else {
    lo = r.lo;
    hi = r.hi;
  }
}

double RowSystem::slack(const Problem& p, std::size_t k) const {
  return rate(p.rows[k], p.bodies) - target[k] + p.rows[k].cfm * p.lambda[k];
}

double RowSystem::violation(double l, double lo, double hi, double w) {
  // An impulse within round-off of a bound counts as at the bound.
  const double tol = 1e-12 * (1.0 + std::abs(l));
  const bool at_lo = l <= lo + tol, at_hi = l >= hi - tol;
  double v;
  if (at_lo && at_hi)
    v = 0.0;  // lo == hi: any slack is admissible
  else if (at_lo)
    v = std::max(0.0, -w);
  else if (at_hi)
    v = std::max(0.0, w);
  else
    v = std::abs(w);
  return std::max({v, lo - l, l - hi});  // an impulse outside its bounds is a violation too
}

double RowSystem::residual(const Problem& p) const {
  double worst = 0.0;
  for (std::size_t k = 0; k < p.rows.size(); ++k) {
    double lo, hi;
    bounds(p.rows, p.lambda, k, lo, hi);
    worst = std::max(worst, violation(p.lambda[k], lo, hi, slack(p, k)));
  }
  return worst;
}

}  // namespace linx::solver
