#include "step/projection.hpp"

#include "dynamics/integrator.hpp"
#include "solver/exact_solver.hpp"
#include "step/assembly.hpp"

#include <algorithm>
#include <cmath>

namespace linx::step {

namespace {
/// Keeps the rows that carry a position error and makes each remove all of it (erp = 1, h = 1).
/// Rows softer than the world's (a spring-damper made of cfm) keep their stretch: it is physics,
/// not drift. Returns the largest error among the rows kept.
double positionalRows(std::vector<Row>& rows, double world_cfm,
                      std::span<const std::uint8_t> frozen) {
  double err = 0.0;
  auto fixed = [&](int body) {
    return body < 0 || (!frozen.empty() && frozen[static_cast<std::size_t>(body)]);
  };
  std::erase_if(rows, [&](Row& r) {
    const bool positional =
        r.kind == RowKind::Bilateral || (r.kind == RowKind::Unilateral && r.phi < 0.0);
    const bool keep = positional && r.cfm <= world_cfm && !(fixed(r.body_a) && fixed(r.body_b));
    if (!keep) return true;
    err = std::max(err, std::abs(r.phi));
    r.speed = 0.0;
    r.erp = 1.0;
    return false;
  });
  return err;
}
}  // namespace

double projectPositions(std::span<const std::unique_ptr<Joint>> joints, std::span<Body> bodies,
                        const SolverSettings& settings, std::span<const std::uint8_t> frozen) {
  solver::ExactSolver solver;
  std::vector<Row> rows;
  std::vector<solver::SolverBody> sb(bodies.size());
  std::vector<double> lambda;

  double err = 0.0;
  for (int it = 0; it <= settings.projection_iterations; ++it) {
    assembleRows(joints, bodies, settings, 1.0, rows);
    err = positionalRows(rows, settings.cfm, frozen);
    if (err <= settings.projection_tolerance || it == settings.projection_iterations) break;
    for (std::size_t i = 0; i < bodies.size(); ++i) {
      const Body& b = bodies[i];
      sb[i] = !frozen.empty() && frozen[i]
                  ? solver::SolverBody{0.0, Mat3::Zero(), Vec3::Zero(), Vec3::Zero()}
                  : solver::SolverBody{b.inverseMass(), b.inverseInertiaWorld(), Vec3::Zero(),
                                       Vec3::Zero()};
    }
    lambda.assign(rows.size(), 0.0);
    solver::Problem p{rows, sb, lambda, 1.0};
    solver.solve(p, settings);
    // The solve leaves the displacement in the velocity slots: apply it as a unit-time step.
    for (std::size_t i = 0; i < bodies.size(); ++i) {
      Body& b = bodies[i];
      if (b.isStatic() || (!frozen.empty() && frozen[i])) continue;
      const Vec3 v = b.linearVelocity(), w = b.angularVelocity();
      b.setLinearVelocity(sb[i].v);
      b.setAngularVelocity(sb[i].w);
      dynamics::integratePosition(b, 1.0);
      b.setLinearVelocity(v);
      b.setAngularVelocity(w);
    }
  }
  return err;
}

}  // namespace linx::step
