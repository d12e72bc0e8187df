#include "step/constrained_dynamics.hpp"

#include "joints/row_parts.hpp"
#include "math/rotation.hpp"
#include "step/assembly.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <utility>

namespace linx::step {

namespace {

/// The length the rows are assembled for: short, so that what a row takes over it is what it
/// takes at the rows' time (a force or a motor's target rate at time + h / 2 or time + h); the
/// impulses of coordinate forces and the bounds of drives are divided by it.
constexpr double kAssemblyStep = 1e-9;

/// The regularization of the equality rows in the acceleration solve, relative to their
/// J M^-1 J^T.
constexpr double kRegularization = 1e-11;

/// A coordinate force: a motor row whose bounds pin its impulse (Joint::setForce, "force").
bool isForceRow(const Row& r) {
  return r.kind == RowKind::Motor && r.lo == r.hi;
}

/// The free coordinate a joint row acts on (its key: (joint + 1) << 8 | slot, slots from 16 the
/// coordinates' parts) and the part (joints::coordinateSlot); none for a joint's own rows.
struct CoordinatePart {
  const CoordinateDef* coordinate = nullptr;
  int part = -1;
};
CoordinatePart coordinateOf(const Row& r, std::span<const std::unique_ptr<Joint>> joints) {
  const auto joint = static_cast<std::size_t>((r.key >> 8) - 1);
  const int slot = static_cast<int>(r.key & 0xff);
  if (joint >= joints.size() || slot < joints::coordinateSlot(0, 0)) return {};
  const auto index = static_cast<std::size_t>((slot - 16) / 16);
  const auto& coordinates = joints[joint]->def().coordinates;
  if (index >= coordinates.size()) return {};
  return {&coordinates[index], (slot - 16) % 16};
}

/// The stiffness and damping of a drive row (a spring, a servo), none for other rows.
std::optional<std::pair<double, double>> driveLaw(const Row& r,
                                                  std::span<const std::unique_ptr<Joint>> joints) {
  if (r.kind != RowKind::Drive) return std::nullopt;
  const auto [c, part] = coordinateOf(r, joints);
  if (!c) return std::nullopt;
  if (part == 3 && c->spring) return std::pair{c->spring->stiffness, c->spring->damping};
  if (part == 2 && c->motor && c->motor->isServo())
    return std::pair{c->motor->target_position ? c->motor->stiffness : 0.0, c->motor->damping};
  return std::nullopt;  // armature
}

/// A held limit's row as the equality it is held as (its bounds are the solver's business
/// otherwise: an active set would never let it pull, which is how the release is found).
Row asEquality(Row r) {
  r.kind = RowKind::Bilateral;
  r.lo = -kInfinity;
  r.hi = kInfinity;
  return r;
}

/// d/dt of a velocity row's target: a velocity motor's target_velocity's rate (a table's slope);
/// friction's target is zero.
double targetRate(const Row& r, std::span<const std::unique_ptr<Joint>> joints, double time) {
  const auto [c, part] = coordinateOf(r, joints);
  return c && part == 2 && c->motor ? c->motor->target_velocity.rate(time) : 0.0;
}

bool isMoving(BodyId id, std::span<const std::uint8_t> moving) {
  return !id.isWorld() && moving[static_cast<std::size_t>(id.index)] != 0;
}

/// Whether a joint acts on a moving body (else none of its rows does).
bool touchesMoving(const Joint& j, std::span<const std::uint8_t> moving) {
  const std::array<BodyId, 2> more = j.coupledBodies();
  return isMoving(j.body1(), moving) || isMoving(j.body2(), moving) || isMoving(more[0], moving) ||
         isMoving(more[1], moving);
}

/// `ctx` with the joint's moving bodies moved along their velocities for dt, at time + dt.
JointContext shifted(const JointContext& ctx, const Joint& j, std::span<const std::uint8_t> moving,
                     double dt) {
  JointContext s = ctx;
  s.time += dt;
  const auto move = [&](BodyId id, BodyState& state) {
    if (!isMoving(id, moving)) return;
    state.pose.position += dt * state.v;
    state.pose.orientation = math::integrate(state.pose.orientation, state.w, dt);
  };
  move(j.body1(), s.b1);
  move(j.body2(), s.b2);
  const std::array<BodyId, 2> more = j.coupledBodies();
  move(more[0], s.more[0]);
  move(more[1], s.more[1]);
  return s;
}

/// The difference's time step: the fastest moving body turns or moves 1e-5 (rad, or m over a
/// metre) along it. The central difference's truncation error is then about 1e-10 of the curvature
/// and its round-off about 1e-16 / 1e-5 of the rows' size times the speed.
double differenceStep(std::span<const Body> bodies, std::span<const std::uint8_t> moving) {
  double speed = 1.0;
  for (std::size_t i = 0; i < bodies.size(); ++i)
    if (moving[i])
      speed =
          std::max({speed, bodies[i].linearVelocity().norm(), bodies[i].angularVelocity().norm()});
  return 1e-5 / speed;
}

/// Joint j's maxRows() slots in `scratch`, which only grows (a row is built once; fillJoint blanks
/// the slots it fills).
std::span<Row> slotsFor(const Joint& j, std::vector<Row>& scratch) {
  const auto most = static_cast<std::size_t>(j.maxRows());
  if (scratch.size() < most) scratch.resize(most);
  return std::span<Row>(scratch).first(most);
}

/// (J_after - J_before) u with the bodies' velocities: the change of a row's rate between two of
/// its fills (on the same bodies).
double rateChange(const Row& after, const Row& before, std::span<const Body> bodies) {
  double change = 0.0;
  const auto add = [&](int body, const Vec6& a, const Vec6& b) {
    if (body < 0) return;
    const Body& x = bodies[static_cast<std::size_t>(body)];
    const Vec6 d = a - b;
    change += d.head<3>().dot(x.linearVelocity()) + d.tail<3>().dot(x.angularVelocity());
  };
  add(after.body_a, after.Ja, before.Ja);
  add(after.body_b, after.Jb, before.Jb);
  add(after.body_c, after.Jc, before.Jc);
  add(after.body_d, after.Jd, before.Jd);
  return change;
}

}  // namespace

bool actsOnMoving(const Row& r, std::span<const std::uint8_t> moving) {
  bool any = false, all = true;
  r.forEachBlock([&](int body, const Vec6&) {
    if (body < 0) return;
    if (moving[static_cast<std::size_t>(body)] != 0)
      any = true;
    else
      all = false;
  });
  return any && all;
}

void gatherEqualities(std::span<const std::unique_ptr<Joint>> joints, std::span<const Body> bodies,
                      const SolverSettings& settings, std::span<const std::uint8_t> moving,
                      const Switches& switches, double time, std::vector<Row>& all,
                      std::vector<Row>& out, std::vector<double>* targets) {
  out.clear();
  if (targets) targets->clear();
  for (std::size_t ji = 0; ji < joints.size(); ++ji) {
    const Joint& j = *joints[ji];
    if (!j.enabled() || !touchesMoving(j, moving)) continue;
    const std::span<Row> slots = slotsFor(j, all);
    const int n =
        fillJoint(joints, ji, bodies, contextOf(bodies, j, settings, kAssemblyStep, time), slots);
    for (const Row& r : std::span<const Row>(slots).first(static_cast<std::size_t>(n)))
      if (holdsExactly(r, settings, switches) && actsOnMoving(r, moving)) {
        out.push_back(asEquality(r));
        if (targets)
          targets->push_back(isVelocityRow(r) ? r.speed : std::numeric_limits<double>::quiet_NaN());
      }
  }
}

bool actsAsForce(const Row& row, std::span<const std::unique_ptr<Joint>> joints) {
  return isForceRow(row) || driveLaw(row, joints).has_value();
}

double velocityBound(const Row& row) {
  return row.hi / kAssemblyStep;
}

bool holdsExactly(const Row& row, const SolverSettings& settings, const Switches& switches) {
  // (Joint friction's row is softened for the step's direct solvers, which would otherwise meet
  // it and a limit on the same coordinate as a singular pair; held, it is an equality.)
  if (isVelocityRow(row)) return switches.holds(row.key);
  if (row.cfm > settings.cfm) return false;
  if (isLimit(row)) return switches.holds(row.key);
  // (Only a prescribed coordinate's equality has a speed of its own; the step's curvature may have
  // set one on the others.)
  return row.kind == RowKind::Bilateral &&
         !joints::isPrescribedSlot(static_cast<int>(row.key & 0xff));
}

double rowSpeed(const Row& row, std::span<const Body> bodies) {
  double s = 0.0;
  row.forEachBlock([&](int body, const Vec6& j) {
    if (body < 0) return;
    const Body& b = bodies[static_cast<std::size_t>(body)];
    s += j.head<3>().dot(b.linearVelocity()) + j.tail<3>().dot(b.angularVelocity());
  });
  return s;
}

void ConstrainedDynamics::gather(std::span<const std::unique_ptr<Joint>> joints,
                                 std::span<const Body> bodies, const SolverSettings& settings,
                                 std::span<const std::uint8_t> moving, double time) {
  const double eps = differenceStep(bodies, moving);
  rows_.clear();
  forces_.clear();
  open_.clear();
  curvature_.clear();
  target_rate_.clear();
  for (std::size_t ji = 0; ji < joints.size(); ++ji) {
    const Joint& j = *joints[ji];
    if (!j.enabled() || !touchesMoving(j, moving)) continue;
    // h scales only what these rows do not use (a motor's bound: a force row's impulse over h).
    const JointContext ctx = contextOf(bodies, j, settings, kAssemblyStep, time);
    const std::span<Row> slots = slotsFor(j, slots_);
    const auto rows = std::span<const Row>(slots).first(
        static_cast<std::size_t>(fillJoint(joints, ji, bodies, ctx, slots)));
    bool equalities = false;
    for (const Row& r : rows) {
      if (!actsOnMoving(r, moving)) continue;
      if (holdsExactly(r, settings, switches_)) {
        rows_.push_back(asEquality(r));
        target_rate_.push_back(isVelocityRow(r) ? targetRate(r, joints, time) : 0.0);
        equalities = true;
      } else if (isLimit(r)) {
        open_.push_back(r);
      } else if (isVelocityRow(r)) {
        // Slipping: its bound towards its target (the direction settled at the step's start).
        open_.push_back(r);
        const double bound = velocityBound(r);
        if (!std::isfinite(bound)) continue;  // (held as soon as its step starts)
        const double push = switches_.push(r.key, r.speed >= rowSpeed(r, bodies) ? 1.0 : -1.0);
        Row& f = forces_.emplace_back(r);
        f.lo = f.hi = push * bound;
      } else if (isForceRow(r)) {
        Row& f = forces_.emplace_back(r);
        f.lo = f.hi = r.lo / kAssemblyStep;
      } else if (const auto law = driveLaw(r, joints)) {
        // A drive's force at the bodies' state, as a coordinate force.
        const auto [stiffness, damping] = *law;
        const double force = -stiffness * r.phi - damping * (rowSpeed(r, bodies) - r.speed);
        Row& f = forces_.emplace_back(r);
        f.kind = RowKind::Motor;
        f.lo = f.hi = std::clamp(force, r.lo / kAssemblyStep, r.hi / kAssemblyStep);
      }
    }
    if (equalities) measureCurvature(joints, ji, bodies, settings, moving, ctx, rows, eps);
  }
  rows_.insert(rows_.end(), forces_.begin(), forces_.end());
}

void ConstrainedDynamics::measureCurvature(std::span<const std::unique_ptr<Joint>> joints,
                                           std::size_t ji, std::span<const Body> bodies,
                                           const SolverSettings& settings,
                                           std::span<const std::uint8_t> moving,
                                           const JointContext& ctx, std::span<const Row> rows,
                                           double eps) {
  const Joint& j = *joints[ji];
  // In closed form where the joint type has it: the rows' own turning at the bodies' velocities
  // (a body that is not moving does not turn: its velocity is taken as zero, as the differences
  // below leave it in place).
  JointContext still = ctx;
  if (!isMoving(j.body1(), moving)) still.b1.v = still.b1.w = Vec3::Zero();
  if (!isMoving(j.body2(), moving)) still.b2.v = still.b2.w = Vec3::Zero();
  closed_.resize(rows.size());
  j.curvature(still, rows, closed_);
  const std::size_t start = curvature_.size();
  bool known = true;
  for (std::size_t k = 0; k < rows.size() && known; ++k) {
    if (!actsOnMoving(rows[k], moving) || !holdsExactly(rows[k], settings, switches_)) continue;
    known = std::isfinite(closed_[k]);
    curvature_.push_back(closed_[k]);
  }
  if (known) return;
  // Otherwise by a central difference of the rows filled with the bodies moved back and forth.
  curvature_.resize(start);
  const auto fillAt = [&](double dt, std::vector<Row>& scratch) {
    const std::span<Row> slots = slotsFor(j, scratch);
    return std::span<const Row>(slots).first(static_cast<std::size_t>(
        fillJoint(joints, ji, bodies, shifted(ctx, j, moving, dt), slots)));
  };
  const std::span<const Row> before = fillAt(-eps, before_);
  const std::span<const Row> after = fillAt(eps, after_);
  // The three lists are in the joint's order: a row's match is found from just past the last
  // match (a row that comes or goes between them, if any, is passed over without losing the place).
  const auto match = [](std::span<const Row> list, std::size_t& cursor, std::uint64_t key) {
    for (std::size_t k = cursor; k < list.size(); ++k)
      if (list[k].key == key) {
        cursor = k + 1;
        return k;
      }
    return list.size();
  };
  std::size_t next_before = 0, next_after = 0;
  for (const Row& r : rows) {
    if (!actsOnMoving(r, moving) || !holdsExactly(r, settings, switches_)) continue;
    const std::size_t b = match(before, next_before, r.key);
    const std::size_t a = match(after, next_after, r.key);
    if (b == before.size() || a == after.size()) {  // a row that comes or goes
      curvature_.push_back(0.0);
      continue;
    }
    curvature_.push_back(rateChange(after[a], before[b], bodies) / (2.0 * eps));
  }
}

void ConstrainedDynamics::refine(std::size_t equalities) {
  // The regularized solve leaves J a short of its target by the regularization's C lambda. C is
  // relative to each row's J M^-1 J^T, which a light body's rotation makes large (a hinged
  // pendulum bob of 1e-4 kg m^2: 1e4) while the motion's own direction is stiff (1): relative to
  // it the shortfall is 1e-7, a first-order error over a run (IFToMM A01 on a hinge, 100 s at
  // tolerance 1e-10: 9.6e-6 m off the closed form). One step of iterated regularization solves
  // (A + C) d = the shortfall with the same factorization and adds d: the shortfall falls to
  // (C / A)^2 of itself (A01: 1.8e-7 m), while a near-singular direction stays damped (its filter
  // factor goes from s / (s + c) to about 2 s / c). Measured cost: A02's 20 s take 31 % more
  // attempts through its singular positions (5126 steps + 2048 refused, was 4658 + 810).
  residual_.resize(equalities);
  for (std::size_t k = 0; k < equalities; ++k) {
    double rate = 0.0;
    rows_[k].forEachBlock([&](int body, const Vec6& j) {
      if (body < 0) return;
      const solver::SolverBody& s = solver_bodies_[static_cast<std::size_t>(body)];
      rate += j.head<3>().dot(s.v) + j.tail<3>().dot(s.w);
    });
    residual_[k] = rows_[k].speed - rate;
  }
  if (dense_)
    dense_solver_.backSolve(residual_);
  else if (!solver_.backSolve(residual_))
    return;
  for (std::size_t k = 0; k < equalities; ++k) {
    const double d = residual_[k];
    lambda_[k] += d;
    rows_[k].forEachBlock([&](int body, const Vec6& j) {
      if (body < 0) return;
      solver::SolverBody& s = solver_bodies_[static_cast<std::size_t>(body)];
      s.v += s.inv_mass * d * j.head<3>();
      s.w += s.inv_inertia * (d * j.tail<3>());
    });
  }
}

void ConstrainedDynamics::accelerations(std::span<const std::unique_ptr<Joint>> joints,
                                        std::span<const Body> bodies, const WorldSettings& settings,
                                        std::span<const std::uint8_t> moving,
                                        const Switches& switches, double time, int threads,
                                        std::span<Vec3> dv, std::span<Vec3> dw) {
  switches_ = switches;
  // The equality rows first (they are solved), then the coordinate forces (they are applied).
  gather(joints, bodies, settings.solver, moving, time);
  const std::size_t equalities = curvature_.size();

  // The unconstrained accelerations M^-1 f, with the coordinate forces' J^T F.
  solver_bodies_.resize(bodies.size());
  for (std::size_t i = 0; i < bodies.size(); ++i) {
    solver::SolverBody& s = solver_bodies_[i];
    if (!moving[i]) {
      s = solver::SolverBody{};
      continue;
    }
    const Body& b = bodies[i];
    const Mat3 inertia = b.inertiaWorld();
    const Vec3 w = b.angularVelocity();
    const Vec3 force =
        b.mass() * settings.gravity + b.force() - b.mass() * b.linearDamping() * b.linearVelocity();
    const Vec3 torque = b.torque() - w.cross(inertia * w) - b.angularDamping() * (inertia * w);
    s = solver::SolverBody{b.inverseMass(), b.inverseInertiaWorld(), b.inverseMass() * force,
                           Vec3::Zero()};
    s.w = s.inv_inertia * torque;
  }
  for (const Row& r : rows_) {
    if (!isForceRow(r)) continue;
    r.forEachBlock([&](int body, const Vec6& j) {
      if (body < 0) return;
      solver::SolverBody& s = solver_bodies_[static_cast<std::size_t>(body)];
      s.v += s.inv_mass * r.lo * j.head<3>();
      s.w += s.inv_inertia * (r.lo * j.tail<3>());
    });
  }

  // J a = -(dJ/dt) u on the equality rows (plus d(target)/dt on a held velocity row's): a velocity
  // solve of unit length with the accelerations in place of the velocities, without error
  // reduction, and regularized by 1e-11 of each row's J M^-1 J^T: near a singular position (a
  // four-bar at its dead point) the rows' small pivots would otherwise amplify round-off and the
  // curvature's difference error into accelerations that jump from stage to stage, and the error
  // control would cut the step to a hundredth. The regularization's own error is then taken back by
  // one refinement (refine). A coordinate force's row takes no part in it (its bounds pin its
  // impulse: it stays at its force).
  for (std::size_t k = 0; k < equalities; ++k) {
    Row& r = rows_[k];
    r.speed = target_rate_[k] - curvature_[k];
    r.phi = 0.0;
    r.erp = 0.0;
    double diagonal = 0.0;
    r.forEachBlock([&](int body, const Vec6& j) {
      if (body < 0) return;
      const solver::SolverBody& s = solver_bodies_[static_cast<std::size_t>(body)];
      diagonal +=
          s.inv_mass * j.head<3>().squaredNorm() + j.tail<3>().dot(s.inv_inertia * j.tail<3>());
    });
    r.cfm = kRegularization * diagonal;
  }
  lambda_.assign(rows_.size(), 0.0);
  for (std::size_t k = equalities; k < rows_.size(); ++k) lambda_[k] = rows_[k].lo;
  SolverSettings exact = settings.solver;
  exact.type = SolverType::Exact;
  solver::Problem problem{std::span<const Row>(rows_).first(equalities), solver_bodies_,
                          std::span<double>(lambda_).first(equalities), 1.0, threads};
  if (equalities > 0) {
    // A few bodies' rows dense; else (or when the dense factorization fails) the exact solver.
    dense_ = dense_solver_.solve(problem, true);
    if (!dense_) solver_.solve(problem, exact);
    refine(equalities);
  }
  for (std::size_t i = 0; i < bodies.size(); ++i) {
    if (!moving[i]) continue;
    dv[i] = solver_bodies_[i].v;
    dw[i] = solver_bodies_[i].w;
  }
}

}  // namespace linx::step
