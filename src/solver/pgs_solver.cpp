#include "solver/pgs_solver.hpp"

#include "solver/row_system.hpp"

#include <algorithm>
#include <cmath>

namespace linx::solver {

SolverReport PgsSolver::solve(Problem& p, const SolverSettings& settings) {
  SolverReport report;
  const std::size_t n = p.rows.size();
  report.rows = static_cast<int>(n);
  if (n == 0) return report;

  // Gather: velocities (one extra slot, always zero, for "no body") and compact rows.
  const int none = static_cast<int>(p.bodies.size());
  velocities_.resize(p.bodies.size() + 1);
  for (std::size_t i = 0; i < p.bodies.size(); ++i) velocities_[i] = {p.bodies[i].v, p.bodies[i].w};
  velocities_.back() = Velocity{};
  rows_.resize(n);
  for (std::size_t k = 0; k < n; ++k) {
    const Row& r = p.rows[k];
    CompactRow& c = rows_[k];
    c.ja_v = r.Ja.head<3>();
    c.ja_w = r.Ja.tail<3>();
    c.jb_v = r.Jb.head<3>();
    c.jb_w = r.Jb.tail<3>();
    double diag = r.cfm;
    c.a = none;
    c.wa_v.setZero();
    c.wa_w.setZero();
    if (r.body_a >= 0) {
      const SolverBody& b = p.bodies[static_cast<std::size_t>(r.body_a)];
      c.a = r.body_a;
      c.wa_v = b.inv_mass * c.ja_v;
      c.wa_w = b.inv_inertia * c.ja_w;
      diag += c.ja_v.dot(c.wa_v) + c.ja_w.dot(c.wa_w);
    }
    c.b = none;
    c.wb_v.setZero();
    c.wb_w.setZero();
    if (r.body_b >= 0) {
      const SolverBody& b = p.bodies[static_cast<std::size_t>(r.body_b)];
      c.b = r.body_b;
      c.wb_v = b.inv_mass * c.jb_v;
      c.wb_w = b.inv_inertia * c.jb_w;
      diag += c.jb_v.dot(c.wb_v) + c.jb_w.dot(c.wb_w);
    }
    c.inv_diag = diag > 0.0 ? 1.0 / diag : 0.0;  // 0: a row that touches no movable body
    c.diag = diag > 0.0 ? diag / settings.sor : 0.0;
    c.target = r.target(p.h);
    c.cfm = r.cfm;
    c.lo = r.lo;
    c.hi = r.hi;
    c.mu = r.mu;
    c.normal = r.kind == RowKind::Friction ? r.normal : -1;
  }

  double* lambda = p.lambda.data();
  const auto bounds = [&](const CompactRow& c, double& lo, double& hi) {
    if (c.normal >= 0) {
      hi = c.mu * std::max(0.0, lambda[c.normal]);
      lo = -hi;
    } else {
      lo = c.lo;
      hi = c.hi;
    }
  };
  const auto slack = [&](const CompactRow& c, double l) {
    const Velocity& a = velocities_[static_cast<std::size_t>(c.a)];
    const Velocity& b = velocities_[static_cast<std::size_t>(c.b)];
    return c.ja_v.dot(a.v) + c.ja_w.dot(a.w) + c.jb_v.dot(b.v) + c.jb_w.dot(b.w) - c.target +
           c.cfm * l;
  };
  const auto apply = [&](const CompactRow& c, double delta) {
    Velocity& a = velocities_[static_cast<std::size_t>(c.a)];
    a.v += delta * c.wa_v;
    a.w += delta * c.wa_w;
    Velocity& b = velocities_[static_cast<std::size_t>(c.b)];
    b.v += delta * c.wb_v;
    b.w += delta * c.wb_w;
  };

  // Warm start: apply the initial guess, clamped to the bounds it must respect.
  for (std::size_t k = 0; k < n; ++k) {
    double lo, hi;
    bounds(rows_[k], lo, hi);
    lambda[k] = std::clamp(lambda[k], lo, hi);
    if (lambda[k] != 0.0) apply(rows_[k], lambda[k]);
  }

  const double omega = settings.sor;
  report.converged = false;
  for (int it = 0; it < settings.iterations; ++it) {
    double sweep_violation = 0.0;  // of each row as it is visited, before its update
    // Sweeps alternate direction (symmetric Gauss-Seidel): a one-way sweep leaves a bias
    // towards the rows it visits last, which tilts a symmetric pile of contacts.
    const bool forward = it % 2 == 0;
    for (std::size_t visit = 0; visit < n; ++visit) {
      const std::size_t k = forward ? visit : n - 1 - visit;
      const CompactRow& c = rows_[k];
      double lo, hi;
      bounds(c, lo, hi);
      const double l = lambda[k];
      const double w = slack(c, l);
      const double next = std::clamp(l - omega * w * c.inv_diag, lo, hi);
      // The row's violation before its update, without a branch: |w| for a free impulse, the
      // part of w that pushes away from a bound the impulse sits at, and for an impulse outside
      // its (moved) bounds the distance to them in slack units. All are |next - l| / A_kk for
      // omega = 1. A row touching no movable body has inv_diag = 0 and never changes.
      sweep_violation = std::max(sweep_violation, std::abs(next - l) * c.diag);
      lambda[k] = next;
      apply(c, next - l);
    }
    report.iterations = it + 1;
    if (sweep_violation <= settings.tolerance) {
      report.converged = true;
      break;
    }
  }

  // Scatter the velocities; the residual is measured with them.
  for (std::size_t i = 0; i < p.bodies.size(); ++i) {
    p.bodies[i].v = velocities_[i].v;
    p.bodies[i].w = velocities_[i].w;
  }
  double residual = 0.0;
  for (std::size_t k = 0; k < n; ++k) {
    double lo, hi;
    bounds(rows_[k], lo, hi);
    residual =
        std::max(residual, RowSystem::violation(lambda[k], lo, hi, slack(rows_[k], lambda[k])));
  }
  report.residual = residual;
  return report;
}

}  // namespace linx::solver
