// Each record of the scene format described once, as the fields of its C++ struct in the file's
// order (docs/scene-format.md). `describe(v, record)` hands every field to the visitor `v` with
// its FieldInfo, and `rules(record)` names what no single field's bounds say; the scene reader,
// the writer, the C++ checks, the docs' tables and Python's linx.schema() are visitors
// (src/schema/visitors.hpp), so a new field is this one line. The style is cereal's and
// Boost.Describe's: one function lists the members, each use walks it.
//
// A visitor takes `field(T& value, const FieldInfo&)` for T in double, int, bool, Signal,
// std::optional<double>, std::optional<Vec3>, std::optional<Signal>, an enum (with
// FieldInfo::choices) and std::optional<R> of a described record R.
#pragma once

#include <linx/contact.hpp>
#include <linx/integrator.hpp>
#include <linx/joint.hpp>
#include <linx/scene.hpp>
#include <linx/schema.hpp>
#include <linx/solver.hpp>
#include <linx/world.hpp>

#include <fmt/format.h>

#include <optional>
#include <string>
#include <string_view>

namespace linx::schema {

/// What a record's rules found wrong: the field (empty: the record) and the problem.
struct Problem {
  std::string field;
  std::string problem;
};

inline constexpr Range kPositive = Range::above(0.0);
inline constexpr Range kNonNegative = Range::atLeast(0.0);
inline constexpr Range kFraction = Range::closed(0.0, 1.0);

inline constexpr std::string_view kSolverTypes[] = {"auto", "exact", "pgs", "soft"};
inline constexpr std::string_view kIntegratorTypes[] = {"step", "accurate", "auto"};

/// The records a field may hold (as `std::optional<R>`): described below.
template <class T>
inline constexpr bool kIsRecord = false;
template <>
inline constexpr bool kIsRecord<JointLimits> = true;
template <>
inline constexpr bool kIsRecord<JointMotor> = true;
template <>
inline constexpr bool kIsRecord<JointSpring> = true;

// --- Settings ------------------------------------------------------------------------------------

template <class V>
void describe(V& v, SolverSettings& s) {
  v.field(s.type, {.name = "type",
                   .doc = "`exact`: sparse factorization with an active set, joints to round-off, "
                          "closed loops included; `pgs`: projected Gauss-Seidel with warm "
                          "starting; `auto`: per island, `exact` without friction (mechanisms) and "
                          "`pgs` with friction (contacts); `soft`: the soft step, substeps of one "
                          "soft sweep each ([solver.md](solver.md#the-soft-step))",
                   .choices = kSolverTypes});
  v.field(s.iterations,
          {.name = "iterations",
           .range = Range::atLeast(1),
           .doc = "PGS sweeps, or active-set iterations of the exact solver, at most"});
  v.field(s.tolerance, {.name = "tolerance",
                        .unit = "m/s",
                        .range = kNonNegative,
                        .doc = "stop when the largest complementarity violation is below"});
  v.field(s.erp, {.name = "erp",
                  .range = kFraction,
                  .doc = "error reduction: the fraction of a joint's position error removed per "
                         "step"});
  v.field(
      s.cfm,
      {.name = "cfm", .range = kNonNegative, .doc = "constraint force mixing (regularization)"});
  v.field(s.warm_start, {.name = "warm_start", .doc = "start from the previous step's impulses"});
  v.field(s.sor, {.name = "sor", .range = Range::open(0.0, 2.0), .doc = "PGS over-relaxation"});
  v.field(s.substeps,
          {.name = "substeps",
           .range = Range::atLeast(1),
           .doc = "each step is split into this many assemble-solve-integrate passes; with "
                  "`soft`, the soft step's substeps"});
  v.field(s.post_stabilization,
          {.name = "post_stabilization",
           .range = Range::atLeast(0),
           .doc = "Newton iterations per step, at most, that remove the joints' position errors "
                  "after the positions move, with the joints' rows aiming at their constraint to "
                  "second order ([solver.md](solver.md#post-stabilization)); `0` turns both off "
                  "(error reduction alone)"});
  v.field(s.projection,
          {.name = "projection",
           .doc = "the older name: at least `projection_iterations` iterations of the "
                  "post-stabilization"});
  v.field(s.projection_iterations, {.name = "projection_iterations",
                                    .range = Range::atLeast(1),
                                    .doc = "iterations with `projection` on"});
  v.field(s.projection_tolerance, {.name = "projection_tolerance",
                                   .unit = "m or rad",
                                   .range = kNonNegative,
                                   .doc = "stop the iterations below this error"});
  v.field(s.geometric_stiffness,
          {.name = "geometric_stiffness",
           .doc = "the joints' geometric stiffness in the velocity solve: heavy bodies on light "
                  "links (1000:1) stay stable at one solve a step "
                  "([solver.md](solver.md#geometric-stiffness))"});
}

template <class V>
void describe(V& v, IntegratorSettings& s) {
  v.field(s.type, {.name = "type",
                   .doc = "`step`: every island by the velocity-level step; `accurate`: islands "
                          "of joints alone move by an error-controlled fifth-order integrator "
                          "([integrators.md](integrators.md)); `auto`: the accurate integrator "
                          "on the frames where one of its steps holds the tolerance, the step on "
                          "the others",
                   .choices = kIntegratorTypes});
  v.field(s.tolerance, {.name = "tolerance",
                        .range = Range::closed(1e-14, 1e-2),
                        .doc = "the accurate integrator's local error bound per step, relative "
                               "to the larger of 1 and each value's size"});
}

inline constexpr std::string_view kStiffnessAliases[] = {"kp", "k", "spring_stiffness"};
inline constexpr std::string_view kDampingAliases[] = {"kd", "c", "kv", "damper"};

template <class V>
void describe(V& v, ContactSettings& c) {
  v.field(c.enabled, {.name = "enabled", .doc = "detect contacts between shapes"});
  v.field(c.margin, {.name = "margin",
                     .unit = "m",
                     .range = kNonNegative,
                     .doc = "speculative distance: closer shapes get contact rows before they "
                            "touch"});
  v.field(c.slop, {.name = "slop",
                   .unit = "m",
                   .range = kNonNegative,
                   .doc = "allowed penetration, left uncorrected"});
  v.field(c.erp, {.name = "erp",
                  .range = kFraction,
                  .doc = "fraction of the penetration beyond the slop removed per step"});
  v.field(c.cfm,
          {.name = "cfm", .range = kNonNegative, .doc = "constraint force mixing of contact rows"});
  v.field(c.stiffness, {.name = "stiffness",
                        .unit = "N/m",
                        .range = kPositive,
                        .doc = "instead of `erp` and `cfm` (not with them): a contact spring; "
                               "with `damping`, both or neither",
                        .aliases = kStiffnessAliases});
  v.field(c.damping, {.name = "damping",
                      .unit = "N s/m",
                      .range = kNonNegative,
                      .doc = "the contact spring's damper, with `stiffness`",
                      .aliases = kDampingAliases});
  v.field(c.restitution_threshold, {.name = "restitution_threshold",
                                    .unit = "m/s",
                                    .range = kNonNegative,
                                    .doc = "approach speeds below this do not bounce"});
  v.field(c.max_push_out, {.name = "max_push_out",
                           .unit = "m/s",
                           .range = kNonNegative,
                           .doc = "penetration is pushed out no faster than this, however deep"});
  v.field(c.hertz, {.name = "hertz",
                    .unit = "Hz",
                    .range = kNonNegative,
                    .doc = "soft step: the contact spring's frequency; 0 takes an eighth of the "
                           "substep rate, the stiffest that stays stable, and a larger value is "
                           "capped there"});
  v.field(c.damping_ratio, {.name = "damping_ratio",
                            .range = kNonNegative,
                            .doc = "soft step: the contact spring's damping ratio"});
}

inline std::optional<Problem> rules(const ContactSettings& c) {
  if (c.stiffness.has_value() != c.damping.has_value())
    return Problem{c.stiffness ? "damping" : "stiffness",
                   "missing required field (stiffness and damping go together)"};
  const ContactSettings d;
  if (c.stiffness && (c.erp != d.erp || c.cfm != d.cfm))
    return Problem{c.erp != d.erp ? "erp" : "cfm",
                   "give either erp and cfm, or stiffness and damping"};
  return std::nullopt;
}

template <class V>
void describe(V& v, SleepSettings& s) {
  v.field(s.enabled, {.name = "enabled", .doc = "let resting islands sleep"});
  v.field(s.linear_velocity, {.name = "linear_velocity",
                              .unit = "m/s",
                              .range = kNonNegative,
                              .doc = "a body rests while its speed is below this"});
  v.field(s.angular_velocity, {.name = "angular_velocity",
                               .unit = "rad/s",
                               .range = kNonNegative,
                               .doc = "... and its angular speed below this"});
  v.field(s.time, {.name = "time",
                   .unit = "s",
                   .range = kNonNegative,
                   .doc = "time at rest before the island sleeps"});
}

template <class V>
void describe(V& v, FaultSettings& s) {
  v.field(s.max_speed, {.name = "max_speed",
                        .unit = "m/s",
                        .range = kPositive,
                        .doc = "a body faster than this stops the run (checked every step)",
                        .infinite = true});
  v.field(s.max_angular_speed, {.name = "max_angular_speed",
                                .unit = "rad/s",
                                .range = kPositive,
                                .doc = "... or turning faster than this",
                                .infinite = true});
  v.field(s.max_joint_error,
          {.name = "max_joint_error",
           .unit = "m or rad",
           .range = kPositive,
           .doc = "a joint whose error (the `error` column of `joints.csv`) is above this stops "
                  "the run",
           .infinite = true});
  v.field(s.joint_error_every, {.name = "joint_error_every",
                                .unit = "steps",
                                .range = Range::atLeast(1),
                                .doc = "how often the joint errors are checked"});
  v.field(s.energy, {.name = "energy", .doc = "check the energy at all"});
  v.field(s.kinetic_fraction,
          {.name = "kinetic_fraction",
           .range = kNonNegative,
           .doc = "the energy bound's part proportional to the largest kinetic energy seen"});
  v.field(s.height, {.name = "height",
                     .unit = "m",
                     .range = kNonNegative,
                     .doc = "the energy bound allows position correction to lift every body this "
                            "far..."});
  v.field(s.speed, {.name = "speed",
                    .unit = "m/s",
                    .range = kNonNegative,
                    .doc = "... or push it to this speed"});
}

template <class V>
void describe(V& v, SceneView& s) {
  v.field(s.eye,
          {.name = "eye", .unit = "m", .doc = "where the camera is", .default_text = "automatic"});
  v.field(s.target, {.name = "target",
                     .unit = "m",
                     .doc = "the point it looks at; must differ from `eye`",
                     .default_text = "automatic"});
  v.field(s.up, {.name = "up",
                 .doc = "the picture's up direction, normalized; must not be parallel to "
                        "`target - eye`",
                 .default_text = "against gravity (`[0, 0, 1]` without gravity)",
                 .direction = true});
  v.field(s.fov, {.name = "fov",
                  .unit = "degrees",
                  .range = Range::open(0.0, 180.0),
                  .doc = "vertical field of view"});
}

inline std::optional<Problem> rules(const SceneView& s) {
  if (s.eye && s.target && (*s.target - *s.eye).norm() <= 1e-12 * (1 + s.eye->norm()))
    return Problem{"target", "must differ from eye"};
  if (s.eye && s.target && s.up &&
      (*s.target - *s.eye).normalized().cross(s.up->normalized()).norm() < 1e-6)
    return Problem{"up", "must not be parallel to target - eye"};
  return std::nullopt;
}

// --- What acts on a joint's coordinate -----------------------------------------------------------

inline constexpr std::string_view kLowerAliases[] = {"min", "low", "minimum", "lo"};
inline constexpr std::string_view kUpperAliases[] = {"max", "high", "maximum", "hi"};

template <class V>
void describe(V& v, JointLimits& l) {
  v.field(l.lower, {.name = "lower",
                    .unit = "m or rad",
                    .doc = "the lowest value of the coordinate",
                    .aliases = kLowerAliases,
                    .default_text = "unbounded",
                    .infinite = true});
  v.field(l.upper, {.name = "upper",
                    .unit = "m or rad",
                    .doc = "the highest; not below `lower`",
                    .aliases = kUpperAliases,
                    .default_text = "unbounded",
                    .infinite = true});
}

inline std::optional<Problem> rules(const JointLimits& l) {
  if (l.lower > l.upper)
    return Problem{"", fmt::format("lower ({}) is above upper ({})", l.lower, l.upper)};
  return std::nullopt;
}

inline constexpr std::string_view kMaxForceAliases[] = {"max_torque",  "max_effort", "effort",
                                                        "force_limit", "forcerange", "maxforce"};
inline constexpr std::string_view kTargetVelocityAliases[] = {"velocity", "speed", "target_speed",
                                                              "target_vel"};
inline constexpr std::string_view kTargetPositionAliases[] = {"position", "target", "target_pos",
                                                              "setpoint", "angle"};

template <class V>
void describe(V& v, JointMotor& m) {
  v.field(m.target_velocity,
          {.name = "target_velocity",
           .unit = "m/s or rad/s",
           .doc = "the rate a velocity motor holds, or a servo's damping aims at; a number or a "
                  "table in time",
           .aliases = kTargetVelocityAliases});
  v.field(m.max_force, {.name = "max_force",
                        .unit = "N or N m",
                        .range = kNonNegative,
                        .doc = "the most force or torque it acts with; **required** for a "
                               "velocity motor (one without `damping` or `target_position`)",
                        .aliases = kMaxForceAliases,
                        .default_text = "unbounded (servo, damped motor)",
                        .infinite = true});
  v.field(m.target_position,
          {.name = "target_position",
           .unit = "m or rad",
           .doc = "makes it a position servo (PD): force stiffness (target - coordinate) + "
                  "damping (target_velocity - rate), stable at any gain; a number or a table in "
                  "time",
           .aliases = kTargetPositionAliases,
           .default_text = "none"});
  v.field(m.stiffness, {.name = "stiffness",
                        .unit = "N/m or N m/rad",
                        .range = kNonNegative,
                        .doc = "the servo's gain, > 0 with `target_position` and only with it",
                        .aliases = kStiffnessAliases});
  v.field(m.damping, {.name = "damping",
                      .unit = "N s/m or N m s/rad",
                      .range = kNonNegative,
                      .doc = "without `target_position`: a damped velocity motor, force damping "
                             "(target_velocity - rate)",
                      .aliases = kDampingAliases});
}

inline std::optional<Problem> rules(const JointMotor& m) {
  if (m.target_position && !(m.stiffness > 0.0))
    return Problem{"stiffness",
                   "a servo (target_position) needs a stiffness > 0 to pull towards it"};
  if (!m.target_position && m.stiffness > 0.0)
    return Problem{"target_position", "missing: a stiffness pulls towards a target_position"};
  return std::nullopt;
}

inline constexpr std::string_view kRestAliases[] = {"rest_length", "rest_position", "rest_angle",
                                                    "springref"};
inline constexpr std::string_view kReferenceAliases[] = {"ref", "zero"};

template <class V>
void describe(V& v, JointSpring& s) {
  v.field(s.stiffness,
          {.name = "stiffness",
           .unit = "N/m or N m/rad",
           .range = kNonNegative,
           .doc = "force -stiffness (coordinate - rest); this or `damping` given, or both",
           .aliases = kStiffnessAliases});
  v.field(s.damping, {.name = "damping",
                      .unit = "N s/m or N m s/rad",
                      .range = kNonNegative,
                      .doc = "force -damping rate",
                      .aliases = kDampingAliases});
  v.field(s.rest, {.name = "rest",
                   .unit = "m or rad",
                   .doc = "where the spring is relaxed",
                   .aliases = kRestAliases});
}

inline constexpr std::string_view kFrictionAliases[] = {"frictionloss", "dry_friction"};
inline constexpr std::string_view kArmatureAliases[] = {"rotor_inertia", "reflected_inertia"};
inline constexpr std::string_view kLockedAliases[] = {"fixed", "lock"};
inline constexpr std::string_view kInitialAliases[] = {"start", "qpos", "initial_position"};

// A coordinate's fields: a joint's own with one free coordinate (a hinge's `limits`), an object
// per coordinate with several (`angle1`), or a serial joint's axis.
template <class V>
void describe(V& v, CoordinateDef& c) {
  v.field(c.limits, {.name = "limits",
                     .doc = "bounds on the coordinate; either may be left out (unbounded on that "
                            "side)",
                     .default_text = "none"});
  v.field(c.motor, {.name = "motor",
                    .doc = "a velocity motor, a damped motor or a position servo "
                           "([joints.md](joints.md#drives-and-springs))",
                    .default_text = "none"});
  v.field(c.spring, {.name = "spring",
                     .doc = "a spring and damper on the coordinate; an undamped one keeps its "
                            "amplitude",
                     .default_text = "none"});
  v.field(c.friction, {.name = "friction",
                       .unit = "N or N m",
                       .range = kNonNegative,
                       .doc = "dry (Coulomb) friction in the joint: a force of at most this much "
                              "holds the coordinate still "
                              "([joints.md](joints.md#joint-friction))",
                       .aliases = kFrictionAliases});
  v.field(c.locked, {.name = "locked",
                     .doc = "the coordinate is held at its value at the start (an equality row); "
                            "takes nothing else",
                     .aliases = kLockedAliases});
  v.field(c.prescribed,
          {.name = "prescribed",
           .unit = "m or rad",
           .doc = "the coordinate moves exactly as the table says, from its zero at the start, by "
                  "whatever force it takes; takes nothing else "
                  "([joints.md](joints.md#prescribed-motion))",
           .default_text = "none"});
  v.field(c.reference, {.name = "reference",
                        .unit = "m or rad",
                        .doc = "the coordinate's value where the model is built: limits, "
                               "targets, spring rest and tables count from the zero it implies "
                               "([joints.md](joints.md#coordinates))",
                        .aliases = kReferenceAliases});
  v.field(c.initial, {.name = "initial",
                      .unit = "m or rad",
                      .doc = "where the coordinate starts (with the reference): body1's side of "
                             "the mechanism is moved there once every joint is made; not on a "
                             "locked coordinate nor in a closed loop",
                      .aliases = kInitialAliases,
                      .default_text = "none"});
  v.field(c.armature, {.name = "armature",
                       .unit = "kg m^2 or kg",
                       .range = kNonNegative,
                       .doc = "the inertia of a rotor geared to the coordinate "
                              "([joints.md](joints.md#armature-and-applied-forces))",
                       .aliases = kArmatureAliases});
  v.field(c.force, {.name = "force",
                    .unit = "N or N m",
                    .doc = "a force or torque applied along the coordinate, a number or a table in "
                           "time: an actuator's effort",
                    .default_text = "none"});
}

inline std::optional<Problem> rules(const CoordinateDef& c) {
  const bool acted_on =
      c.limits || c.motor || c.spring || c.friction != 0.0 || c.armature != 0.0 || c.force;
  if (c.prescribed && (acted_on || c.locked))
    return Problem{"prescribed",
                   "a prescribed coordinate takes no limits, motor, spring, "
                   "friction, armature, force or lock"};
  if (c.locked && acted_on)
    return Problem{"locked",
                   "a locked coordinate takes no limits, motor, spring, friction, "
                   "armature or force"};
  if (c.locked && c.initial)
    return Problem{"initial", "a locked coordinate stays where it was made"};
  return std::nullopt;
}

}  // namespace linx::schema
