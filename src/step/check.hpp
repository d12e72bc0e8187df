// The check after a step: faults that make its results meaningless stop the run instead of
// passing silently (FaultSettings in linx/world.hpp, docs/solver.md "Faults"):
//   - a body whose pose or velocity is not finite (NonFiniteState);
//   - a body faster than the settings' max_speed or max_angular_speed (BoundExceeded);
//   - energy made by steps that nothing drove, beyond the settings' bound (EnergyGrowth).
#pragma once

#include <linx/body.hpp>
#include <linx/world.hpp>

#include <cstdint>
#include <span>

namespace linx::state {
class Archive;
}

namespace linx::step {

class FaultCheck {
 public:
  /// Before a step: the energy it starts from, and whether an applied load drives it.
  void begin(std::span<const Body> bodies, const Vec3& gravity);
  /// After the step (`motors`: its rows held a motor, which drives it). Throws NonFiniteState
  /// naming the first body whose state is not finite, then EnergyGrowth naming the body with the
  /// most kinetic energy.
  void end(std::span<const Body> bodies, const Vec3& gravity, const FaultSettings& settings,
           bool motors, std::int64_t step, double time);
  /// Throws BoundExceeded for the first body faster than the settings' max_speed or
  /// max_angular_speed.
  static void checkSpeeds(std::span<const Body> bodies, const FaultSettings& settings,
                          std::int64_t step, double time);
  /// Throws BoundExceeded for the first body that is not static whose position is beyond
  /// kMaxExtent (linx/bounds.hpp) from the origin.
  static void checkPositions(std::span<const Body> bodies, std::int64_t step, double time);
  /// Throws NonFiniteState naming the first body whose energy (kinetic and gravitational) is not
  /// finite, or the world's when only the sum is not.
  [[noreturn]] static void throwNonFiniteEnergy(std::span<const Body> bodies, const Vec3& gravity,
                                                std::int64_t step, double time);
  /// Reads or writes the sums carried from step to step (World::saveState).
  void persist(state::Archive& archive);

 private:
  double before_ = 0.0;        // (J) total energy at the start of the step
  bool loaded_ = false;        // an applied force or torque drove the step
  double produced_ = 0.0;      // (J) energy made by undriven steps, summed
  double lowest_ = 0.0;        // (J) the lowest value of produced_ so far
  double kinetic_peak_ = 0.0;  // (J) the largest kinetic energy seen before or after a step
};

}  // namespace linx::step
