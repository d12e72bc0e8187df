// Joint limits inside the accurate integrator (docs/integrators.md, "Limits"): the events of its
// steps. A limit (a coordinate's, a ball joint's cone, a rope's length: every unilateral joint
// row) is either open, its row taking no part while the coordinate moves freely, or held, its row
// one more equality among the joints'. Two events switch it:
//   - impact: an open limit's gap closes. A step that ends past the bound is refused and retried
//     shorter, its length from the gap's secant over the step, until it ends on the bound; there
//     the limit is held, and the velocity projection takes its closing rate away: a plastic
//     impact, as the step's limit rows make it (they arrive at the bound and stay).
//   - release: a held limit's force falls to zero. A step that ends with the limit pulling is
//     refused and retried shorter the same way; there the limit opens.
// At each step's start the held set is brought up to date from the state (an open limit on or
// past its bound and not leaving it is held; a held one whose force pulls is let go). It carries
// from frame to frame (and in saved states) while the accurate integrator moves the limit's bodies
// from the state it left them in; a body that took the step, or whose state was set, starts with
// its limits open.
#pragma once

#include <linx/body.hpp>
#include <linx/row.hpp>

#include "step/constrained_dynamics.hpp"

#include <array>
#include <cstdint>
#include <span>
#include <vector>

namespace linx::state {
class Archive;
}

namespace linx::step {

/// One limit's event function at one state: an open limit's gap (m or rad) or a held one's force
/// (N or N m); the limit keeps its state while it is >= 0.
struct LimitValue {
  std::uint64_t key = 0;  ///< the limit row's
  bool held = false;
  double value = 0.0;
  double rate = 0.0;                  ///< an open limit's: the gap's rate J u
  std::array<int, 2> bodies{-1, -1};  ///< the bodies the row acts on (-1: none)
};

class LimitEvents {
 public:
  HeldLimits held() const { return held_; }
  /// Opens the held limits on a body not flagged in `moving` or flagged in `unprojected` (a state
  /// the accurate integrator did not leave; empty: none), before a frame.
  void keep(std::span<const std::uint8_t> moving, std::span<const std::uint8_t> unprojected);

  /// The event functions at the bodies' state, from the acceleration solve there: the gaps and
  /// rates of the `open` limits, the forces of the held ones among the solve's `rows` (`forces`).
  void measure(std::span<const Row> open, std::span<const Row> rows, std::span<const double> forces,
               std::span<const Body> bodies, std::vector<LimitValue>& out) const;

  /// At a step's start, from the values there (`now`): holds every open limit on its bound (gap
  /// within the tolerance) and not leaving it (rate <= tolerance), or past it by more than the
  /// tolerance, but those in `released`, and lets go
  /// of every held limit whose force pulls (or whose row is gone), adding it to `released` (so
  /// that a limit at its bound that the motion leaves is not held again at the same start).
  /// Appends the first body of each limit it switched to `switched`.
  void settle(std::span<const LimitValue> now, double tolerance,
              std::vector<std::uint64_t>& released, std::vector<int>& switched);

  /// For a limit's value at a step's end: 1 where it kept its state (an open limit at most
  /// `tolerance` past its bound, a held one pulling by at most tolerance of its force at the
  /// step's start), else the share of the step to retry with: where the secant of its value
  /// between the step's `start` values and this one crosses just past zero, or half the step when
  /// the value at the start is unknown or within the tolerance of zero.
  static double share(const LimitValue& end, std::span<const LimitValue> start, double tolerance);
  /// The smallest share() of the values at a step's end.
  static double share(std::span<const LimitValue> end, std::span<const LimitValue> start,
                      double tolerance);

  /// Reads or writes the held limits (World::saveState).
  void persist(state::Archive& archive);

 private:
  void hold(const LimitValue& v);

  std::vector<std::uint64_t> held_;              // sorted
  std::vector<std::array<int, 2>> held_bodies_;  // the bodies of held_[k]
};

}  // namespace linx::step
