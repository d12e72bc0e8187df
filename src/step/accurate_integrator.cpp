#include "step/accurate_integrator.hpp"

#include "dynamics/dormand_prince.hpp"
#include "world/state_archive.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace linx::step {

namespace dp = dynamics::dormand_prince;

namespace {

/// The first dynamic body's island of a row, -1 for none; `kinematic` tells whether the row holds
/// a kinematic body.
int islandOf(const Row& r, std::span<const Body> bodies, const Islands& islands, bool& kinematic) {
  int island = -1;
  kinematic = false;
  r.forEachBlock([&](int body, const Vec6&) {
    if (body < 0) return;
    const Body& b = bodies[static_cast<std::size_t>(body)];
    if (b.isKinematic()) kinematic = true;
    if (island < 0 && b.isDynamic()) island = islands.islandOf(body);
  });
  return island;
}

/// dq/dt = 1/2 (0, w) q, q as (w, x, y, z).
Eigen::Vector4d quaternionRate(const Vec3& w, const Eigen::Vector4d& q) {
  const Vec3 qv = q.tail<3>();
  Eigen::Vector4d d;
  d[0] = -0.5 * w.dot(qv);
  d.tail<3>() = 0.5 * (q[0] * w + w.cross(qv));
  return d;
}

}  // namespace

bool onFlaggedBody(const Row& r, std::span<const std::uint8_t> flags) {
  bool any = false;
  r.forEachBlock([&](int body, const Vec6&) {
    if (body >= 0 && static_cast<std::size_t>(body) < flags.size() &&
        flags[static_cast<std::size_t>(body)])
      any = true;
  });
  return any;
}

int AccurateIntegrator::select(std::span<const std::unique_ptr<Joint>> joints,
                               std::span<const Body> bodies, std::span<const Row> rows,
                               std::size_t joint_rows, const Islands& islands,
                               std::span<const std::uint8_t> island_awake,
                               const SolverSettings& settings, bool trying,
                               std::vector<std::uint8_t>& accurate) {
  // 1: it may; 0: it may not; 2: it may once a joint row shows it is jointed (trying).
  island_ok_.assign(static_cast<std::size_t>(islands.count()), trying ? 2 : 1);
  for (std::size_t i = 0; i < island_ok_.size(); ++i)
    if (!island_awake.empty() && island_awake[i] == 0) island_ok_[i] = 0;
  for (std::size_t k = 0; k < rows.size(); ++k) {
    bool kinematic = false;
    const int island = islandOf(rows[k], bodies, islands, kinematic);
    if (island < 0) continue;
    const bool held = k < joint_rows && !(trying && isVelocityRow(rows[k])) &&
                      (mayHold(rows[k], settings) || actsAsForce(rows[k], joints));
    std::uint8_t& ok = island_ok_[static_cast<std::size_t>(island)];
    if (!held || kinematic)
      ok = 0;
    else if (ok == 2)
      ok = 1;
  }
  accurate.assign(bodies.size(), 0);
  int count = 0;
  for (std::size_t i = 0; i < bodies.size(); ++i) {
    if (!bodies[i].isDynamic()) continue;
    const int island = islands.islandOf(static_cast<int>(i));
    if (island >= 0 && island_ok_[static_cast<std::size_t>(island)] == 1) {
      accurate[i] = 1;
      ++count;
    }
  }
  return count;
}

void AccurateIntegrator::persist(state::Archive& archive) {
  archive(next_step_);
  events_.persist(archive);
  if (archive.loading() && !(next_step_ >= 0.0 && std::isfinite(next_step_)))
    throw state::StateError("accurate integrator: step size not a finite number >= 0");
}

bool AccurateIntegrator::flaggedAny(std::span<const std::uint8_t> flags) const {
  if (flags.empty()) return false;
  for (const int i : ids_)
    if (flags[static_cast<std::size_t>(i)]) return true;
  return false;
}

void AccurateIntegrator::put(std::span<const Motion> state, std::span<Body> bodies) const {
  for (std::size_t n = 0; n < ids_.size(); ++n) {
    Body& b = bodies[static_cast<std::size_t>(ids_[n])];
    const Motion& m = state[n];
    b.setPose(Pose{m.x, Quat(m.q[0], m.q[1], m.q[2], m.q[3])});
    b.setLinearVelocity(m.v);
    b.setAngularVelocity(m.w);
  }
}

Vec3 AccurateIntegrator::anchorArm(const Row& r) const {
  const std::size_t owner = static_cast<std::size_t>(r.key >> 8);
  if (owner == 0 || owner > joints_.size()) return Vec3::Zero();
  const Joint& j = *joints_[owner - 1];
  return bodies_[static_cast<std::size_t>(j.body1().index)].orientation() * j.anchor1();
}

void AccurateIntegrator::rates(std::span<const Motion> state, double time, std::span<Motion> rate,
                               std::vector<Row>& forces) {
  put(state, bodies_);
  dynamics_.accelerations(joints_, bodies_, *settings_, moving_, events_.switches(), time, threads_,
                          dv_, dw_);
  for (std::size_t n = 0; n < ids_.size(); ++n) {
    const auto i = static_cast<std::size_t>(ids_[n]);
    const Motion& m = state[n];
    rate[n] = Motion{m.v, quaternionRate(m.w, m.q), dv_[i], dw_[i]};
  }
  const std::span<const Row> rows = dynamics_.rows();
  const std::span<const double> f = dynamics_.forces();
  forces.assign(rows.begin(), rows.end());
  for (std::size_t k = 0; k < rows.size(); ++k) {
    forces[k].speed = f[k];
    // Body1's angular part about the joint's anchor here: summed over the stages, it is the
    // torque the joint passed at its anchor (putImpulses takes it back about the centre of mass
    // at the frame's end, where the joint's loads are measured).
    const Vec3 arm = anchorArm(forces[k]);
    forces[k].Ja.tail<3>() -= arm.cross(forces[k].Ja.head<3>());
  }
  for (std::size_t n = 0; n < rate.size(); ++n)
    if (!(rate[n].v.allFinite() && rate[n].w.allFinite()))
      throw std::domain_error(fmt::format(
          "accurate integrator: the accelerations of {} are not finite (masses, inertias, loads, "
          "gravity or gains beyond what a double holds?)",
          namedIsland(ids_[n])));
}

std::string AccurateIntegrator::namedIsland(int body) const {
  // The bodies the joints link to `body` among those moved here, and those joints, in order.
  std::vector<int> bodies{body};
  std::vector<std::size_t> joints;
  for (std::size_t k = 0; k < bodies.size(); ++k)
    for (std::size_t j = 0; j < joints_.size(); ++j) {
      const int a = joints_[j]->body1().index, b = joints_[j]->body2().index;
      if (a != bodies[k] && b != bodies[k]) continue;
      if (std::find(joints.begin(), joints.end(), j) == joints.end()) joints.push_back(j);
      for (const int other : {a, b})
        if (other >= 0 && std::find(ids_.begin(), ids_.end(), other) != ids_.end() &&
            std::find(bodies.begin(), bodies.end(), other) == bodies.end())
          bodies.push_back(other);
    }
  constexpr std::size_t kNamed = 4;
  const auto list = [&](auto&& items, auto&& name) {
    std::string out;
    for (std::size_t k = 0; k < items.size() && k < kNamed; ++k)
      out += (k ? ", " : "") + name(items[k]);
    if (items.size() > kNamed) out += fmt::format(" and {} more", items.size() - kNamed);
    return out;
  };
  const std::string named_bodies = list(bodies, [&](int i) {
    return fmt::format("bodies[{}] ({})", i, bodies_[static_cast<std::size_t>(i)].name());
  });
  if (joints.empty()) return named_bodies;
  return named_bodies + " and joints " +
         list(joints, [&](std::size_t j) { return fmt::format("'{}'", joints_[j]->def().name); });
}

double AccurateIntegrator::bodyError(std::size_t n, double tolerance) const {
  double worst = 0.0;
  const auto part = [&](auto&& e, auto&& a, auto&& b) {
    for (Eigen::Index c = 0; c < e.size(); ++c) {
      const double scale = tolerance * std::max({1.0, std::abs(a[c]), std::abs(b[c])});
      worst = std::max(worst, std::abs(e[c]) / scale);
    }
  };
  part(error_[n].x, y0_[n].x, y1_[n].x);
  part(error_[n].q, y0_[n].q, y1_[n].q);
  part(error_[n].v, y0_[n].v, y1_[n].v);
  part(error_[n].w, y0_[n].w, y1_[n].w);
  return std::isfinite(worst) ? worst : kInfinity;
}

double AccurateIntegrator::errorNorm(double tolerance) const {
  double worst = 0.0;
  for (std::size_t n = 0; n < ids_.size(); ++n) worst = std::max(worst, bodyError(n, tolerance));
  return worst;
}

void AccurateIntegrator::begin(std::span<const std::unique_ptr<Joint>> joints,
                               std::span<Body> bodies, const WorldSettings& settings,
                               std::span<const std::uint8_t> accurate, int threads) {
  joints_ = joints;
  bodies_ = bodies;
  settings_ = &settings;
  moving_ = accurate;
  threads_ = threads;
  ids_.clear();
  for (std::size_t i = 0; i < bodies.size(); ++i)
    if (accurate[i]) ids_.push_back(static_cast<int>(i));
  const std::size_t n = ids_.size();
  dv_.resize(bodies.size());
  dw_.resize(bodies.size());
  for (auto& k : k_) k.resize(n);
  y0_.resize(n);
  y_.resize(n);
  y1_.resize(n);
  error_.resize(n);
  impulses_.clear();
  switched_.clear();
}

void AccurateIntegrator::take() {
  for (std::size_t m = 0; m < ids_.size(); ++m) {
    const Body& b = bodies_[static_cast<std::size_t>(ids_[m])];
    const Quat& q = b.orientation();
    y0_[m] = Motion{b.position(), Eigen::Vector4d(q.w(), q.x(), q.y(), q.z()), b.linearVelocity(),
                    b.angularVelocity()};
    if (!(y0_[m].x.allFinite() && y0_[m].q.allFinite() && y0_[m].v.allFinite() &&
          y0_[m].w.allFinite()))
      throw std::domain_error("accurate integrator: the state is not finite");
  }
}

void AccurateIntegrator::settleEvents(double time) {
  const SolverSettings& solver = settings_->solver;
  const double tolerance = settings_->integrator.tolerance;
  released_.clear();
  // Each round switches at least one row and a released one is not held again: it ends.
  for (;;) {
    measureEvents(start_values_);
    const std::size_t before = switched_.size();
    events_.settle(start_values_, tolerance, released_, switched_);
    if (switched_.size() == before) return;
    // The state onto the manifold with the rows held now (rates() left it in the bodies): a limit
    // past its bound comes back to it, one closing loses its rate, a locked row takes its target.
    projection_.project(joints_, bodies_, solver, moving_, events_.switches(), time, 10,
                        solver.projection_tolerance, threads_);
    take();
    rates(y0_, time, k_[0], stage_rows_[0]);
  }
}

void AccurateIntegrator::startFrame(const Handover& lag, double time) {
  events_.keep(moving_, lag.unprojected);
  take();
  rates(y0_, time, k_[0], stage_rows_[0]);
  settleEvents(time);
  // A state the accurate integrator did not leave (the step's, which holds the joints to its
  // solver's tolerance, or one set) onto the manifold, positions then velocities, as after each
  // of its steps: its index-1 equations would keep a velocity's violation for the whole step.
  if (flaggedAny(lag.unprojected)) {
    const SolverSettings& solver = settings_->solver;
    projection_.project(joints_, bodies_, solver, moving_, events_.switches(), time, 10,
                        solver.projection_tolerance, threads_);
    take();
    rates(y0_, time, k_[0], stage_rows_[0]);
    settleEvents(time);
  }
  // The bodies behind catch up by the acceleration with the switched rows as they stand (a body
  // resting on a limit, or a motor's locked rate, gains nothing along them).
  if (!flaggedAny(lag.behind)) return;
  for (std::size_t n = 0; n < ids_.size(); ++n) {
    if (!lag.behind[static_cast<std::size_t>(ids_[n])]) continue;
    y0_[n].v += lag.time * k_[0][n].v;
    y0_[n].w += lag.time * k_[0][n].w;
  }
  rates(y0_, time, k_[0], stage_rows_[0]);
  settleEvents(time);
}

double AccurateIntegrator::attempt(double time, double dt) {
  const std::size_t n = ids_.size();
  // Stage s's state is y0 + dt sum_j a[s][j] k_j; the last stage's is the fifth-order solution.
  for (int s = 1; s < dp::kStages; ++s) {
    std::vector<Motion>& y = s + 1 == dp::kStages ? y1_ : y_;
    for (std::size_t m = 0; m < n; ++m) {
      y[m] = y0_[m];
      for (int j = 0; j < s; ++j) {
        const double a = dp::a[static_cast<std::size_t>(s)][static_cast<std::size_t>(j)] * dt;
        if (a == 0.0) continue;
        const Motion& k = k_[static_cast<std::size_t>(j)][m];
        y[m].x += a * k.x;
        y[m].q += a * k.q;
        y[m].v += a * k.v;
        y[m].w += a * k.w;
      }
    }
    rates(y, time + dp::c[static_cast<std::size_t>(s)] * dt, k_[static_cast<std::size_t>(s)],
          stage_rows_[static_cast<std::size_t>(s)]);
  }
  // The local error: the fifth-order solution minus the embedded fourth-order one.
  for (std::size_t m = 0; m < n; ++m) {
    Motion e;
    for (int s = 0; s < dp::kStages; ++s) {
      const double w = dp::e[static_cast<std::size_t>(s)] * dt;
      const Motion& k = k_[static_cast<std::size_t>(s)][m];
      e.x += w * k.x;
      e.q += w * k.q;
      e.v += w * k.v;
      e.w += w * k.w;
    }
    error_[m] = e;
  }
  measureEvents(end_values_);  // the last stage's state is y1
  return errorNorm(settings_->integrator.tolerance);
}

void AccurateIntegrator::addImpulses(double dt, std::span<const std::uint8_t> only) {
  for (int s = 0; s < dp::kStages; ++s) {
    const double w = dp::b[static_cast<std::size_t>(s)] * dt;
    if (w == 0.0) continue;
    for (const Row& r : stage_rows_[static_cast<std::size_t>(s)]) {
      if (!only.empty() && !onFlaggedBody(r, only)) continue;
      Impulse& i = impulses_[r.key];
      const double l = w * r.speed;
      i.lambda += l;
      i.Ja += l * r.Ja;
      i.Jb += l * r.Jb;
      i.Jc += l * r.Jc;
      i.Jd += l * r.Jd;
    }
  }
}

void AccurateIntegrator::putImpulses(std::span<Row> rows, std::span<double> lambda) const {
  for (std::size_t k = 0; k < rows.size(); ++k) {
    const auto it = impulses_.find(rows[k].key);
    if (it == impulses_.end()) continue;
    const Impulse& i = it->second;
    lambda[k] = i.lambda;
    // Without an impulse there is no mean direction: the row keeps its own, at the frame's start.
    if (!(std::abs(i.lambda) > 1e-300)) continue;
    Row& r = rows[k];
    r.Ja = i.Ja / i.lambda;
    r.Ja.tail<3>() += anchorArm(r).cross(r.Ja.head<3>());
    r.Jb = i.Jb / i.lambda;
    r.Jc = i.Jc / i.lambda;
    r.Jd = i.Jd / i.lambda;
  }
}

IntegratorReport AccurateIntegrator::advance(std::span<const std::unique_ptr<Joint>> joints,
                                             std::span<Body> bodies, const WorldSettings& settings,
                                             std::span<const std::uint8_t> accurate,
                                             const Handover& lag, double time, double h,
                                             int threads, std::span<Row> rows,
                                             std::span<double> lambda) {
  begin(joints, bodies, settings, accurate, threads);
  IntegratorReport report;
  report.bodies = static_cast<int>(ids_.size());
  if (ids_.empty()) return report;
  startFrame(lag, time);
  const SolverSettings& solver = settings.solver;
  const double tolerance = settings.integrator.tolerance;
  double t = 0.0;  // into the frame
  // The error's proposal for the next step: the last frame's, else the whole frame.
  double proposal = next_step_ > 0.0 ? std::min(next_step_, h) : h;
  double cut = kInfinity;  // an event ahead: the step's length to retry with
  bool fresh = true;       // k_[0] holds the rates at y0_, start_values_ the events' values there
  constexpr int kMaxSteps = 100000;
  while (t < h) {
    double dt = std::min(proposal, cut);
    if (report.steps + report.rejected > kMaxSteps || !(dt > h * 1e-12))
      throw std::domain_error(
          fmt::format("accurate integrator: the step size fell to {:.3g} s at t = {} s (the motion "
                      "is too fast or the joints are singular for integrator.tolerance {})",
                      dt, time + t, tolerance));
    const bool last = t + dt >= h * (1.0 - 1e-12);
    if (last) dt = h - t;
    if (!fresh) {
      rates(y0_, time + t, k_[0], stage_rows_[0]);
      settleEvents(time + t);
    }
    fresh = true;
    const double err = attempt(time + t, dt);
    // The next size from the estimate (Hairer, Norsett, Wanner II.4): safety 0.9, between a fifth
    // and five times this one.
    const double grow =
        std::clamp(0.9 * std::pow(std::max(err, 1e-10), -1.0 / dp::kErrorExponent), 0.2, 5.0);
    if (!(err <= 1.0)) {
      ++report.rejected;
      proposal = dt * std::min(grow, 0.9);
      continue;
    }
    // A step that ends past an event is retried shorter, to end on it.
    const double share = RowEvents::share(end_values_, start_values_, tolerance);
    if (share < 1.0) {
      ++report.rejected;
      cut = dt * share;
      continue;
    }
    addImpulses(dt);
    put(y1_, bodies);
    t = last ? h : t + dt;
    report.error = std::max(
        report.error, projection_.project(joints, bodies, solver, accurate, events_.switches(),
                                          time + t, 10, solver.projection_tolerance, threads));
    take();
    // The next step starts from the rates at the projected state: the last stage's, taken before
    // the projection, made the four-bar through its singular positions reject steps and cost 4x.
    fresh = false;
    ++report.steps;
    // A step cut short (to end the frame, or on an event) proposes no less than the size it was
    // cut from.
    proposal = dt < proposal ? std::max(proposal, dt * grow) : dt * grow;
    cut = kInfinity;
  }
  report.events = static_cast<int>(switched_.size());
  next_step_ = proposal;
  putImpulses(rows, lambda);
  return report;
}

IntegratorReport AccurateIntegrator::tryOneStep(
    std::span<const std::unique_ptr<Joint>> joints, std::span<Body> bodies,
    const WorldSettings& settings, const Islands& islands, std::span<const double> limits,
    std::vector<std::uint8_t>& accurate, const Handover& lag, double time, double h, int threads,
    std::span<Row> rows, std::span<double> lambda) {
  begin(joints, bodies, settings, accurate, threads);
  IntegratorReport report;
  lag_v_.assign(bodies.size(), Vec3::Zero());
  lag_w_.assign(bodies.size(), Vec3::Zero());
  if (ids_.empty()) return report;
  startFrame(lag, time);
  attempt(time, h);
  // Each island on its own error (the islands do not act on each other), and its events: one whose
  // step ends past an event takes the step for this frame.
  const double tolerance = settings.integrator.tolerance;
  island_error_.assign(static_cast<std::size_t>(islands.count()), 0.0);
  for (std::size_t n = 0; n < ids_.size(); ++n) {
    const auto island = static_cast<std::size_t>(islands.islandOf(ids_[n]));
    double& e = island_error_[island];
    e = std::max(e, bodyError(n, tolerance) / limits[island]);
  }
  for (const EventValue& v : end_values_)
    if (RowEvents::share(v, start_values_, tolerance) < 1.0)
      island_error_[static_cast<std::size_t>(islands.islandOf(v.bodies[0]))] = kInfinity;
  for (std::size_t n = 0; n < ids_.size(); ++n) {
    const auto i = static_cast<std::size_t>(ids_[n]);
    if (island_error_[static_cast<std::size_t>(islands.islandOf(ids_[n]))] <= 1.0) {
      ++report.bodies;
      continue;
    }
    accurate[i] = 0;
    if (lag.behind.empty() || !lag.behind[i]) {
      lag_v_[i] = lag.time * k_[0][n].v;
      lag_w_[i] = lag.time * k_[0][n].w;
    }
  }
  for (const double e : island_error_)
    if (!(e <= 1.0)) ++report.rejected;
  if (report.bodies == 0) return report;
  report.steps = 1;
  // Only the kept islands' bodies take the step's result.
  for (std::size_t n = 0; n < ids_.size(); ++n)
    if (!accurate[static_cast<std::size_t>(ids_[n])]) y1_[n] = y0_[n];
  put(y1_, bodies);
  addImpulses(h, accurate);
  report.error = projection_.project(joints, bodies, settings.solver, accurate, events_.switches(),
                                     time + h, 10, settings.solver.projection_tolerance, threads);
  for (const int body : switched_)
    if (body >= 0 && accurate[static_cast<std::size_t>(body)]) ++report.events;
  putImpulses(rows, lambda);
  return report;
}

}  // namespace linx::step

namespace linx {

std::string_view integratorTypeName(IntegratorType type) {
  switch (type) {
    case IntegratorType::Step:
      return "step";
    case IntegratorType::Accurate:
      return "accurate";
    case IntegratorType::Auto:
      return "auto";
  }
  return "unknown";
}

}  // namespace linx
