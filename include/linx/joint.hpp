// The joint interface: every joint type is one class behind it, in its own file (src/joints/).
// Nothing else in the engine knows the concrete types. A joint says how many rows it may need
// this step, fills them from the two bodies' current state, and reads out its coordinate and
// its position error.
#pragma once

#include <linx/body.hpp>
#include <linx/row.hpp>
#include <linx/signal.hpp>
#include <linx/types.hpp>

#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace linx {

namespace state {
class Archive;
}

/// A joint of a World: its slot and the slot's generation (as BodyId).
struct JointId {
  int index = -1;
  std::uint32_t generation = 0;
  friend bool operator==(JointId, JointId) = default;
};

/// Unilateral limits on a joint coordinate (m for sliders, rad for hinges).
struct JointLimits {
  double lower = -kInfinity;
  double upper = kInfinity;
};

/// The swing cone of a cone-twist joint: how far body 1's twist axis may tilt from body 2's, as the
/// half-angles (rad, in (0, pi)) of an elliptical cone: towards `axis2` and towards axis x axis2.
struct ConeLimit {
  double swing1 = 0.0;
  double swing2 = 0.0;
};

/// A drive on a joint coordinate x (m for sliders, rad for hinges), acting with a force (N) or
/// torque (N m) of at most max_force (docs/joints.md):
/// - a velocity motor (the default): holds the rate x' at target_velocity;
/// - a position servo (target_position given): F = stiffness (target_position - x)
///   + damping (target_velocity - x'), a PD controller;
/// - a damped velocity motor (damping > 0, no target_position): F = damping (target_velocity - x').
/// Servos are integrated implicitly: stable at any gain.
/// Targets may change in time (Signal); a servo's damping then aims at target_velocity plus the
/// position table's own rate, so it follows a moving target without lag.
struct JointMotor {
  Signal target_velocity = 0.0;                          ///< (m/s or rad/s)
  double max_force = kInfinity;                          ///< (N or N m), >= 0; infinite: no bound
  std::optional<Signal> target_position = std::nullopt;  ///< (m or rad): makes it a servo
  double stiffness = 0.0;  ///< servo gain (N/m or N m/rad), >= 0; needs target_position
  double damping = 0.0;    ///< (N s/m or N m s/rad), >= 0

  /// A velocity motor holds its rate rigidly; a servo or damped motor acts as a spring-damper.
  bool isServo() const { return target_position.has_value() || damping > 0.0; }
  friend bool operator==(const JointMotor&, const JointMotor&) = default;
};

/// A spring and damper on a joint coordinate x: F = -stiffness (x - rest) - damping x'. Both terms
/// are integrated implicitly where the stiffness needs it and without numerical damping where it
/// does not (docs/joints.md): an undamped spring keeps its amplitude.
struct JointSpring {
  double stiffness = 0.0;  ///< (N/m or N m/rad), >= 0
  double damping = 0.0;    ///< (N s/m or N m s/rad), >= 0
  double rest = 0.0;       ///< coordinate at which the spring is relaxed (m or rad)
};

/// What acts on one free coordinate of a joint (a hinge's angle, a slider's position, each of a
/// universal joint's two angles): limits, a drive, a spring, and dry friction. Units are the
/// coordinate's: m and N for a linear one, rad and N m for an angle.
struct CoordinateDef {
  std::optional<JointLimits> limits = std::nullopt;
  std::optional<JointMotor> motor = std::nullopt;
  std::optional<JointSpring> spring = std::nullopt;
  /// (N or N m), >= 0: a force of at most this much holds the coordinate's rate at zero (Coulomb
  /// friction in the joint, a bounded row).
  double friction = 0.0;
  /// Held at its value at creation (an equality row): a generic joint's locked axis. A locked
  /// coordinate takes nothing else.
  bool locked = false;
  /// Prescribed motion: the coordinate follows this signal (m or rad, from its zero at creation)
  /// exactly, by whatever force it takes (an equality row: each step ends on the signal's value).
  /// A prescribed coordinate takes nothing else; with a table, it starts on the first value.
  std::optional<Signal> prescribed = std::nullopt;
  /// The coordinate's value where the bodies are when the joint is made (m or rad): the model is
  /// built at this value, and the coordinate, its limits, targets, spring rest and prescribed
  /// table all count from the zero it implies (MJCF's `ref`). 0: the creation pose is the zero.
  double reference = 0.0;
  /// Where the coordinate starts (m or rad, with the reference): the scene builder (or
  /// World::setJointCoordinate) moves body1's side of the mechanism there once every joint is
  /// made, so that a model built straight starts bent. None: where it was built.
  std::optional<double> initial = std::nullopt;
  /// (kg m^2 for an angle, kg for a linear coordinate), >= 0: the inertia of a rotor geared to
  /// the coordinate (a motor's armature, MJCF's `armature`): it adds armature x'^2 / 2 to the
  /// kinetic energy, so the coordinate accelerates as if this much inertia were added along it.
  /// Integrated implicitly (docs/joints.md).
  double armature = 0.0;
  /// A force (N) or torque (N m) applied along the coordinate, constant or in time: an actuator's
  /// effort (MJCF's `motor`), set between steps with Joint::setForce. None: no force.
  std::optional<Signal> force = std::nullopt;

  bool empty() const {
    return !limits && !motor && !spring && friction == 0.0 && !locked && !prescribed &&
           armature == 0.0 && !force;
  }
};

/// The most free coordinates a joint type has (a generic joint's six).
inline constexpr int kMaxCoordinates = 6;

/// One hinge or slide of a serial joint (JointDef::axes), world frame at creation.
struct SerialAxis {
  bool linear = false;         ///< a slide along `axis` (else a hinge about it)
  Vec3 axis = Vec3::UnitZ();   ///< non-zero direction
  Vec3 anchor = Vec3::Zero();  ///< a point on a hinge's axis (m); a slide does not use it
};

/// Plain definition of a joint. Points and directions in the world frame at creation, or with
/// `local` in the bodies' frames. Not every type uses every field: a ball joint has no axis, a
/// fixed joint neither axis nor coordinates.
struct JointDef {
  std::string name;
  BodyId body1 = kWorldBody;  ///< must be a body
  BodyId body2 = kWorldBody;  ///< kWorldBody fixes body1 to the world
  /// The joint attached to each body by a local frame: `anchor`, `axis` and `axes` are given in
  /// body 1's frame (its centre of mass and axes), `anchor2` and `axis2` in body 2's (the world's
  /// for the world), instead of all in the world frame at creation. The joint is made from them
  /// at the bodies' poses at creation (Joint::def() then holds the world-frame form).
  bool local = false;
  /// A point on the joint (m), world frame at creation; default: body1's centre of mass.
  std::optional<Vec3> anchor = std::nullopt;
  Vec3 axis = Vec3::UnitZ();  ///< hinge rotation axis / slider direction, world frame
  /// Universal joint: `axis` turns with body 1 and `axis2` with body 2, perpendicular at creation.
  Vec3 axis2 = Vec3::UnitY();
  /// Gear joint: body 2 turns about `axis2` at `ratio` times body 1's rate about `axis` (its sign
  /// gives the sense: -2 for a meshing wheel of half the teeth on a parallel axle).
  double ratio = 1.0;
  /// Cone-twist joint: the cone its twist axis swings in (none: it swings freely).
  std::optional<ConeLimit> cone = std::nullopt;
  /// Distance joint: the point on body 2 (m), world frame at creation; default: body 2's centre
  /// of mass (`anchor` is the point on body 1).
  std::optional<Vec3> anchor2 = std::nullopt;
  /// Distance joint: the distance kept between the two points (m), > 0; default: theirs at
  /// creation.
  std::optional<double> length = std::nullopt;
  /// Distance joint: a rope, which only keeps the points within `length` (else a rod, at it).
  bool rope = false;
  /// Serial joint: its hinges and slides (1 to 6, independent), in order from body 2 to body 1:
  /// body 1 moves on axes[k-1], which moves on axes[k-2], ..., on axes[0], fixed in body 2, as a
  /// body with several joints in MJCF. Coordinate i is axes[i]'s angle or position.
  std::vector<SerialAxis> axes = {};
  /// Mimic joint: the two joints whose coordinates it ties (URDF's <mimic>), each's first free
  /// coordinate (a hinge's angle, a slider's position, with its reference):
  ///   follower = ratio leader + offset.
  /// Its bodies are the follower's (World::createJoint sets body1 and body2).
  std::optional<JointId> leader = std::nullopt;
  std::optional<JointId> follower = std::nullopt;
  double offset = 0.0;  ///< (m or rad) mimic joint: see `leader`
  /// Limits, drives, springs and friction of the type's free coordinates, in the order of
  /// JointTypeInfo::coordinates (a hinge's angle is coordinates[0]); the rest stay empty.
  std::array<CoordinateDef, kMaxCoordinates> coordinates = {};
  /// Breakable joint: it breaks (World::jointBreaks, then acts no more) at the end of the first
  /// step over which the force it applied (N) exceeded `break_force`, or its torque about the
  /// anchor (N m) `break_torque` (World::jointReaction). Both > 0; none: it never breaks.
  std::optional<double> break_force = std::nullopt;
  std::optional<double> break_torque = std::nullopt;
  std::optional<double> erp = std::nullopt;  ///< overrides the world's error reduction
  std::optional<double> cfm = std::nullopt;  ///< overrides the world's constraint force mixing
  bool collide = false;  ///< the two joined bodies' shapes still collide with each other
};

/// A joint's force (N) and torque (N m) on a body, world frame (World::jointReaction).
struct JointReaction {
  Vec3 force = Vec3::Zero();
  Vec3 torque = Vec3::Zero();
};

/// State of one of a joint's two bodies (the world frame: identity pose, zero velocity).
struct BodyState {
  Pose pose;
  Vec3 v = Vec3::Zero();
  Vec3 w = Vec3::Zero();
};

/// Inverse mass and world-frame inverse inertia of one of a joint's two bodies (zero: the world,
/// a static body).
struct BodyInertia {
  double inv_mass = 0.0;
  Mat3 inv_inertia = Mat3::Zero();
};

/// What a joint needs to fill its rows.
struct JointContext {
  BodyState b1, b2;
  double h = 0.0;    ///< step length (s)
  double erp = 0.2;  ///< effective error reduction for this joint
  double cfm = 0.0;  ///< effective constraint force mixing for this joint
  /// The bodies' inertia, for drives and springs (their implicit share depends on it).
  BodyInertia m1 = {}, m2 = {};
  /// (s) the time at the step's start: a position target is taken there (with the coordinate), a
  /// velocity target at its end (time + h), where the rate is.
  double time = 0.0;
  /// The bodies' velocities at the (sub)step's start, before gravity and applied forces moved
  /// them: armature keeps the rotor's rate from there (its poses are b1's and b2's). Assembly
  /// sets them; none: the same as b1's and b2's.
  std::optional<std::pair<BodyState, BodyState>> start = std::nullopt;
  /// The states of Joint::coupledBodies() (a mimic joint's leader's two bodies).
  std::array<BodyState, 2> more = {};
};

/// A joint's coordinate values (at most kMaxCoordinates, no allocation).
using JointCoordinates = Eigen::Matrix<double, Eigen::Dynamic, 1, 0, kMaxCoordinates, 1>;

class Joint {
 public:
  explicit Joint(const JointDef& def) : def_(def) {}
  virtual ~Joint() = default;
  Joint(const Joint&) = delete;
  Joint& operator=(const Joint&) = delete;

  /// "fixed", "slider", "hinge", "ball", ...
  virtual std::string_view type() const = 0;
  /// The most rows fill() may write this step (count stage of assembly).
  virtual int maxRows() const = 0;
  /// Fills rows[0..n) and returns n. Rows arrive with erp/cfm set from the context; bodies and
  /// keys are set by assembly. Row slots are stable: slot i always means the same constraint.
  virtual int fill(const JointContext& ctx, std::span<Row> rows) const = 0;
  /// The joint's coordinates, zero at creation, in the order of JointTypeInfo::coordinates:
  /// hinge angle (rad, continuous: it counts turns), slider position (m), a universal joint's two
  /// angles, ball-joint relative rotation angle (rad, >= 0); none for a fixed joint.
  virtual JointCoordinates coordinates(const BodyState& b1, const BodyState& b2) const = 0;
  /// Called by the world after every (sub)step with the new state, for joints that follow history
  /// (a hinge counts its turns). Motion between two calls must stay below half a turn.
  virtual void track(const BodyState& /*b1*/, const BodyState& /*b2*/) {}
  /// Largest position error of the joint's equality rows, and of a violated limit (m or rad);
  /// `more`: the states of coupledBodies().
  double error(const BodyState& b1, const BodyState& b2,
               const std::array<BodyState, 2>& more = {}) const;
  /// Bodies beyond body1 and body2 that the joint's rows act on as well (a mimic joint: its
  /// leader's two; the world for none), whose states come in JointContext::more.
  virtual std::array<BodyId, 2> coupledBodies() const { return {kWorldBody, kWorldBody}; }
  /// Fills `row` with free coordinate `index`'s J (the coordinate's rate is J u) and phi (its
  /// value from the joint's zero, without its reference), as the coordinate's limits and drives
  /// take them; false for a type without such a row. A mimic joint ties joints through it.
  virtual bool coordinateRow(const JointContext& /*ctx*/, int /*index*/, Row& /*row*/) const {
    return false;
  }
  /// The turning of the joint's forces, K = d(J^T lambda)/dq: how the generalized force of the
  /// impulses `lambda` on the rows fill() wrote at ctx (`rows`) changes as the bodies move.
  /// q = (body1 position, rotation, body2 position, rotation), rotations as small rotation vectors
  /// about the world axes; a row of K per entry of J^T lambda in the same order. The geometric
  /// stiffness of the velocity solve is made of it (docs/solver.md). The default differentiates
  /// fill() numerically; joint types with a closed form override it.
  virtual Mat12 stiffness(const JointContext& ctx, std::span<const Row> rows,
                          std::span<const double> lambda) const;
  /// The curvature (dJ/dt) u of each of the rows fill() wrote at ctx (`rows`), into `out`: how
  /// fast J u changes at fixed velocities u (ctx's) as J turns and moves with the bodies. The
  /// accurate integrator's equations need it (J a = -(dJ/dt) u). NaN for a row without a closed
  /// form here (the default: every row), which the integrator then measures by differences.
  virtual void curvature(const JointContext& ctx, std::span<const Row> rows,
                         std::span<double> out) const;

  /// The anchor in body1's frame: where the joint's reaction torque is taken.
  const Vec3& anchor1() const { return anchor1_; }
  const std::string& name() const { return def_.name; }
  BodyId body1() const { return def_.body1; }
  BodyId body2() const { return def_.body2; }
  const JointDef& def() const { return def_; }
  /// How many free coordinates the joint has (JointTypeInfo::freeCoordinates of its definition).
  int freeCoordinates() const;
  /// Set or remove the motor, limits, spring or friction of free coordinate `coordinate` (the
  /// order of JointTypeInfo::coordinates); throws std::invalid_argument as makeJoint does.
  void setMotor(std::optional<JointMotor> motor, int coordinate = 0);
  void setLimits(std::optional<JointLimits> limits, int coordinate = 0);
  void setSpring(std::optional<JointSpring> spring, int coordinate = 0);
  void setFriction(double friction, int coordinate = 0);
  void setForce(std::optional<Signal> force, int coordinate = 0);
  /// A disabled joint (broken, or switched off) has no rows and no longer keeps its two bodies'
  /// shapes from colliding; its coordinates are still reported. Enabling it again pulls the
  /// bodies back together (a sleeping island notices at World::wake).
  bool enabled() const { return enabled_; }
  void setEnabled(bool enabled) { enabled_ = enabled; }
  /// Reads or writes what the joint carries from step to step (World::saveState): whether it is
  /// enabled, and what track() follows.
  void persist(state::Archive& archive);

 protected:
  /// What track() follows (the branch a hinge's angle unwraps onto); nothing by default.
  virtual void persistTracked(state::Archive& /*archive*/) {}

 private:
  friend std::unique_ptr<Joint> makeJoint(std::string_view type, const JointDef& def,
                                          const BodyState& b1, const BodyState& b2,
                                          std::array<const Joint*, 2> coupled);
  JointDef def_;
  Vec3 anchor1_ = Vec3::Zero();
  bool enabled_ = true;
};

/// Creates a joint of a registered type ("fixed", "slider", "hinge", "ball", "universal", ...)
/// from its definition and the two bodies' states at creation; `coupled`: the joints a type that
/// couples joints ties (a mimic joint's leader and follower, JointTypeInfo::couplesJoints).
/// Throws std::invalid_argument for an unknown type or a definition the type cannot accept (a
/// zero axis, inverted limits, a negative motor force).
std::unique_ptr<Joint> makeJoint(std::string_view type, const JointDef& def, const BodyState& b1,
                                 const BodyState& b2,
                                 std::array<const Joint*, 2> coupled = {nullptr, nullptr});
/// One coordinate a joint type reports.
struct CoordinateInfo {
  std::string_view name;  ///< "angle", "position", "angle1", ... (scene files use it)
  bool linear = false;    ///< m (else rad)
  /// Takes a CoordinateDef (limits, motor, spring, friction); a cone-twist joint's swing does not.
  bool free = true;
  /// Takes limits only, and only an upper one: an angle >= 0 that is not smooth at zero (a ball
  /// joint's rotation angle, which its limit keeps within a cone about its start).
  bool limits_only = false;
};

/// A joint's own fields, beyond the common ones (name, bodies, frame, erp, cfm, collide, breaking)
/// and its coordinates': each type takes some of them (JointTypeInfo::fields), named in a scene
/// file as below (docs/scene-format.md, "joints").
enum class JointField : std::uint8_t {
  Anchor,    ///< "anchor": JointDef::anchor, the joint's point
  Anchor1,   ///< "anchor1": JointDef::anchor, body 1's point of a joint between two points
  Anchor2,   ///< "anchor2": JointDef::anchor2, body 2's point
  Axis,      ///< "axis": JointDef::axis
  Axis1,     ///< "axis1": JointDef::axis, the first of a frame's axes or of two axles
  Axis2,     ///< "axis2": JointDef::axis2; perpendicular to axis1 unless the type has a ratio
  Length,    ///< "length": JointDef::length
  Rope,      ///< "rope": JointDef::rope
  Cone,      ///< "cone": JointDef::cone
  Ratio,     ///< "ratio": JointDef::ratio
  Axes,      ///< "axes": JointDef::axes, a serial joint's, each with its coordinate
  Leader,    ///< "leader": JointDef::leader, a joint that ties two joints
  Follower,  ///< "follower": JointDef::follower
  Offset,    ///< "offset": JointDef::offset
};

/// The scene file's name of a joint field ("anchor", "axis1", ...).
std::string_view jointFieldName(JointField field);

/// A field a type takes, and whether it must be given.
struct TypeField {
  JointField field;
  bool required = false;
};

/// What a registered joint type uses of a JointDef.
struct JointTypeInfo {
  std::string_view name;
  /// Its own fields, in the order scene files and the docs list them.
  std::span<const TypeField> fields = {};
  /// The coordinates Joint::coordinates reports, in order.
  std::span<const CoordinateInfo> coordinates = {};

  /// Whether the type takes `field`, and whether it needs it.
  bool uses(JointField field) const;
  bool needs(JointField field) const;
  /// JointDef::axis (as "axis" or "axis1") and JointDef::axis2.
  bool usesAxis() const { return uses(JointField::Axis) || uses(JointField::Axis1); }
  bool usesAxis2() const { return uses(JointField::Axis2); }
  /// A joint between two points (distance, spring): JointDef::anchor and anchor2.
  bool usesAnchor2() const { return uses(JointField::Anchor2); }
  /// JointDef::axes (a serial joint): its free coordinates are one per axis.
  bool usesAxes() const { return uses(JointField::Axes); }
  /// It ties two joints' coordinates (a mimic joint), its bodies the follower's.
  bool couplesJoints() const { return uses(JointField::Leader); }
  /// How many of its coordinates are free (take limits, drives, springs, friction): the first.
  int freeCoordinates() const;
  /// The same for a joint of this type defined by `def` (a serial joint's: one per axis).
  int freeCoordinates(const JointDef& def) const;
};

/// The registered joint types, in registration order.
std::span<const JointTypeInfo> jointTypes();
/// The registered type called `type`, or nullptr.
const JointTypeInfo* findJointType(std::string_view type);
/// Whether `type` names a registered joint type.
bool isJointType(std::string_view type);

}  // namespace linx
