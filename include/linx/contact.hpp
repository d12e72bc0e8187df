// Contacts: how touching shapes are turned into constraint rows, and what a step reports of them.
// docs/contacts.md explains the parameters and the rules that combine two materials.
#pragma once

#include <linx/body.hpp>
#include <linx/types.hpp>

#include <cstdint>
#include <optional>

namespace linx {

/// How contacts behave, for the whole world.
struct ContactSettings {
  bool enabled = true;  ///< detect contacts between shapes at all
  /// Speculative distance (m): shapes closer than this (plus what their speed covers in a step)
  /// get contact rows before they touch, so a fast body stops at the surface instead of sinking in.
  double margin = 0.01;
  double slop = 5e-4;  ///< allowed penetration (m): deeper is pushed out by erp, shallower is left
  double erp = 0.2;    ///< fraction of the penetration beyond the slop removed per step, [0, 1]
  double cfm = 1e-10;  ///< constraint force mixing of contact rows (compliance), >= 0
  /// Instead of erp and cfm: a contact stiffness (N/m) and damping (N s/m), both given or neither.
  std::optional<double> stiffness = std::nullopt;
  std::optional<double> damping = std::nullopt;
  /// Approach speeds (m/s) below this do not bounce, whatever the restitution: resting contacts
  /// stay at rest instead of chattering.
  double restitution_threshold = 0.2;
  /// The fastest (m/s) that penetration is pushed out: a body created deep inside another leaves
  /// it at this speed instead of erp / h times the depth (10 m/s for 5 cm at h = 1 ms).
  double max_push_out = 3.0;
  /// Soft step (solver type "soft"): the contacts' spring frequency (Hz) and damping ratio, in
  /// place of erp, cfm and slop. A resting contact sinks by g / (2 pi hertz)^2 under its own
  /// body's weight, more under a stack, so the default 0 takes the stiffest that stays stable, an
  /// eighth of the substep rate (60 Hz at 60 Hz and 8 substeps); a given value is capped there.
  double hertz = 0.0;
  double damping_ratio = 10.0;

  bool operator==(const ContactSettings&) const = default;
};

/// When bodies fall asleep: an island (bodies linked by joints and contacts) whose bodies have all
/// moved slower than these speeds for `time` seconds sleeps; it stops being integrated until a
/// body of its island moves again (something touches it, a joint or a contact links it to an
/// awake body, or the program moves or pushes it).
struct SleepSettings {
  bool enabled = true;            ///< false: nothing sleeps (sleeping bodies are woken)
  double linear_velocity = 0.05;  ///< (m/s) a body rests while |v| is below this
  double angular_velocity = 0.1;  ///< (rad/s) ... and |w| below this
  double time = 0.5;              ///< (s) time at rest before an island falls asleep
};

/// One contact point of the last step.
struct Contact {
  BodyId body1, body2;          ///< body2 may be a static body; never the world frame
  int shape1 = 0, shape2 = 0;   ///< shape indices within the bodies
  Vec3 point = Vec3::Zero();    ///< world (m), midway between the surfaces
  Vec3 normal = Vec3::UnitZ();  ///< world unit normal, from body1 towards body2
  double depth = 0.0;           ///< penetration at the start of the step (m), negative: a gap
  double normal_impulse = 0.0;  ///< on body2 along +normal (N s); body1 gets the opposite
  Vec3 friction_impulse = Vec3::Zero();  ///< tangential impulse on body2 (N s), world frame
  std::uint32_t feature = 0;             ///< which features touch; stable across steps
};

}  // namespace linx
