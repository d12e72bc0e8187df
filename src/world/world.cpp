// The world: its bodies and joints, their creation and queries. The step itself is a list of
// named stages in step/step.hpp; World::step() runs `substeps` passes of it, then checks the state.
#include <linx/world.hpp>

#include <linx/bounds.hpp>
#include <linx/mass_properties.hpp>

#include "dynamics/energy.hpp"
#include "joints/local_frames.hpp"
#include "joints/validation.hpp"
#include "math/rotation.hpp"
#include "parallel/parallel_for.hpp"
#include "schema/check.hpp"
#include "step/assembly.hpp"
#include "step/check.hpp"
#include "step/step.hpp"
#include "world/applied_loads.hpp"
#include "world/joint_pose.hpp"
#include "world/slots.hpp"
#include "world/world_impl.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <tuple>
#include <unordered_map>
#include <utility>

namespace linx {

namespace {

/// Why a length (m) or a point's largest coordinate is beyond kMaxExtent, "" if it is not.
std::string beyondExtent(double length) {
  if (std::abs(length) <= kMaxExtent) return "";
  return fmt::format(
      "{:.6g} m is beyond {:g} m: doubles there are {:.2g} m apart, too coarse to resolve a "
      "contact within the slop",
      length, kMaxExtent, std::abs(length) * 0x1p-52);
}
std::string beyondExtent(const Vec3& x) {
  return beyondExtent(x.cwiseAbs().maxCoeff());
}

/// The first field of a shape whose geometry lies beyond kMaxExtent, and why ("" for none).
std::pair<std::string, std::string> shapeBeyondExtent(const ShapeDef& s) {
  if (std::string far = beyondExtent(s.position); !far.empty()) return {"position", far};
  const std::pair<const char*, double> sizes[] = {
      {"radius", s.radius}, {"length", s.length}, {"size", s.size.cwiseAbs().maxCoeff()}};
  for (const auto& [field, value] : sizes)
    if (std::string far = beyondExtent(value); !far.empty()) return {field, far};
  if (std::string far = beyondExtent(s.offset); !far.empty()) return {"offset", far};
  for (const Vec3& p : s.points)
    if (std::string far = beyondExtent(p); !far.empty()) return {"points", far};
  return {};
}

/// Whether something drove the world over the last step, making energy that is not the solver's:
/// motors, servos, prescribed motion, moving kinematic bodies. (A spring's energy is not counted
/// in the fault check's.)
bool driven(std::span<const Row> rows, std::span<const std::unique_ptr<Joint>> joints,
            std::span<const Body> bodies) {
  const auto drive = [](const Row& r) {
    return r.kind == RowKind::Motor || r.kind == RowKind::Drive;
  };
  const auto prescribed = [](const std::unique_ptr<Joint>& j) {
    const auto& c = j->def().coordinates;
    return std::any_of(c.begin(), c.end(), [](const CoordinateDef& d) { return d.prescribed; });
  };
  const auto moving = [](const Body& b) { return b.isKinematic() && b.isMoving(); };
  return std::any_of(rows.begin(), rows.end(), drive) ||
         std::any_of(joints.begin(), joints.end(), prescribed) ||
         std::any_of(bodies.begin(), bodies.end(), moving);
}

/// What stays in a removed joint's slot until a new joint takes it: no rows, no coordinates, no
/// effect on collisions. It names the removed joint's body1, a slot that stays valid.
class RemovedJoint final : public Joint {
 public:
  explicit RemovedJoint(BodyId body1) : Joint(defOf(body1)) { setEnabled(false); }
  std::string_view type() const override { return "removed"; }
  int maxRows() const override { return 0; }
  int fill(const JointContext&, std::span<Row>) const override { return 0; }
  JointCoordinates coordinates(const BodyState&, const BodyState&) const override {
    return JointCoordinates(0);
  }

 private:
  static JointDef defOf(BodyId body1) {
    JointDef def;
    def.body1 = body1;
    return def;
  }
};

}  // namespace

World::World(const WorldSettings& settings)
    : settings_(settings), impl_(std::make_unique<Impl>()) {}
World::~World() = default;
World::World(World&&) noexcept = default;
World& World::operator=(World&&) noexcept = default;

BodyId World::createBody(const BodyDef& given) {
  if (given.name.empty()) throw std::invalid_argument("name: must not be empty");
  if (findBody(given.name))
    throw std::invalid_argument(fmt::format("duplicate body name '{}'", given.name));
  // A mass given is checked before anything is made from it (an inertia filled to it).
  if (given.is_static && given.kinematic)
    throw std::invalid_argument("kinematic: a body is static or kinematic, not both");
  if (given.path && !given.kinematic)
    throw std::invalid_argument("path: only a kinematic body follows a path");
  if (given.path)
    for (int k = 0; k < 3; ++k)
      joints::validateSignal(given.path->components[static_cast<std::size_t>(k)],
                             fmt::format("path[{}]", k));
  if (given.kinematic && (given.mass || given.inertia))
    throw std::invalid_argument("mass: a kinematic body has infinite mass: give it none");
  if (!given.is_static && given.mass && !(*given.mass > 0.0 && std::isfinite(*given.mass)))
    throw std::invalid_argument("mass: must be finite and > 0");
  BodyDef def = given;
  completeMassProperties(def);
  if (!def.position.allFinite() || !def.orientation.coeffs().allFinite() ||
      !def.linear_velocity.allFinite() || !def.angular_velocity.allFinite())
    throw std::invalid_argument("pose and velocities must be finite");
  if (def.orientation.norm() < 1e-12) throw std::invalid_argument("orientation: zero quaternion");
  if (const std::string far = beyondExtent(def.position); !far.empty())
    throw std::invalid_argument("position: " + far);
  for (const auto& [field, value] : {std::pair{"linear_damping", def.linear_damping},
                                     std::pair{"angular_damping", def.angular_damping}})
    if (!(std::isfinite(value) && value >= 0.0))
      throw std::invalid_argument(fmt::format("{}: must be finite and >= 0", field));
  if (!def.is_static && !def.kinematic) {
    if (!(*def.mass > 0.0) || !std::isfinite(*def.mass))
      throw std::invalid_argument("mass: must be finite and > 0");
    const Mat3 sym = 0.5 * (*def.inertia + def.inertia->transpose());
    if (!def.inertia->allFinite() || sym.llt().info() != Eigen::Success)
      throw std::invalid_argument("inertia: must be finite, symmetric and positive definite");
    // A rigid body's principal moments satisfy the triangle inequality: each at most the sum of
    // the other two (a thin plate's largest is their sum; sum of m r^2 over the others' axes).
    const Vec3 moments =
        Eigen::SelfAdjointEigenSolver<Mat3>(sym, Eigen::EigenvaluesOnly).eigenvalues();
    if (moments[2] > (moments[0] + moments[1]) * (1.0 + 1e-9))
      throw std::invalid_argument(fmt::format(
          "inertia: principal moments {:.6g}, {:.6g}, {:.6g} are not a rigid body's (the largest "
          "exceeds the sum of the other two)",
          moments[0], moments[1], moments[2]));
  }
  for (std::size_t k = 0; k < def.shapes.size(); ++k) {
    const ShapeDef& s = def.shapes[k];
    auto bad = [&](const std::string& what) {
      return std::invalid_argument(
          fmt::format("shapes[{}] ({}): {}", k, shapeTypeName(s.type), what));
    };
    if (isStaticOnly(s.type) && !def.is_static) throw bad("only a static body may carry it");
    if (def.kinematic && s.density) throw bad("density: a kinematic body has no mass");
    if (!(s.friction >= 0.0) || !std::isfinite(s.friction)) throw bad("friction: must be >= 0");
    if (!(s.restitution >= 0.0 && s.restitution <= 1.0))
      throw bad("restitution: must be in [0, 1]");
    if (!s.position.allFinite() || !s.orientation.coeffs().allFinite() ||
        s.orientation.norm() < 1e-12)
      throw bad("position and orientation must be finite, the quaternion non-zero");
    const auto [field, far] = shapeBeyondExtent(s);
    if (!far.empty()) throw bad(fmt::format("{}: {}", field, far));
  }
  Body body(def);
  Slots& slots = impl_->body_slots;
  const int slot = slots.next();
  impl_->step.contact.setBody(slot, body);  // prepares hulls and meshes; throws for bad ones
  slots.take();
  body.id_ = BodyId{slot, slots.generation(slot)};
  if (slot == bodyCount())
    bodies_.push_back(std::move(body));
  else
    bodies_[static_cast<std::size_t>(slot)] = std::move(body);
  impl_->body_names.emplace(def.name, slot);
  if (def.path) impl_->paths.emplace_back(slot, *def.path);
  impl_->step.sleep.resize(bodyCount());
  impl_->step.sleep.wake(slot);  // a taken slot forgets its last body's rest
  return BodyId{slot, slots.generation(slot)};
}

JointId World::createJoint(std::string_view type, const JointDef& given) {
  // A joint that ties two joints (a mimic joint) is between the follower's bodies.
  JointDef def = given;
  std::array<const Joint*, 2> coupled = {nullptr, nullptr};
  if (const JointTypeInfo* t = findJointType(type); t && t->couplesJoints()) {
    for (const auto& [field, id, out] : {std::tuple{"leader", def.leader, &coupled[0]},
                                         std::tuple{"follower", def.follower, &coupled[1]}}) {
      if (!id) throw std::invalid_argument(fmt::format("{}: a {} joint needs one", field, type));
      if (!contains(*id))
        throw std::invalid_argument(fmt::format("{}: not a joint of this world", field));
      *out = &joint(*id);
    }
    def.body1 = coupled[1]->body1();
    def.body2 = coupled[1]->body2();
  }
  if (!contains(def.body1)) throw std::invalid_argument("body1: must be a body of this world");
  if (!def.body2.isWorld() && !contains(def.body2))
    throw std::invalid_argument("body2: not a body of this world");
  if (def.body1 == def.body2) throw std::invalid_argument("body1 and body2 are the same body");
  if (def.name.empty()) throw std::invalid_argument("name: must not be empty");
  if (findJoint(def.name))
    throw std::invalid_argument(fmt::format("duplicate joint name '{}'", def.name));
  const BodyState b1 = bodyState(def.body1), b2 = bodyState(def.body2);
  auto joint = makeJoint(type, joints::inWorldFrame(def, b1.pose, b2.pose), b1, b2, coupled);
  Slots& slots = impl_->joint_slots;
  const int slot = slots.take();
  if (slot == jointCount())
    joints_.push_back(std::move(joint));
  else
    joints_[static_cast<std::size_t>(slot)] = std::move(joint);
  impl_->joint_names.emplace(def.name, slot);
  // A new joint may pull on sleeping bodies.
  impl_->step.sleep.wake(def.body1.index);
  if (!def.body2.isWorld()) impl_->step.sleep.wake(def.body2.index);
  return JointId{slot, slots.generation(slot)};
}

void World::removeBody(BodyId id) {
  const Body& removed = body(id);  // checks the id
  const auto slot = static_cast<std::size_t>(id.index);
  for (const JointId j : jointIds()) {
    const Joint& joint = *joints_[static_cast<std::size_t>(j.index)];
    if (joint.body1() == id || joint.body2() == id) removeJoint(j);
  }
  step::wakeWithNeighbours(bodies_, impl_->step, id.index);  // they may lose their support
  impl_->loads.removeBody(id.index);
  std::erase_if(impl_->paths, [&](const auto& path) { return path.first == id.index; });
  impl_->body_names.erase(removed.name());
  impl_->step.contact.removeBody(id.index);
  // What stays in the slot: a static body without shapes, which every stage passes over.
  BodyDef empty;
  empty.is_static = true;
  bodies_[slot] = Body(empty);
  impl_->body_slots.release(id.index);
}

void World::removeJoint(JointId id) {
  const Joint& removed = joint(id);  // checks the id
  const auto slot = static_cast<std::size_t>(id.index);
  // A joint that ties this one to another (a mimic joint) goes with it.
  for (const JointId j : jointIds()) {
    const JointDef& def = joints_[static_cast<std::size_t>(j.index)]->def();
    if (j != id && (def.leader == id || def.follower == id)) removeJoint(j);
  }
  for (const BodyId b : {removed.body1(), removed.body2()})  // they may have hung on it
    if (!b.isWorld()) impl_->step.sleep.wake(b.index);
  impl_->joint_names.erase(removed.name());
  impl_->step.joint_warm.forget(slot);
  impl_->step.joint_loads.forget(slot);
  impl_->step.stabilization.forget(slot);
  joints_[slot] = std::make_unique<RemovedJoint>(removed.body1());
  impl_->joint_slots.release(id.index);
}

bool World::contains(BodyId id) const {
  return impl_->body_slots.matches(id.index, id.generation);
}
bool World::contains(JointId id) const {
  return impl_->joint_slots.matches(id.index, id.generation);
}

std::vector<BodyId> World::bodyIds() const {
  std::vector<BodyId> ids;
  for (int i = 0; i < bodyCount(); ++i)
    if (impl_->body_slots.used(i)) ids.push_back(BodyId{i, impl_->body_slots.generation(i)});
  return ids;
}
std::vector<JointId> World::jointIds() const {
  std::vector<JointId> ids;
  for (int i = 0; i < jointCount(); ++i)
    if (impl_->joint_slots.used(i)) ids.push_back(JointId{i, impl_->joint_slots.generation(i)});
  return ids;
}

Body& World::body(BodyId id) {
  if (!contains(id))
    throw std::out_of_range(id.index >= 0 && id.index < bodyCount() ? "no such body: it was removed"
                                                                    : "no such body");
  return bodies_[static_cast<std::size_t>(id.index)];
}
const Body& World::body(BodyId id) const {
  return const_cast<World*>(this)->body(id);
}
Joint& World::joint(JointId id) {
  if (!contains(id))
    throw std::out_of_range(id.index >= 0 && id.index < jointCount()
                                ? "no such joint: it was removed"
                                : "no such joint");
  return *joints_[static_cast<std::size_t>(id.index)];
}
const Joint& World::joint(JointId id) const {
  return const_cast<World*>(this)->joint(id);
}

std::optional<BodyId> World::findBody(std::string_view name) const {
  const auto it = impl_->body_names.find(std::string(name));
  if (it == impl_->body_names.end()) return std::nullopt;
  return BodyId{it->second, impl_->body_slots.generation(it->second)};
}
std::optional<JointId> World::findJoint(std::string_view name) const {
  const auto it = impl_->joint_names.find(std::string(name));
  if (it == impl_->joint_names.end()) return std::nullopt;
  return JointId{it->second, impl_->joint_slots.generation(it->second)};
}

BodyState World::bodyState(BodyId id) const {
  if (!id.isWorld()) body(id);  // checks the id
  return step::stateOf(bodies_, id);
}

const IntegratorReport& World::lastIntegratorReport() const {
  return impl_->step.accurate_report;
}

void World::step() {
  const double h = settings_.timestep;
  if (!(h >= kMinTimestep) || !std::isfinite(h))
    throw std::invalid_argument(fmt::format(
        "timestep: must be finite and at least {:g} s (the step forms h^2)", kMinTimestep));
  if (settings_.threads < 0 || settings_.threads > kMaxThreads)
    throw std::invalid_argument(
        fmt::format("threads: must be in [0, {}] (0: one per core)", kMaxThreads));
  // Each section as a scene file's is checked (src/schema/describe.hpp): a field out of its
  // bounds is named, "solver.erp: must be between 0 and 1, got 2".
  schema::check(settings_.solver, "solver.");
  schema::check(settings_.integrator, "integrator.");
  schema::check(settings_.contact, "contact.");
  schema::check(settings_.sleep, "sleep.");
  schema::check(settings_.faults, "faults.");
  const FaultSettings& faults = settings_.faults;
  // The soft step substeps within one pass; the others pass `substeps` times.
  const int substeps =
      settings_.solver.type == SolverType::Soft ? 1 : std::max(1, settings_.solver.substeps);
  for (const auto& [body, path] : impl_->paths)  // the velocity that reaches the path at t + h
    bodies_[static_cast<std::size_t>(body)].setLinearVelocity(
        (path.at(time_ + h) - bodies_[static_cast<std::size_t>(body)].position()) / h);
  if (impl_->force_callback) impl_->force_callback(*this);
  impl_->actuators.apply(*this, time_);
  impl_->loads.apply(bodies_, time_);
  step::Scene scene{bodies_, joints_, settings_, parallel::resolveThreads(settings_.threads)};
  impl_->check.begin(bodies_, settings_.gravity);
  try {
    for (int s = 0; s < substeps; ++s) {
      scene.time = time_ + s * (h / substeps);
      report_ = step::pass(scene, impl_->step, h / substeps);
    }
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
  const auto& rows = impl_->step.rows.rows;
  const bool motors = driven(rows, joints_, bodies_);
  try {
    impl_->check.end(bodies_, settings_.gravity, faults, motors, steps_, time_);
    if (steps_ % faults.joint_error_every == 0) checkJointErrors();
  } catch (const NonFiniteState&) {
    throw;
  } catch (const StepFault& fault) {
    if (faults.stop) throw;
    if (faults_.size() < kKeptFaults) faults_.emplace_back(fault.what());
    ++fault_count_;
  }
  breakOverloadedJoints();
}

void World::checkJointErrors() const {
  const double bound = settings_.faults.max_joint_error;
  if (std::isinf(bound)) return;
  for (const JointId id : jointIds()) {
    const double error = jointError(id);
    if (!(error > bound)) continue;
    throw BoundExceeded(
        fmt::format("joints[{}] ({}): error {:.6g} (m or rad) is above faults.max_joint_error ({}) "
                    "after step {} (t = {} s)",
                    id.index, joint(id).name(), error, bound, steps_, time_),
        -1, id.index, steps_, time_);
  }
}

void World::breakOverloadedJoints() {
  for (std::size_t i = 0; i < joints_.size(); ++i) {
    Joint& j = *joints_[i];
    const JointDef& def = j.def();
    if (!j.enabled() || !(def.break_force || def.break_torque)) continue;
    const JointReaction r = impl_->step.joint_loads.of(i);
    if (r.force.norm() > def.break_force.value_or(kInfinity) ||
        r.torque.norm() > def.break_torque.value_or(kInfinity)) {
      j.setEnabled(false);
      const int slot = static_cast<int>(i);
      breaks_.push_back(
          JointBreak{JointId{slot, impl_->joint_slots.generation(slot)}, steps_, time_, r});
    }
  }
}

LoadId World::addLoad(const LoadDef& def) {
  if (!contains(def.body)) throw std::invalid_argument("body: must be a body of this world");
  return impl_->loads.add(def, bodies_);
}

void World::removeLoad(LoadId id) {
  impl_->loads.remove(id);
}

int World::loadCount() const {
  return impl_->loads.count();
}

void World::setForceCallback(std::function<void(World&)> callback) {
  impl_->force_callback = std::move(callback);
}

bool World::isAsleep(BodyId id) const {
  body(id);  // checks the id
  return impl_->step.sleep.asleep(id.index);
}

void World::wake(BodyId id) {
  body(id);
  step::wakeWithNeighbours(bodies_, impl_->step, id.index);
}

std::span<const Contact> World::contacts() const {
  return impl_->step.contact.contacts();
}

ActuatorId World::createActuator(const ActuatorDef& def) {
  return impl_->actuators.add(def, *this);
}
int World::actuatorCount() const {
  return impl_->actuators.count();
}
const ActuatorDef& World::actuator(ActuatorId id) const {
  return impl_->actuators.def(id);
}
std::optional<ActuatorId> World::findActuator(std::string_view name) const {
  return impl_->actuators.find(name);
}
std::span<double> World::controls() {
  return impl_->actuators.controls();
}
std::span<const double> World::controls() const {
  return std::as_const(*impl_).actuators.controls();
}
void World::setControl(ActuatorId id, double value) {
  impl_->actuators.setControl(id, value);
}
double World::actuatorForce(ActuatorId id) const {
  return impl_->actuators.force(id, *this);
}

JointCoordinates World::jointCoordinates(JointId id) const {
  const Joint& j = joint(id);
  JointCoordinates q = j.coordinates(bodyState(j.body1()), bodyState(j.body2()));
  const int free = j.freeCoordinates();
  for (int i = 0; i < free && i < q.size(); ++i)
    q[i] += j.def().coordinates[static_cast<std::size_t>(i)].reference;
  return q;
}

JointCoordinates World::jointRates(JointId id) const {
  const Joint& j = joint(id);
  constexpr double kDt = 1e-6;  // (s) round-off ~1e-16 / kDt, truncation ~kDt^2 x''' / 6
  const auto moved = [](BodyState s, double dt) {
    s.pose.position += s.v * dt;
    s.pose.orientation = math::integrate(s.pose.orientation, s.w, dt);
    return s;
  };
  const BodyState b1 = bodyState(j.body1()), b2 = bodyState(j.body2());
  const JointCoordinates ahead = j.coordinates(moved(b1, kDt), moved(b2, kDt));
  const JointCoordinates behind = j.coordinates(moved(b1, -kDt), moved(b2, -kDt));
  return (ahead - behind) / (2.0 * kDt);
}

JointReaction World::jointReaction(JointId id) const {
  joint(id);  // checks the id
  return impl_->step.joint_loads.of(static_cast<std::size_t>(id.index));
}

void World::setJointCoordinate(JointId id, int coordinate, double value) {
  const Joint& j = joint(id);
  const double reference = coordinate >= 0 && coordinate < kMaxCoordinates
                               ? j.def().coordinates[static_cast<std::size_t>(coordinate)].reference
                               : 0.0;
  if (!std::isfinite(value)) throw std::invalid_argument("initial: must be finite");
  moveToCoordinate(bodies_, joints_, static_cast<std::size_t>(id.index), coordinate,
                   value - reference);
  for (const BodyId b : {j.body1(), j.body2()})
    if (!b.isWorld()) wake(b);
}

double World::jointError(JointId id) const {
  const Joint& j = joint(id);
  if (!j.enabled()) return 0.0;
  const std::array<BodyId, 2> more = j.coupledBodies();
  return j.error(bodyState(j.body1()), bodyState(j.body2()),
                 {bodyState(more[0]), bodyState(more[1])});
}

double World::maxJointError() const {
  double e = 0.0;
  for (const JointId j : jointIds()) e = std::max(e, jointError(j));
  return e;
}

Energy World::energy() const {
  return dynamics::computeEnergy(bodies_, settings_.gravity);
}

}  // namespace linx
