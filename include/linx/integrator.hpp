// Which time integrator moves the bodies of a world's islands (docs/integrators.md).
#pragma once

#include <string_view>

namespace linx {

enum class IntegratorType {
  /// The velocity-level step of every island (docs/solver.md): first order, for contacts.
  Step,
  /// Islands whose constraints are joints only (no contact, limit or velocity motor rows; springs,
  /// servos and coordinate forces act as forces) move by an error-controlled Runge-Kutta method of
  /// order 5 on the index-1 equations of motion, projected onto the joints' manifold after each of
  /// its steps; the others take the step.
  Accurate,
  /// The accurate integrator on each island of joints alone (at least one) on the frames where
  /// one of its steps holds the tolerance (it then costs 1.5 to 2.6 times the step), else the
  /// step; an island that misses tries again 8, 16, ... up to 256 frames later
  /// (docs/integrators.md).
  Auto,
};

struct IntegratorSettings {
  IntegratorType type = IntegratorType::Auto;
  /// The accurate integrator's local error bound, per step of it, on each position (m), rotation
  /// (rad) and velocity (m/s, rad/s), relative to the larger of 1 and the value's size: a frame
  /// that would err more is split into smaller steps.
  double tolerance = 1e-10;
};

/// What the accurate integrator did over the last step (World::lastIntegratorReport; the last
/// pass's with solver substeps).
struct IntegratorReport {
  int bodies = 0;      ///< bodies it moved (the others took the step)
  int steps = 0;       ///< its accepted Runge-Kutta steps
  int rejected = 0;    ///< steps it tried and refused (local error above the tolerance)
  double error = 0.0;  ///< the largest joint error it projected away (m or rad)
  /// Rows it switched in the states it kept, each at an event its steps ended on: limits met (a
  /// plastic impact, then held) or left (their force fell to zero), velocity motors and joint
  /// friction locked on their target rate or slipping at their bound (docs/integrators.md,
  /// "Limits, motors and friction").
  int events = 0;
};

std::string_view integratorTypeName(IntegratorType type);

}  // namespace linx
