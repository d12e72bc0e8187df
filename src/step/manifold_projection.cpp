#include "step/manifold_projection.hpp"

#include "dynamics/integrator.hpp"
#include "step/constrained_dynamics.hpp"

#include <algorithm>
#include <cmath>

namespace linx::step {

void ManifoldProjection::solve(const SolverSettings& settings, int threads) {
  for (Row& r : rows_) {
    r.erp = 0.0;
    r.cfm = 0.0;
  }
  lambda_.assign(rows_.size(), 0.0);
  SolverSettings exact = settings;
  exact.type = SolverType::Exact;
  solver::Problem problem{rows_, solver_bodies_, lambda_, 1.0, threads};
  // A few bodies' rows dense, unless they are redundant; else the exact solver, which keeps
  // redundant rows finite.
  if (!dense_.solve(problem, false)) solver_.solve(problem, exact);
}

double ManifoldProjection::project(std::span<const std::unique_ptr<Joint>> joints,
                                   std::span<Body> bodies, const SolverSettings& settings,
                                   std::span<const std::uint8_t> moving, const Switches& switches,
                                   double time, int iterations, double tolerance, int threads) {
  solver_bodies_.resize(bodies.size());
  const auto gatherBodies = [&](bool velocities) {
    for (std::size_t i = 0; i < bodies.size(); ++i) {
      const Body& b = bodies[i];
      solver_bodies_[i] = moving[i]
                              ? solver::SolverBody{b.inverseMass(), b.inverseInertiaWorld(),
                                                   velocities ? b.linearVelocity() : Vec3::Zero(),
                                                   velocities ? b.angularVelocity() : Vec3::Zero()}
                              : solver::SolverBody{};
    }
  };
  // Positions: Newton's iterations on phi = 0, the rows assembled afresh at each (those that hold
  // a position: not the velocity rows).
  double error = 0.0;
  for (int it = 0;; ++it) {
    gatherEqualities(joints, bodies, settings, moving, switches, time, all_, gathered_, &targets_);
    rows_.clear();
    for (std::size_t k = 0; k < gathered_.size(); ++k)
      if (std::isnan(targets_[k])) rows_.push_back(gathered_[k]);
    error = 0.0;
    for (const Row& r : rows_) error = std::max(error, std::abs(r.phi));
    if (rows_.empty() || error <= tolerance || it == iterations) break;
    for (Row& r : rows_) r.speed = -r.phi;
    gatherBodies(false);
    solve(settings, threads);
    for (std::size_t i = 0; i < bodies.size(); ++i)
      if (moving[i]) dynamics::displace(bodies[i], solver_bodies_[i].v, solver_bodies_[i].w);
  }
  // Velocities: onto the tangent at the poses reached (gathered_ there), the velocity rows at
  // their targets.
  if (gathered_.empty()) return error;
  rows_ = gathered_;
  for (std::size_t k = 0; k < rows_.size(); ++k)
    rows_[k].speed = std::isnan(targets_[k]) ? 0.0 : targets_[k];
  gatherBodies(true);
  solve(settings, threads);
  for (std::size_t i = 0; i < bodies.size(); ++i) {
    if (!moving[i]) continue;
    bodies[i].setLinearVelocity(solver_bodies_[i].v);
    bodies[i].setAngularVelocity(solver_bodies_[i].w);
  }
  return error;
}

}  // namespace linx::step
