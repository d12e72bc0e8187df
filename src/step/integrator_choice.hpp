// Integrator "auto" (docs/integrators.md): which islands of joints alone try the accurate
// integrator in a pass. An island that tries takes one Runge-Kutta step over the whole pass; where
// that step holds the tolerance the island keeps it (1.5 times the step's cost on the IFToMM
// pendulum, 2.6 on the spatial slider-crank, measured); where it does not, the island takes the
// step for that pass and tries again 8 passes later, then 16, 32 and so on up to 256 while it
// keeps failing, so that an island the accurate integrator would need several steps a pass for
// costs the step's price plus under 1 %. The waits are counted in passes, not seconds: a run
// repeats exactly, and a saved state carries them.
#pragma once

#include "step/islands.hpp"

#include <cstdint>
#include <span>
#include <vector>

namespace linx::state {
class Archive;
}

namespace linx::step {

class IntegratorChoice {
 public:
  /// Clears in `accurate` (one flag per body) the bodies of islands still waiting, after counting
  /// one more pass of every wait. Returns how many bodies stay flagged.
  int keepTrying(const Islands& islands, std::vector<std::uint8_t>& accurate);

  /// Per island (after keepTrying): the share of the tolerance its step must hold. An island that
  /// failed its last try must hold kReturnMargin of it, one that kept it the whole tolerance: an
  /// island on the edge does not switch back and forth: each switch between the step (first order,
  /// symplectic) and the accurate integrator moves an oscillator's amplitude by up to omega h of
  /// it. (A mass-spring oscillator of 100 steps a period lost 1.7 % of its amplitude over ten
  /// periods without the margin, 6e-5 with it.)
  std::span<const double> errorLimits() const { return island_limit_; }

  /// After the pass: `tried` flagged the bodies that tried, `kept` those whose island's step held
  /// the tolerance. A body that tried and failed waits twice as long as last time (8 at first).
  void record(std::span<const std::uint8_t> tried, std::span<const std::uint8_t> kept);

  /// Reads or writes the waits (World::saveState).
  void persist(state::Archive& archive);

  static constexpr int kFirstWait = 8;  ///< passes after a first failure
  static constexpr int kLongestWait = 256;
  /// A step half as long as the one that holds the tolerance errs 2^-5 of it (fifth order).
  static constexpr double kReturnMargin = 1.0 / 32.0;

 private:
  std::vector<std::int32_t> wait_;     // passes left before the body's island tries again
  std::vector<std::int32_t> backoff_;  // the body's last wait; 0: its last try held
  std::vector<std::int32_t> island_wait_;
  std::vector<double> island_limit_;
};

}  // namespace linx::step
