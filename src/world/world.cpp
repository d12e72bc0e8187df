// The world and its step. A step of length h runs `substeps` passes of these stages, in order
// (docs/architecture.md lists the same):
//   1. velocities   u* = u + h M^-1 (f_ext - gyroscopic)          dynamics/integrator
//   2. assembly     joints -> rows (count, allocate, fill, verify)  world/assembly
//                   shapes -> contact points -> contact rows        world/contact_stage
//   3. warm start   impulses of the previous step, by row key (contacts by feature id)
//   4. solve        the boxed LCP for lambda, u+ = u* + M^-1 J^T lambda   solver/
//   5. positions    x += h v+, q = exp(h w+) q                     dynamics/integrator
//   6. projection   optional post-stabilization of joint errors    world/projection
//   7. tracking     joints follow their history (a hinge counts turns)
//   8. sleeping     islands at rest for a while fall asleep          world/sleep
// Islands (bodies linked by this step's rows) are solved one by one, sleeping ones not at all.
// then loads are cleared and the state is checked to be finite.
#include <linx/world.hpp>

#include "dynamics/energy.hpp"
#include "dynamics/integrator.hpp"
#include "parallel/parallel_for.hpp"
#include "solver/problem.hpp"
#include "world/assembly.hpp"
#include "world/contact_stage.hpp"
#include "world/island_solver.hpp"
#include "world/islands.hpp"
#include "world/joint_warm_start.hpp"
#include "world/projection.hpp"
#include "world/sleep.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <unordered_map>

namespace linx {

namespace {
/// Bodies from which the per-body stages of a step are split over the threads.
constexpr std::ptrdiff_t kParallelBodies = 4096;
}  // namespace

struct World::Impl {
  std::vector<Row> rows;
  std::vector<solver::SolverBody> solver_bodies;
  std::vector<double> lambda;
  world::JointWarmStart joint_warm;
  world::ContactStage contact;
  world::Islands islands;
  world::IslandWorkspace island_work;
  world::SleepTracker sleep;
  std::vector<std::pair<int, int>> links;
  std::vector<std::uint8_t> movable, was_asleep, may_sleep;
  std::vector<double> lambda0;
  std::vector<int> neighbours;  // the warm-start impulses, kept for sleeping islands
  std::unique_ptr<solver::ConstraintSolver> solver;
  SolverType solver_type = SolverType::Auto;  // what `solver` is
  // Names to indices: a scene of 64,000 bodies would otherwise spend seconds in duplicate checks.
  std::unordered_map<std::string, int> body_names, joint_names;
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
  for (std::size_t k = 0; k < def.shapes.size(); ++k) {
    const ShapeDef& s = def.shapes[k];
    auto bad = [&](const std::string& what) {
      return std::invalid_argument(
          fmt::format("shapes[{}] ({}): {}", k, shapeTypeName(s.type), what));
    };
    if (isStaticOnly(s.type) && !def.is_static) throw bad("only a static body may carry it");
    if (!(s.friction >= 0.0) || !std::isfinite(s.friction)) throw bad("friction: must be >= 0");
    if (!(s.restitution >= 0.0 && s.restitution <= 1.0))
      throw bad("restitution: must be in [0, 1]");
    if (!s.position.allFinite() || !s.orientation.coeffs().allFinite() ||
        s.orientation.norm() < 1e-12)
      throw bad("position and orientation must be finite, the quaternion non-zero");
  }
  Body body(def);
  impl_->contact.addBody(body);  // prepares hulls and meshes; throws for bad ones
  bodies_.push_back(std::move(body));
  impl_->body_names.emplace(def.name, bodyCount() - 1);
  impl_->sleep.resize(bodyCount());
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
  impl_->joint_names.emplace(def.name, jointCount() - 1);
  // A new joint may pull on sleeping bodies.
  impl_->sleep.wake(def.body1.index);
  if (!def.body2.isWorld()) impl_->sleep.wake(def.body2.index);
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
  const auto it = impl_->body_names.find(std::string(name));
  if (it == impl_->body_names.end()) return std::nullopt;
  return BodyId{it->second};
}
std::optional<JointId> World::findJoint(std::string_view name) const {
  const auto it = impl_->joint_names.find(std::string(name));
  if (it == impl_->joint_names.end()) return std::nullopt;
  return JointId{it->second};
}

BodyState World::bodyState(BodyId id) const {
  return world::stateOf(bodies_, id);
}

void World::step() {
  const double h = settings_.timestep;
  if (!(h > 0.0) || !std::isfinite(h)) throw std::invalid_argument("timestep: must be > 0");
  if (settings_.threads < 0 || settings_.threads > kMaxThreads)
    throw std::invalid_argument(
        fmt::format("threads: must be in [0, {}] (0: one per core)", kMaxThreads));
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
  const int threads = parallel::resolveThreads(settings_.threads);
  const SleepSettings& sleep = settings_.sleep;
  auto awake = [&](std::size_t i) { return !m.sleep.asleep(static_cast<int>(i)); };
  // Something pushed or moved a sleeping body from outside: it wakes (with its island, below).
  for (std::size_t i = 0; i < bodies_.size(); ++i) {
    const Body& b = bodies_[i];
    if (!awake(i) && (!b.linearVelocity().isZero(0) || !b.angularVelocity().isZero(0) ||
                      !b.force().isZero(0) || !b.torque().isZero(0)))
      wakeWithNeighbours(static_cast<int>(i));
  }
  // Per-body stages are split over the threads in large worlds (each body writes only itself).
  const auto each_body = [&](auto&& body) {
    parallel::forEach(static_cast<std::ptrdiff_t>(bodies_.size()), threads, kParallelBodies,
                      [&](std::ptrdiff_t i) { body(static_cast<std::size_t>(i)); });
  };
  // 1. velocities (sleeping bodies stay at rest)
  each_body([&](std::size_t i) {
    if (awake(i)) dynamics::integrateVelocity(bodies_[i], settings_.gravity, h);
  });
  // 2. assembly, 3. warm start: joint rows, then contact rows
  world::assembleRows(joints_, bodies_, settings_.solver, h, m.rows);
  const std::size_t joint_rows = m.rows.size();
  m.lambda.assign(joint_rows, 0.0);
  if (settings_.solver.warm_start) m.joint_warm.load(m.rows, m.lambda);
  m.contact.detect(bodies_, joints_, settings_.contact, h, threads);
  m.contact.appendRows(bodies_, h, m.rows, m.lambda, settings_.solver.warm_start, threads);
  // Islands: bodies linked by this step's rows. An island with an awake body wakes entirely; the
  // bodies it wakes get this step's velocity update too.
  world::rowLinks(m.rows, m.links);
  m.movable.resize(bodies_.size());
  for (std::size_t i = 0; i < bodies_.size(); ++i) m.movable[i] = !bodies_[i].isStatic();
  m.islands.build(bodyCount(), m.movable, m.links);
  m.was_asleep.resize(bodies_.size());
  for (std::size_t i = 0; i < bodies_.size(); ++i) m.was_asleep[i] = !awake(i);
  const std::span<const std::uint8_t> island_awake =
      sleep.enabled ? m.sleep.wakeIslands(m.islands) : std::span<const std::uint8_t>{};
  if (!sleep.enabled) m.sleep.wakeAll();
  for (std::size_t i = 0; i < bodies_.size(); ++i)
    if (m.was_asleep[i] && awake(i)) dynamics::integrateVelocity(bodies_[i], settings_.gravity, h);
  // 4. solve, island by island (sleeping islands are skipped)
  m.solver_bodies.resize(bodies_.size());
  each_body([&](std::size_t i) {
    const Body& b = bodies_[i];
    m.solver_bodies[i] = solver::SolverBody{b.inverseMass(), b.inverseInertiaWorld(),
                                            b.linearVelocity(), b.angularVelocity()};
  });
  if (!m.solver || m.solver_type != settings_.solver.type) {
    m.solver = solver::makeSolver(settings_.solver.type);
    m.solver_type = settings_.solver.type;
  }
  m.lambda0 = m.lambda;
  report_ = world::solveIslands(m.islands, island_awake, m.rows, m.solver_bodies, m.lambda, h,
                                *m.solver, settings_.solver, m.island_work, threads);
  // Sleeping islands keep the impulses they rested on, for when they wake.
  for (std::size_t k = 0; k < m.rows.size(); ++k) {
    const int island = m.island_work.row_island[k];
    if (island >= 0 && !island_awake.empty() && !island_awake[static_cast<std::size_t>(island)])
      m.lambda[k] = m.lambda0[k];
  }
  m.joint_warm.store(std::span<const Row>(m.rows).first(joint_rows), m.lambda);
  m.contact.store(bodies_, m.lambda, threads);
  // 5. positions
  each_body([&](std::size_t i) {
    if (bodies_[i].isStatic() || !awake(i)) return;
    bodies_[i].setLinearVelocity(m.solver_bodies[i].v);
    bodies_[i].setAngularVelocity(m.solver_bodies[i].w);
    dynamics::integratePosition(bodies_[i], h);
  });
  // 6. projection
  if (settings_.solver.projection) {
    for (std::size_t i = 0; i < bodies_.size(); ++i) m.was_asleep[i] = !awake(i);
    world::projectPositions(joints_, bodies_, settings_.solver, m.was_asleep);
  }
  // 7. tracking
  for (auto& j : joints_) j->track(bodyState(j->body1()), bodyState(j->body2()));
  // 8. sleeping: islands at rest long enough fall asleep, their bodies stop
  if (sleep.enabled) {
    // Only islands that rest on contacts sleep: a mechanism of joints alone keeps moving however
    // slowly it swings (a pendulum at 1 cm amplitude is below every rest threshold).
    m.may_sleep.assign(static_cast<std::size_t>(m.islands.count()), 0);
    for (std::size_t k = joint_rows; k < m.rows.size(); ++k) {
      const int island = m.island_work.row_island[k];
      if (island >= 0) m.may_sleep[static_cast<std::size_t>(island)] = 1;
    }
    m.sleep.update(m.islands, bodies_, h, sleep, m.may_sleep);
    for (std::size_t i = 0; i < bodies_.size(); ++i) {
      if (awake(i) || bodies_[i].isStatic()) continue;
      bodies_[i].setLinearVelocity(Vec3::Zero());
      bodies_[i].setAngularVelocity(Vec3::Zero());
    }
  }
}

bool World::isAsleep(BodyId id) const {
  body(id);  // checks the id
  return impl_->sleep.asleep(id.index);
}

void World::wake(BodyId id) {
  body(id);
  wakeWithNeighbours(id.index);
}

void World::wakeWithNeighbours(int index) {
  // The bodies it touched wake too: if it moves away, or was moved away, they must notice (the
  // islands of the next step no longer link them). A static body wakes only its neighbours.
  if (!bodies_[static_cast<std::size_t>(index)].isStatic()) impl_->sleep.wake(index);
  impl_->neighbours.clear();
  impl_->contact.touching(index, impl_->neighbours);
  for (const int n : impl_->neighbours)
    if (!bodies_[static_cast<std::size_t>(n)].isStatic()) impl_->sleep.wake(n);
}

std::span<const Contact> World::contacts() const {
  return impl_->contact.contacts();
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
