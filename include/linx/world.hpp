// The world: bodies, joints and the time step. See docs/architecture.md for the stages of a step.
#pragma once

#include <linx/actuator.hpp>
#include <linx/body.hpp>
#include <linx/contact.hpp>
#include <linx/integrator.hpp>
#include <linx/joint.hpp>
#include <linx/joint_defs.hpp>
#include <linx/loads.hpp>
#include <linx/solver.hpp>
#include <linx/types.hpp>

#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace linx {

namespace state {
class Archive;
}

/// A fault found by World::step() that makes its results meaningless: the run must stop. The
/// world keeps the state in which the fault was found.
class StepFault : public std::runtime_error {
 public:
  StepFault(const std::string& what, int body, std::int64_t step, double time)
      : std::runtime_error(what), body_(body), step_(step), time_(time) {}
  int body() const { return body_; }  ///< index of the body at fault, -1 for a joint's rows
  std::int64_t step() const { return step_; }
  double time() const { return time_; }

 private:
  int body_;
  std::int64_t step_;
  double time_;
};

/// A body's state, or a joint's rows, stopped being finite. what() reads "bodies[i] (NAME):
/// position is not finite after step N (t = T s)", or names the joint.
class NonFiniteState : public StepFault {
 public:
  using StepFault::StepFault;
};

/// A body moved faster than FaultSettings::max_speed or turned faster than max_angular_speed, or a
/// joint's error passed max_joint_error: what() names it, its value, the bound, the step and the
/// time. joint() is the joint's index, -1 for a body.
class BoundExceeded : public StepFault {
 public:
  BoundExceeded(const std::string& what, int body, int joint, std::int64_t step, double time)
      : StepFault(what, body, step, time), joint_(joint) {}
  int joint() const { return joint_; }

 private:
  int joint_;
};

/// The steps produced more energy than FaultSettings allows while nothing drove the world: the
/// solve is unstable and the motion is not physics. what() names the step, the time and the body
/// with the most kinetic energy.
class EnergyGrowth : public StepFault {
 public:
  EnergyGrowth(const std::string& what, int body, std::int64_t step, double time, double produced,
               double bound)
      : StepFault(what, body, step, time), produced_(produced), bound_(bound) {}
  double produced() const { return produced_; }  ///< (J) energy the steps produced
  double bound() const { return bound_; }        ///< (J) what was allowed

 private:
  double produced_, bound_;
};

/// When World::step() stops a run (docs/solver.md, "Faults"). A non-finite state always does.
/// The energy check sums, over the steps in which nothing drives the world (no applied force or
/// torque, no motor), the change of total energy (kinetic + gravitational) that each step makes,
/// and takes its rise above its lowest value so far: energy an undriven step makes is the solver's
/// doing. The run stops when that rise exceeds
///   kinetic_fraction * (the largest kinetic energy seen) + sum m (|g| height + speed^2 / 2)
/// (sums over the movable bodies),
/// the second term allowing position correction to lift every body by `height` or push it to
/// `speed`. Changes made between steps (a new velocity, a moved body) are not counted.
///
/// The bounds: a body faster than max_speed (m/s) or max_angular_speed (rad/s), checked after
/// every step, or a joint whose error (World::jointError) is above max_joint_error (m or rad),
/// checked every joint_error_every steps (it costs a joint's rows again: 2 to 7 % of a mechanism's
/// step if done every step), stops the run (BoundExceeded). Infinity turns a bound off.
///
/// With `stop` false, a fault other than a non-finite state does not throw: it is kept in
/// World::faults() and the world steps on (`linx run --on-fault continue`).
struct FaultSettings {
  bool energy = true;              ///< check the energy at all
  double kinetic_fraction = 0.5;   ///< >= 0
  double height = 0.1;             ///< (m) >= 0
  double speed = 3.0;              ///< (m/s) >= 0; the contacts' max_push_out by default
  double max_speed = 1e4;          ///< (m/s) > 0
  double max_angular_speed = 1e5;  ///< (rad/s) > 0
  double max_joint_error = 1.0;    ///< (m or rad) > 0
  int joint_error_every = 10;      ///< (steps) >= 1
  bool stop = true;                ///< false: keep going, the faults kept in World::faults()
};

/// The most worker threads a world accepts (WorldSettings::threads, a scene's `threads`,
/// `linx run --threads`).
inline constexpr int kMaxThreads = 1024;

struct WorldSettings {
  Vec3 gravity = Vec3(0.0, 0.0, -9.81);  ///< (m/s^2), world frame
  double timestep = 1e-3;                ///< (s)
  SolverSettings solver{};
  /// The time integrator of islands without contacts (docs/integrators.md).
  IntegratorSettings integrator{};
  ContactSettings contact{};
  SleepSettings sleep{};
  FaultSettings faults{};
  /// Worker threads of a step (collision, per-body stages and the PGS sweep of large islands):
  /// 0 for one per hardware thread. Results are the same to the bit for any count. One by
  /// default, as in the peers: programs that run several worlds at once keep their cores.
  int threads = 1;  ///< in [0, kMaxThreads]
};

/// A joint that broke: what it applied over the step it broke in was more than its break_force or
/// break_torque (JointDef). From then on it is disabled (Joint::enabled).
struct JointBreak {
  JointId joint;
  std::int64_t step = 0;   ///< the step it broke in (1: the first step)
  double time = 0.0;       ///< (s) at the end of that step
  JointReaction reaction;  ///< what it applied to its body1 over that step (World::jointReaction)
};

/// A world's state between two steps (World::saveState): everything that carries from one step to
/// the next, in a binary form tied to this build's byte order and to the world's structure (its
/// bodies, joints and loads), not to the world object. docs/reliability.md lists what it holds.
struct WorldState {
  std::vector<std::byte> bytes;
};

/// Energies of the whole world (J). Potential energy is gravitational, zero at the origin.
struct Energy {
  double kinetic = 0.0;
  double potential = 0.0;
  double total() const { return kinetic + potential; }
};

class World {
 public:
  explicit World(const WorldSettings& settings = {});
  ~World();
  World(World&&) noexcept;
  World& operator=(World&&) noexcept;

  WorldSettings& settings() { return settings_; }
  const WorldSettings& settings() const { return settings_; }

  /// Throws std::invalid_argument for a non-positive mass or inertia on a dynamic body, a
  /// non-finite number, or a duplicate name. Between steps as well as before the first.
  BodyId createBody(const BodyDef& def);
  /// Creates a joint of a registered type at the bodies' current poses; throws
  /// std::invalid_argument for a bad definition or unknown bodies.
  JointId createJoint(std::string_view type, const JointDef& def);
  /// The same from a definition of its own type (linx/joint_defs.hpp): HingeDef, UniversalDef, ...
  template <TypedJointDef T>
  JointId createJoint(const T& def) {
    return createJoint(T::kType, toJointDef(def));
  }
  /// Removes a body between steps with all that holds it: its joints (as removeJoint), its
  /// standing loads and its path. The bodies it touched in the last step wake (they may have lost
  /// their support). Its id, and its joints', refer to nothing from then on (contains() is false,
  /// body() throws); a later createBody may take its slot, under a new generation. contacts()
  /// keeps naming it until the next step. Throws std::out_of_range for an id that is not one of
  /// this world's bodies.
  void removeBody(BodyId id);
  /// Removes a joint between steps; its two bodies wake. Its id refers to nothing from then on;
  /// a later createJoint may take its slot. Throws std::out_of_range for an unknown id.
  void removeJoint(JointId id);
  /// Whether the id is one of this world's bodies (not removed); false for the world frame.
  bool contains(BodyId id) const;
  bool contains(JointId id) const;
  /// The world's bodies and joints, in slot order.
  std::vector<BodyId> bodyIds() const;
  std::vector<JointId> jointIds() const;

  /// Adds a standing load: a force (at a point) and a torque on a body at every step, constant or
  /// given in time (their values at each step's start). Throws std::invalid_argument for a static
  /// or unknown body or a bad table.
  LoadId addLoad(const LoadDef& def);
  /// Removes a standing load between steps (removeBody removes its body's). Throws
  /// std::out_of_range for an id that is not a load in effect.
  void removeLoad(LoadId id);
  int loadCount() const;  ///< the loads in effect
  /// Called at the start of every step, before the standing loads and the step itself, with the
  /// world at the step's start (time()): it applies forces and torques with Body::applyForce,
  /// applyForceAtPoint and applyTorque, or changes drives' targets (a controller). It must not
  /// step the world. An empty function removes it.
  void setForceCallback(std::function<void(World&)> callback);

  /// Adds an actuator on a joint's coordinate (linx/actuator.hpp), at its control. Throws
  /// std::invalid_argument for an empty or repeated name, an unknown joint or coordinate, a
  /// coordinate with a motor or force of its own or a second servo, terms that push away at some
  /// control, a range whose lower end is above its upper, or a number that is not finite.
  ActuatorId createActuator(const ActuatorDef& def);
  int actuatorCount() const;
  /// Throws std::out_of_range for an id that is not one of this world's actuators.
  const ActuatorDef& actuator(ActuatorId id) const;
  std::optional<ActuatorId> findActuator(std::string_view name) const;
  /// The controls, one per actuator in the order of creation, as given (clamped to each
  /// control_range where used): writable between steps, MuJoCo's data.ctrl. An actuator whose
  /// control is a table in time takes the table's value at each step's start instead. Not part of
  /// saveState(): an input, like a motor's target.
  std::span<double> controls();
  std::span<const double> controls() const;
  /// Sets one actuator's control to `value` from now on (ending its table, if it had one). Throws
  /// std::invalid_argument for a value that is not finite.
  void setControl(ActuatorId id, double value);
  /// The actuator's force F along its length (N or N m; its coordinate feels gear F) at the
  /// bodies' current state and its control, within its force_range: what MuJoCo's actuator_force
  /// holds after mj_forward. 0 once its joint is removed.
  double actuatorForce(ActuatorId id) const;

  /// The number of body (joint) slots: ids run from index 0 to bodyCount() - 1. Until something
  /// is removed, every slot holds a body (BodyId{i} is the i-th created); after, some may be
  /// empty (contains(), bodyIds()).
  int bodyCount() const { return static_cast<int>(bodies_.size()); }
  int jointCount() const { return static_cast<int>(joints_.size()); }
  /// Throws std::out_of_range for an id that is not one of this world's (contains()).
  Body& body(BodyId id);
  const Body& body(BodyId id) const;
  Joint& joint(JointId id);
  const Joint& joint(JointId id) const;
  std::optional<BodyId> findBody(std::string_view name) const;
  std::optional<JointId> findJoint(std::string_view name) const;

  /// Whether the body sleeps: its island has been at rest for settings().sleep.time seconds.
  /// A sleeping body is not integrated until a body of its island moves again. Giving it a
  /// velocity or a load wakes it; after moving it with setPose, call wake().
  bool isAsleep(BodyId id) const;
  /// Wakes the body (and, at the next step, its island) and the bodies it touched in the last step.
  /// For a static body (after moving it with setPose) only the bodies it touched.
  void wake(BodyId id);

  /// The contact points of the last step, with their impulses.
  std::span<const Contact> contacts() const;

  /// The whole state between steps: bodies' poses, velocities and sleep, the step counter and
  /// clock, joints' tracked turns and enabled flags, warm-start impulses, contact caches, the
  /// solvers' carried impulses and the fault check's sums. restoreState() on this world or on
  /// another built the same way (same bodies, joints and loads, in the same order) continues
  /// exactly as this one would: bit-identical steps.
  WorldState saveState() const;
  /// Puts the world in a state saveState() returned. Throws std::invalid_argument when the state
  /// is of a world with other bodies, joints or loads, or is damaged; the world is then unchanged.
  void restoreState(const WorldState& state);

  /// Advances by settings().timestep. Throws NonFiniteState when the state stops being finite,
  /// EnergyGrowth when undriven steps make energy beyond settings().faults.
  void step();
  double time() const { return time_; }
  std::int64_t stepCount() const { return steps_; }
  const SolverReport& lastReport() const { return report_; }
  /// What the accurate integrator did over the last step (all zero with integrator "step", or
  /// when every island took the step: a contact, armature, a prescribed coordinate).
  const IntegratorReport& lastIntegratorReport() const;

  /// The joint's coordinates (hinge angle in rad, slider position in m, ...: Joint::coordinates),
  /// zero at creation.
  JointCoordinates jointCoordinates(JointId id) const;
  /// The rates of the joint's coordinates (m/s or rad/s, in the order of jointCoordinates) at the
  /// bodies' current velocities: the time derivative of the joint's coordinate function along the
  /// bodies' motion, by a central difference over +-1e-6 s (good to ~1e-9 of a rate).
  JointCoordinates jointRates(JointId id) const;
  /// Moves body1's side of the mechanism (body1 and every body joined to it other than through
  /// this joint, rigidly) so that free coordinate `coordinate` of the joint reads `value` (with
  /// its reference) and the joint's other coordinates keep theirs: a model built straight, started
  /// bent (CoordinateDef::initial). Velocities turn with the bodies. Throws std::invalid_argument
  /// if body1's side reaches body2 or the world another way (a closed loop: it cannot move
  /// alone), or the coordinate is not reached (out of the joint's range).
  void setJointCoordinate(JointId id, int coordinate, double value);
  /// The joint's largest position error (m or rad); zero for a disabled joint.
  double jointError(JointId id) const;
  /// What the joint applied to its body1 over the last step (world frame): the force and the
  /// torque about the joint's anchor (where it sits on body1). body2 received the opposite of
  /// both, about the same point. Limits, motors, servos and springs included; zero before the
  /// first step; the soft step's are the mean over its substeps (zero for a sleeping island).
  JointReaction jointReaction(JointId id) const;
  /// The faults passed over with FaultSettings::stop false, in order: the first kKeptFaults
  /// messages; faultCount() counts them all.
  std::span<const std::string> faults() const { return faults_; }
  std::int64_t faultCount() const { return fault_count_; }
  static constexpr std::size_t kKeptFaults = 100;
  /// The joints that broke so far, in the order they broke.
  std::span<const JointBreak> jointBreaks() const { return breaks_; }
  /// Largest error over all joints.
  double maxJointError() const;
  Energy energy() const;
  /// State of a body as a joint sees it (identity for the world frame).
  BodyState bodyState(BodyId id) const;

 private:
  struct Impl;
  /// Reads or writes (state::Archive::loading) the state saveState() holds (world_state.cpp).
  void persist(state::Archive& archive);
  /// Throws BoundExceeded for the first joint whose error is above faults.max_joint_error.
  void checkJointErrors() const;
  /// Disables the joints whose reaction over the last step passed their break thresholds.
  void breakOverloadedJoints();

  WorldSettings settings_;
  std::vector<Body> bodies_;
  std::vector<std::unique_ptr<Joint>> joints_;
  double time_ = 0.0;
  std::int64_t steps_ = 0;
  double clock_origin_ = 0.0, clock_step_ = 0.0;  // time_ = origin + clock_steps_ * clock_step_
  std::int64_t clock_steps_ = 0;
  SolverReport report_;
  std::vector<JointBreak> breaks_;
  std::vector<std::string> faults_;
  std::int64_t fault_count_ = 0;
  std::unique_ptr<Impl> impl_;  // solver state kept across steps (warm start, work buffers)
};

}  // namespace linx
