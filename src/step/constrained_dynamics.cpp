#include "step/constrained_dynamics.hpp"

#include "dynamics/integrator.hpp"
#include "joints/row_parts.hpp"
#include "step/assembly.hpp"

#include <algorithm>
#include <cmath>
#include <optional>
#include <utility>

namespace linx::step {

namespace {

/// The length the rows are assembled for: short, so that what a row takes over it is what it
/// takes at the rows' time (a force or a motor's target rate at time + h / 2 or time + h); the
/// impulses of coordinate forces and the bounds of drives are divided by it.
constexpr double kAssemblyStep = 1e-9;

/// A coordinate force: a motor row whose bounds pin its impulse (Joint::setForce, "force").
bool isForceRow(const Row& r) {
  return r.kind == RowKind::Motor && r.lo == r.hi;
}

/// The stiffness and damping of a drive row (a spring, a servo), none for other rows.
std::optional<std::pair<double, double>> driveLaw(const Row& r,
                                                  std::span<const std::unique_ptr<Joint>> joints) {
  if (r.kind != RowKind::Drive) return std::nullopt;
  const auto joint = static_cast<std::size_t>((r.key >> 8) - 1);
  const int slot = static_cast<int>(r.key & 0xff);
  if (joint >= joints.size() || slot < joints::coordinateSlot(0, 0)) return std::nullopt;
  const auto index = static_cast<std::size_t>((slot - 16) / 16);
  const int part = (slot - 16) % 16;
  const auto& coordinates = joints[joint]->def().coordinates;
  if (index >= coordinates.size()) return std::nullopt;
  const CoordinateDef& c = coordinates[index];
  if (part == 3 && c.spring) return std::pair{c.spring->stiffness, c.spring->damping};
  if (part == 2 && c.motor && c.motor->isServo())
    return std::pair{c.motor->target_position ? c.motor->stiffness : 0.0, c.motor->damping};
  return std::nullopt;  // armature
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
                      double time, std::vector<Row>& all, std::vector<Row>& out) {
  assembleRows(joints, bodies, settings, kAssemblyStep, time, all);
  out.clear();
  for (const Row& r : all)
    if (holdsExactly(r, settings) && actsOnMoving(r, moving)) out.push_back(r);
}

bool actsAsForce(const Row& row, std::span<const std::unique_ptr<Joint>> joints) {
  return isForceRow(row) || driveLaw(row, joints).has_value();
}

bool holdsExactly(const Row& row, const SolverSettings& settings) {
  // (Only a prescribed coordinate's equality has a speed of its own; the step's curvature may have
  // set one on the others.)
  return row.kind == RowKind::Bilateral && row.cfm <= settings.cfm &&
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
                                 std::span<const std::uint8_t> moving, double time,
                                 std::vector<Row>& out) {
  // h scales only what these rows do not use (a motor's bound: a force row's impulse over h = 1).
  assembleRows(joints, bodies, settings, kAssemblyStep, time, all_);
  out.clear();
  for (const Row& r : all_) {
    if (!actsOnMoving(r, moving)) continue;
    if (holdsExactly(r, settings)) {
      out.push_back(r);
    } else if (isForceRow(r)) {
      Row& f = out.emplace_back(r);
      f.lo = f.hi = r.lo / kAssemblyStep;
    } else if (const auto law = driveLaw(r, joints)) {
      // A drive's force at the bodies' state, as a coordinate force.
      const auto [stiffness, damping] = *law;
      const double force = -stiffness * r.phi - damping * (rowSpeed(r, bodies) - r.speed);
      Row& f = out.emplace_back(r);
      f.kind = RowKind::Motor;
      f.lo = f.hi = std::clamp(force, r.lo / kAssemblyStep, r.hi / kAssemblyStep);
    }
  }
}

void ConstrainedDynamics::measureCurvature(std::span<const std::unique_ptr<Joint>> joints,
                                           std::span<Body> bodies, const SolverSettings& settings,
                                           std::span<const std::uint8_t> moving, double time) {
  // The time step of the difference: the fastest body turns or moves 1e-5 (rad, or m over a
  // metre) along it. The difference's truncation error is then about 1e-10 of the curvature and
  // its round-off about 1e-16 / 1e-5 of the rows' size times the speed.
  double speed = 1.0;
  for (std::size_t i = 0; i < bodies.size(); ++i)
    if (moving[i])
      speed =
          std::max({speed, bodies[i].linearVelocity().norm(), bodies[i].angularVelocity().norm()});
  const double eps = 1e-5 / speed;
  poses_.resize(bodies.size());
  for (std::size_t i = 0; i < bodies.size(); ++i)
    if (moving[i]) poses_[i] = bodies[i].pose();
  const auto shift = [&](double dt, std::vector<Row>& out) {
    for (std::size_t i = 0; i < bodies.size(); ++i) {
      if (!moving[i]) continue;
      bodies[i].setPose(poses_[i]);
      dynamics::integratePosition(bodies[i], dt);
    }
    gather(joints, bodies, settings, moving, time + dt, out);
  };
  shift(-eps, before_);
  shift(eps, after_);
  for (std::size_t i = 0; i < bodies.size(); ++i)
    if (moving[i]) bodies[i].setPose(poses_[i]);

  // The three lists follow the joints' order: a row's match is found from just past the last
  // match (a row that comes or goes between them, if any, is passed over without losing the place).
  const auto match = [](const std::vector<Row>& list, std::size_t& cursor, std::uint64_t key) {
    for (std::size_t j = cursor; j < list.size(); ++j)
      if (list[j].key == key) {
        cursor = j + 1;
        return j;
      }
    return list.size();
  };
  curvature_.assign(rows_.size(), 0.0);
  std::size_t next_before = 0, next_after = 0;
  for (std::size_t k = 0; k < rows_.size(); ++k) {
    if (isForceRow(rows_[k])) continue;
    const std::size_t b = match(before_, next_before, rows_[k].key);
    const std::size_t a = match(after_, next_after, rows_[k].key);
    if (b == before_.size() || a == after_.size()) continue;  // a row that comes or goes
    const Row& lo = before_[b];
    const Row& hi = after_[a];
    Row d = hi;
    d.Ja -= lo.Ja;
    d.Jb -= lo.Jb;
    d.Jc -= lo.Jc;
    d.Jd -= lo.Jd;
    curvature_[k] = rowSpeed(d, bodies) / (2.0 * eps);
  }
}

void ConstrainedDynamics::accelerations(std::span<const std::unique_ptr<Joint>> joints,
                                        std::span<Body> bodies, const WorldSettings& settings,
                                        std::span<const std::uint8_t> moving, double time,
                                        int threads, std::span<Vec3> dv, std::span<Vec3> dw) {
  gather(joints, bodies, settings.solver, moving, time, rows_);
  // The equality rows first (they are solved), then the coordinate forces (they are applied).
  const auto forces = std::stable_partition(rows_.begin(), rows_.end(),
                                            [](const Row& r) { return !isForceRow(r); });
  const auto equalities = static_cast<std::size_t>(forces - rows_.begin());
  measureCurvature(joints, bodies, settings.solver, moving, time);

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

  // J a = -(dJ/dt) u on the equality rows: a velocity solve of unit length with the accelerations
  // in place of the velocities, without error reduction or regularization. A coordinate force's
  // row takes no part in it (its bounds pin its impulse: it stays at its force).
  for (std::size_t k = 0; k < rows_.size(); ++k) {
    Row& r = rows_[k];
    if (isForceRow(r)) continue;
    r.speed = -curvature_[k];
    r.phi = 0.0;
    r.erp = 0.0;
    r.cfm = 0.0;
  }
  lambda_.assign(rows_.size(), 0.0);
  for (std::size_t k = 0; k < rows_.size(); ++k)
    if (isForceRow(rows_[k])) lambda_[k] = rows_[k].lo;
  SolverSettings exact = settings.solver;
  exact.type = SolverType::Exact;
  solver::Problem problem{std::span<const Row>(rows_).first(equalities), solver_bodies_,
                          std::span<double>(lambda_).first(equalities), 1.0, threads};
  if (equalities > 0) solver_.solve(problem, exact);
  for (std::size_t i = 0; i < bodies.size(); ++i) {
    if (!moving[i]) continue;
    dv[i] = solver_bodies_[i].v;
    dw[i] = solver_bodies_[i].w;
  }
}

}  // namespace linx::step
