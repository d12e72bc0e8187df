#include "step/substep_joints.hpp"

#include "step/assembly.hpp"

#include <algorithm>
#include <cmath>

namespace linx::step {

void SubstepJoints::prepare(std::span<const std::unique_ptr<Joint>> joints,
                            std::span<const Body> bodies, const SolverSettings& settings, double h,
                            double time, std::span<const std::uint8_t> moving, JointWarmStart& warm,
                            PostStabilization& post, bool start,
                            std::span<const StartVelocity> start_velocities) {
  assembleRows(joints, bodies, settings, h, time, all_, start_velocities);
  rows_.clear();
  const auto moves = [&](int body) {
    return body >= 0 && moving[static_cast<std::size_t>(body)] != 0;
  };
  for (const Row& r : all_) {
    bool any = false;
    r.forEachBlock([&](int body, const Vec6&) { any = any || moves(body); });
    if (any) rows_.push_back(r);
  }
  if (settings.post_stabilization > 0) post.addCurvature(bodies, rows_, start);
  lambda_.resize(rows_.size());
  warm.load(rows_, lambda_);
}

void SubstepJoints::apply(std::span<solver::SoftSolver::Body> bodies,
                          std::span<const double> impulses) const {
  for (std::size_t k = 0; k < rows_.size(); ++k) {
    const double l = impulses[k];
    if (l == 0.0) continue;
    const Row& r = rows_[k];
    r.forEachBlock([&](int body, const Vec6& j) {
      if (body < 0) return;
      solver::SoftSolver::Body& b = bodies[static_cast<std::size_t>(body)];
      b.v += (l * b.inv_mass) * j.head<3>();
      b.w += l * (b.inv_inertia * j.tail<3>());
    });
  }
}

void SubstepJoints::warmStart(std::span<solver::SoftSolver::Body> bodies) const {
  apply(bodies, lambda_);
}

SolverReport SubstepJoints::solve(std::span<solver::SoftSolver::Body> bodies, bool bias,
                                  const SolverSettings& settings, double h, int threads) {
  // The change of each impulse, within the bounds that the impulse so far leaves. A drive's force
  // (a spring, a servo) is physics: it acts once a substep, with the poses it started from. Its
  // row holds J u + cfm (lambda + delta) = target, its whole impulse of the substep; the relax pass
  // keeps that impulse (delta 0) rather than re-solve it at the moved poses without the spring.
  shifted_ = rows_;
  for (std::size_t k = 0; k < rows_.size(); ++k) {
    Row& r = shifted_[k];
    r.lo -= lambda_[k];
    r.hi -= lambda_[k];
    if (r.kind == RowKind::Drive) {
      r.speed -= r.cfm * lambda_[k];
      if (!bias) r.lo = r.hi = 0.0;
    } else if (!bias && !(r.kind == RowKind::Unilateral && r.phi > 0.0)) {
      // The relax pass removes the bias, not a gap: a limit not yet reached (speculative) still
      // lets the coordinate close it, as a contact's gap does (without this, a hinge stopped
      // short of its limit by up to the limit's margin and crept onto it).
      r.erp = 0.0;
    }
  }
  gathered_.resize(bodies.size());
  for (std::size_t i = 0; i < bodies.size(); ++i)
    gathered_[i] =
        solver::SolverBody{bodies[i].inv_mass, bodies[i].inv_inertia, bodies[i].v, bodies[i].w};
  delta_.assign(rows_.size(), 0.0);
  solver::Problem problem{shifted_, gathered_, delta_, h, threads};
  const SolverReport report = exact_.solve(problem, settings);
  for (std::size_t i = 0; i < bodies.size(); ++i) {
    bodies[i].v = gathered_[i].v;
    bodies[i].w = gathered_[i].w;
  }
  for (std::size_t k = 0; k < rows_.size(); ++k) lambda_[k] += delta_[k];
  return report;
}

}  // namespace linx::step
