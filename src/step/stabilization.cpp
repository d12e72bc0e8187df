#include "step/stabilization.hpp"

#include "dynamics/integrator.hpp"
#include "step/assembly.hpp"

#include <algorithm>
#include <cmath>

namespace linx::step {

void PostStabilization::beginStep(std::span<const Body> bodies) {
  bool same = poses_.size() == bodies.size();
  for (std::size_t i = 0; same && i < bodies.size(); ++i) {
    const Pose p = bodies[i].pose();
    same = p.position == poses_[i].position &&
           p.orientation.coeffs() == poses_[i].orientation.coeffs();
  }
  // Moved by hand since the last step, or rows older than the last step (post-stabilization was
  // off in between): their normals are not the ones the bodies moved through.
  if (!same || ends_since_remembered_ != 1) previous_.clear();
}

void PostStabilization::endStep(std::span<const Body> bodies) {
  ++ends_since_remembered_;
  poses_.resize(bodies.size());
  for (std::size_t i = 0; i < bodies.size(); ++i) poses_[i] = bodies[i].pose();
}

void PostStabilization::addCurvature(std::span<const Body> bodies, std::span<Row> rows,
                                     bool remember) {
  const auto velocity = [&](int body) -> Vec6 {
    Vec6 u = Vec6::Zero();
    if (body < 0) return u;
    const Body& b = bodies[static_cast<std::size_t>(body)];
    u << b.linearVelocity(), b.angularVelocity();
    return u;
  };
  // Both lists run joint by joint (the key's high bits), each joint's rows in its own order; a row
  // new since (a limit reached) or between other bodies has no curvature yet.
  std::size_t j = 0;
  for (Row& r : rows) {
    if (r.kind != RowKind::Bilateral) continue;
    const std::uint64_t owner = r.key >> 8;
    while (j < previous_.size() && (previous_[j].key >> 8) < owner) ++j;
    for (std::size_t i = j; i < previous_.size() && (previous_[i].key >> 8) == owner; ++i) {
      const Row& p = previous_[i];
      if (p.key != r.key) continue;
      if (p.body_a == r.body_a && p.body_b == r.body_b)
        r.speed -=
            0.5 * ((r.Ja - p.Ja).dot(velocity(r.body_a)) + (r.Jb - p.Jb).dot(velocity(r.body_b)));
      break;
    }
  }
  if (remember) {
    previous_.assign(rows.begin(), rows.end());
    ends_since_remembered_ = 0;
  }
}

double PostStabilization::gather(std::span<const std::unique_ptr<Joint>> joints,
                                 std::span<const Body> bodies, const SolverSettings& settings,
                                 std::span<const std::uint8_t> frozen) {
  assembleRows(joints, bodies, settings, 1.0, rows_);
  const auto fixed = [&](int body) {
    return body < 0 || (!frozen.empty() && frozen[static_cast<std::size_t>(body)]);
  };
  // Rows softer than the world's (a spring-damper made of cfm) keep their stretch: it is physics,
  // not drift. A motor's row holds its coordinate where the velocity step left it: the correction
  // must not turn a driven hinge (a motor at 2 rad/s for 2 s otherwise ends 5e-6 rad ahead).
  std::erase_if(rows_, [&](const Row& r) {
    const bool positional = r.kind == RowKind::Bilateral || r.kind == RowKind::Motor ||
                            (r.kind == RowKind::Unilateral && r.phi < 0.0);
    return !positional || r.cfm > settings.cfm || (fixed(r.body_a) && fixed(r.body_b));
  });
  double err = 0.0;
  for (Row& r : rows_) {
    if (r.kind == RowKind::Motor) {
      r = Row{.Ja = r.Ja,
              .Jb = r.Jb,
              .cfm = r.cfm,
              .key = r.key,
              .body_a = r.body_a,
              .body_b = r.body_b};
    }
    err = std::max(err, std::abs(r.phi));
    r.speed = 0.0;
    r.erp = 1.0;
  }
  return err;
}

template <typename Still>
void PostStabilization::displace(std::span<Body> bodies, std::span<const double> dl,
                                 const Still& still) {
  // dx = M^-1 J^T dl with the factored rows' J and the bodies' inverse masses of that solve.
  dx_.assign(bodies.size(), Vec6::Zero());
  for (std::size_t k = 0; k < factored_.size(); ++k) {
    if (dl[k] == 0.0) continue;
    const Row& r = factored_[k];
    if (r.body_a >= 0) dx_[static_cast<std::size_t>(r.body_a)] += dl[k] * r.Ja;
    if (r.body_b >= 0) dx_[static_cast<std::size_t>(r.body_b)] += dl[k] * r.Jb;
  }
  for (std::size_t i = 0; i < bodies.size(); ++i) {
    if (still(i) || dx_[i].isZero(0)) continue;
    const solver::SolverBody& b = bodies_[i];
    dynamics::displace(bodies[i], b.inv_mass * dx_[i].head<3>(), b.inv_inertia * dx_[i].tail<3>());
  }
}

bool PostStabilization::sameRows() const {
  if (rows_.size() != factored_.size()) return false;
  for (std::size_t k = 0; k < rows_.size(); ++k)
    if (rows_[k].key != factored_[k].key || rows_[k].body_a != factored_[k].body_a ||
        rows_[k].body_b != factored_[k].body_b)
      return false;
  return true;
}

double PostStabilization::run(std::span<const std::unique_ptr<Joint>> joints,
                              std::span<Body> bodies, const SolverSettings& settings,
                              int iterations, std::span<const std::uint8_t> frozen) {
  const auto still = [&](std::size_t i) {
    return bodies[i].isStatic() || (!frozen.empty() && frozen[i]);
  };
  double err = 0.0, last = 0.0;
  for (int it = 0; it < iterations; ++it) {
    err = gather(joints, bodies, settings, frozen);
    if (err <= settings.projection_tolerance) break;
    const bool converging = it > 0 && err <= 0.01 * last;
    last = err;
    if (converging && sameRows()) {
      // The last correction cut the error 100-fold or more: the bodies moved little, and the last
      // factorization (and its J) serves the next iteration as a back-substitution.
      lambda_.resize(rows_.size());
      for (std::size_t k = 0; k < rows_.size(); ++k) lambda_[k] = -rows_[k].phi;
      if (solver_.backSolve(lambda_)) {
        displace(bodies, lambda_, still);
        continue;
      }
    }
    bodies_.resize(bodies.size());
    for (std::size_t i = 0; i < bodies.size(); ++i) {
      const Body& b = bodies[i];
      bodies_[i] = still(i) ? solver::SolverBody{}
                            : solver::SolverBody{b.inverseMass(), b.inverseInertiaWorld(),
                                                 Vec3::Zero(), Vec3::Zero()};
    }
    lambda_.assign(rows_.size(), 0.0);
    solver::Problem p{rows_, bodies_, lambda_, 1.0};
    solver_.solve(p, settings);
    factored_.swap(rows_);
    displace(bodies, lambda_, still);
  }
  return err;
}

}  // namespace linx::step
