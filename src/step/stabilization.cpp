#include "step/stabilization.hpp"

#include "world/state_archive.hpp"

#include "dynamics/integrator.hpp"
#include "step/assembly.hpp"

#include <algorithm>
#include <cmath>

namespace linx::step {

namespace {
/// The largest error (m or rad) whose correction leaves the factorization good for the next
/// iterations: the bodies then turn by 1e-3 rad or so, and J changes by as little.
constexpr double kSmallCorrection = 1e-3;
}  // namespace

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

void PostStabilization::forget(std::size_t joint) {
  std::erase_if(previous_, [&](const Row& r) { return (r.key >> 8) == joint + 1; });
}

void PostStabilization::endStep(std::span<const Body> bodies) {
  ++ends_since_remembered_;
  poses_.resize(bodies.size());
  for (std::size_t i = 0; i < bodies.size(); ++i) poses_[i] = bodies[i].pose();
}

void PostStabilization::addCurvature(std::span<const Body> bodies, std::span<Row> rows,
                                     bool remember, const GeometricStiffness* stiffness) {
  // A body stiffened by the geometric stiffness turns against its joints' forces faster than the
  // step can follow (step/geometric_stiffness.hpp), and the curvature, measured on the last
  // step's motion, is explicit in that turning: taken whole, it fed energy into a chain with a
  // heavy bob until it flew apart. A row takes it at the share of its bodies' own inertia about
  // the row, all of it where nothing is stiffened.
  const auto share = [&](int body, const Vec6& j) {
    if (body < 0 || stiffness == nullptr) return 1.0;
    return stiffness->ownShare(static_cast<std::size_t>(body),
                               bodies[static_cast<std::size_t>(body)], j.tail<3>());
  };
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
      // (A coupled row's J changes with four bodies' turns: it takes none.)
      if (p.body_a == r.body_a && p.body_b == r.body_b && !r.coupled() && !p.coupled())
        r.speed -= 0.5 * std::min(share(r.body_a, r.Ja), share(r.body_b, r.Jb)) *
                   ((r.Ja - p.Ja).dot(velocity(r.body_a)) + (r.Jb - p.Jb).dot(velocity(r.body_b)));
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
                                 std::span<const std::uint8_t> frozen, double time) {
  // A motor's row holds its coordinate; a prescribed coordinate's is an equality with its target
  // at the bodies' time.
  assembleRows(joints, bodies, settings, 1.0, time, rows_);
  const auto fixed = [&](int body) {
    return body < 0 || (!frozen.empty() && frozen[static_cast<std::size_t>(body)]);
  };
  // Rows softer than the world's (a spring-damper made of cfm) keep their stretch: it is physics,
  // not drift. A motor's row holds its coordinate where the velocity step left it: the correction
  // must not turn a driven hinge (a motor at 2 rad/s for 2 s otherwise ends 5e-6 rad ahead).
  // Limits are left to the velocity solve (see the header).
  std::erase_if(rows_, [&](const Row& r) {
    const bool positional = r.kind == RowKind::Bilateral || r.kind == RowKind::Motor;
    bool all_fixed = true;
    r.forEachBlock([&](int body, const Vec6&) { all_fixed = all_fixed && fixed(body); });
    return !positional || r.cfm > settings.cfm || all_fixed;
  });
  double err = 0.0;
  for (Row& r : rows_) {
    // Every kept row is an equality, a motor's holding its coordinate (phi 0): one factorization,
    // no active set.
    r = Row{.Ja = r.Ja,
            .Jb = r.Jb,
            .phi = r.kind == RowKind::Motor ? 0.0 : r.phi,
            .erp = 1.0,  // all of the error, over a unit time
            .cfm = r.cfm,
            .key = r.key,
            .body_a = r.body_a,
            .body_b = r.body_b,
            .Jc = r.Jc,
            .Jd = r.Jd,
            .body_c = r.body_c,
            .body_d = r.body_d};
    err = std::max(err, std::abs(r.phi));
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
    r.forEachBlock([&](int body, const Vec6& j) {
      if (body >= 0) dx_[static_cast<std::size_t>(body)] += dl[k] * j;
    });
  }
  for (std::size_t i = 0; i < bodies.size(); ++i) {
    if (still(i) || dx_[i].isZero(0)) continue;
    const solver::SolverBody& b = bodies_[i];
    dynamics::displace(bodies[i], b.inv_mass * dx_[i].head<3>(), b.inv_inertia * dx_[i].tail<3>());
  }
}

bool PostStabilization::errorsOnFactoredRows() {
  // Both lists run in assembly order. A row of the factorization that is not among the current
  // ones is held (0); a current row the factorization lacks needs a new factorization.
  lambda_.assign(factored_.size(), 0.0);
  std::size_t j = 0;
  for (std::size_t k = 0; k < factored_.size() && j < rows_.size(); ++k) {
    if (factored_[k].key != rows_[j].key) continue;
    lambda_[k] = -rows_[j].phi;
    ++j;
  }
  return j == rows_.size();
}

double PostStabilization::run(std::span<const std::unique_ptr<Joint>> joints,
                              std::span<Body> bodies, const SolverSettings& settings,
                              int iterations, std::span<const std::uint8_t> frozen,
                              const GeometricStiffness& stiffness, double time) {
  const auto still = [&](std::size_t i) {
    return !bodies[i].isDynamic() || (!frozen.empty() && frozen[i]);
  };
  double err = 0.0, last = 0.0, factored_err = 0.0;
  for (int it = 0; it < iterations; ++it) {
    err = gather(joints, bodies, settings, frozen, time);
    if (err <= settings.projection_tolerance) break;
    const bool converging = it > 0 && err <= 0.01 * last && factored_err <= kSmallCorrection;
    last = err;
    if (converging && errorsOnFactoredRows()) {
      // The last correction cut the error 100-fold or more, and the bodies moved little since the
      // last factorization: it (and its J) serves this iteration as a back-substitution.
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
      // The velocity solve's metric: the least motion it measures is the one that step makes
      // (without it, the heavy chain's light links took 0.1 rad zigzags to close 0.2 mm).
      if (!still(i)) stiffness.stiffen(i, b, bodies_[i]);
    }
    lambda_.assign(rows_.size(), 0.0);
    solver::Problem p{rows_, bodies_, lambda_, 1.0};
    solver_.solve(p, settings);
    factored_.swap(rows_);
    factored_err = err;
    displace(bodies, lambda_, still);
  }
  return err;
}

void PostStabilization::persist(state::Archive& a) {
  a.fields(previous_, poses_, ends_since_remembered_);
}

}  // namespace linx::step
