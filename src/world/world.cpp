// The world and its step. A step of length h runs `substeps` passes of these stages, in order
// (docs/architecture.md lists the same):
//   1. velocities   u* = u + h M^-1 (f_ext - gyroscopic)          dynamics/integrator
//   2. assembly     joints -> rows (count, allocate, fill, verify)  world/assembly
//   3. warm start   impulses of the previous step, by row key
//   4. solve        the boxed LCP for lambda, u+ = u* + M^-1 J^T lambda   solver/
//   5. positions    x += h v+, q = exp(h w+) q                     dynamics/integrator
//   6. projection   optional post-stabilization of joint errors    world/projection
//   7. tracking     joints follow their history (a hinge counts turns)
// then loads are cleared and the state is checked to be finite.
#include <linx/world.hpp>

#include "dynamics/energy.hpp"
#include "dynamics/integrator.hpp"
#include "solver/problem.hpp"
#include "world/assembly.hpp"
#include "world/projection.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <unordered_map>

namespace linx {

struct World::Impl {
  std::vector<Row> rows;
  std::vector<solver::SolverBody> solver_bodies;
  std::vector<double> lambda;
  std::unordered_map<std::uint64_t, double> warm;  // row key -> last impulse
  std::unique_ptr<solver::ConstraintSolver> solver;
  SolverType solver_type = SolverType::Exact;  // what `solver` is
};

World::World(const WorldSettings& settings)
    : settings_(settings), impl_(std::make_unique<Impl>()) {}
World::~World() = default;
World::World(World&&) noexcept = default;
World& World::operator=(World&&) noexcept = default;

BodyId World::createBody(const BodyDef& def) {
  if (findBody(def.name))
    throw std::invalid_argument(fmt::format("duplicate body name '{}'", def.name));
  if (!def.position.allFinite() || !def.orientation.coeffs().allFinite() ||
      !def.linear_velocity.allFinite() || !def.angular_velocity.allFinite())
    throw std::invalid_argument("pose and velocities must be finite");
  if (def.orientation.norm() < 1e-12) throw std::invalid_argument("orientation: zero quaternion");
  if (!def.is_static) {
    if (!(def.mass > 0.0) || !std::isfinite(def.mass))
      throw std::invalid_argument("mass: must be finite and > 0");
    const Mat3 sym = 0.5 * (def.inertia + def.inertia.transpose());
    if (!def.inertia.allFinite() || sym.llt().info() != Eigen::Success)
      throw std::invalid_argument("inertia: must be finite, symmetric and positive definite");
  }
  bodies_.emplace_back(def);
  return BodyId{bodyCount() - 1};
}

JointId World::createJoint(std::string_view type, const JointDef& def) {
  auto valid = [&](BodyId id) { return id.isWorld() || id.index < bodyCount(); };
  if (def.body1.isWorld() || !valid(def.body1))
    throw std::invalid_argument("body1: must be a body of this world");
  if (!valid(def.body2)) throw std::invalid_argument("body2: not a body of this world");
  if (def.body1 == def.body2) throw std::invalid_argument("body1 and body2 are the same body");
  if (findJoint(def.name))
    throw std::invalid_argument(fmt::format("duplicate joint name '{}'", def.name));
  joints_.push_back(makeJoint(type, def, bodyState(def.body1), bodyState(def.body2)));
  return JointId{jointCount() - 1};
}

Body& World::body(BodyId id) {
  if (id.index < 0 || id.index >= bodyCount()) throw std::out_of_range("no such body");
  return bodies_[static_cast<std::size_t>(id.index)];
}
const Body& World::body(BodyId id) const {
  return const_cast<World*>(this)->body(id);
}
Joint& World::joint(JointId id) {
  if (id.index < 0 || id.index >= jointCount()) throw std::out_of_range("no such joint");
  return *joints_[static_cast<std::size_t>(id.index)];
}
const Joint& World::joint(JointId id) const {
  return const_cast<World*>(this)->joint(id);
}

std::optional<BodyId> World::findBody(std::string_view name) const {
  for (int i = 0; i < bodyCount(); ++i)
    if (bodies_[static_cast<std::size_t>(i)].name() == name) return BodyId{i};
  return std::nullopt;
}
std::optional<JointId> World::findJoint(std::string_view name) const {
  for (int i = 0; i < jointCount(); ++i)
    if (joints_[static_cast<std::size_t>(i)]->name() == name) return JointId{i};
  return std::nullopt;
}

BodyState World::bodyState(BodyId id) const {
  return world::stateOf(bodies_, id);
}

void World::step() {
  const double h = settings_.timestep;
  if (!(h > 0.0) || !std::isfinite(h)) throw std::invalid_argument("timestep: must be > 0");
  const int substeps = std::max(1, settings_.solver.substeps);
  try {
    for (int s = 0; s < substeps; ++s) substep(h / substeps);
  } catch (const std::domain_error& e) {  // a joint's rows went non-finite (assembly, projection)
    throw NonFiniteState(fmt::format("{} in step {} (t = {} s)", e.what(), steps_ + 1, time_), -1,
                         steps_ + 1, time_);
  }
  for (Body& b : bodies_) b.clearLoads();
  ++steps_;
  // Time as a multiple of the step since the step last changed: no round-off accumulates.
  if (h != clock_step_) {
    clock_origin_ = time_;
    clock_step_ = h;
    clock_steps_ = 0;
  }
  time_ = clock_origin_ + static_cast<double>(++clock_steps_) * h;
  for (std::size_t i = 0; i < bodies_.size(); ++i) {
    const Body& b = bodies_[i];
    const char* what = !b.position().allFinite()               ? "position"
                       : !b.orientation().coeffs().allFinite() ? "orientation"
                       : !b.linearVelocity().allFinite()       ? "linear velocity"
                       : !b.angularVelocity().allFinite()      ? "angular velocity"
                                                               : nullptr;
    if (what)
      throw NonFiniteState(fmt::format("bodies[{}] ({}): {} is not finite after step {} (t = {} s)",
                                       i, b.name(), what, steps_, time_),
                           static_cast<int>(i), steps_, time_);
  }
}

void World::substep(double h) {
  Impl& m = *impl_;
  // 1. velocities
  for (Body& b : bodies_) dynamics::integrateVelocity(b, settings_.gravity, h);
  // 2. assembly
  world::assembleRows(joints_, bodies_, settings_.solver, h, m.rows);
  // 3. warm start
  m.lambda.assign(m.rows.size(), 0.0);
  if (settings_.solver.warm_start) {
    for (std::size_t k = 0; k < m.rows.size(); ++k) {
      const auto it = m.warm.find(m.rows[k].key);
      if (it != m.warm.end()) m.lambda[k] = it->second;
    }
  }
  // 4. solve
  m.solver_bodies.resize(bodies_.size());
  for (std::size_t i = 0; i < bodies_.size(); ++i) {
    const Body& b = bodies_[i];
    m.solver_bodies[i] = solver::SolverBody{b.inverseMass(), b.inverseInertiaWorld(),
                                            b.linearVelocity(), b.angularVelocity()};
  }
  if (!m.solver || m.solver_type != settings_.solver.type) {
    m.solver = solver::makeSolver(settings_.solver.type);
    m.solver_type = settings_.solver.type;
  }
  solver::Problem problem{m.rows, m.solver_bodies, m.lambda, h};
  report_ = m.solver->solve(problem, settings_.solver);
  m.warm.clear();
  for (std::size_t k = 0; k < m.rows.size(); ++k) m.warm[m.rows[k].key] = m.lambda[k];
  for (std::size_t i = 0; i < bodies_.size(); ++i) {
    if (bodies_[i].isStatic()) continue;
    bodies_[i].setLinearVelocity(m.solver_bodies[i].v);
    bodies_[i].setAngularVelocity(m.solver_bodies[i].w);
  }
  // 5. positions
  for (Body& b : bodies_) dynamics::integratePosition(b, h);
  // 6. projection
  if (settings_.solver.projection) world::projectPositions(joints_, bodies_, settings_.solver);
  // 7. tracking
  for (auto& j : joints_) j->track(bodyState(j->body1()), bodyState(j->body2()));
}

std::optional<double> World::jointCoordinate(JointId id) const {
  const Joint& j = joint(id);
  return j.coordinate(bodyState(j.body1()), bodyState(j.body2()));
}

double World::jointError(JointId id) const {
  const Joint& j = joint(id);
  return j.error(bodyState(j.body1()), bodyState(j.body2()));
}

double World::maxJointError() const {
  double e = 0.0;
  for (int i = 0; i < jointCount(); ++i) e = std::max(e, jointError(JointId{i}));
  return e;
}

Energy World::energy() const {
  return dynamics::computeEnergy(bodies_, settings_.gravity);
}

}  // namespace linx
