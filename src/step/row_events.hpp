// The joint rows the accurate integrator switches (docs/integrators.md, "Limits, motors and
// friction"): the events of its steps. Each such row is held, one more equality among the
// joints', or not:
//   - a limit (a coordinate's bound, a ball joint's cone, a rope's length: every unilateral joint
//     row) is open, taking no part, until its gap closes: an impact, plastic (the projection with
//     the row held takes the closing rate away), as the step's limit rows make it; it is held
//     while it pushes, and opens where its force falls to zero;
//   - a velocity row (a velocity motor, joint friction: a target rate with a force bound) is
//     locked, holding its rate at the target, while its force is within the bound; past it, it
//     slips, applying the bound towards its target, until its rate reaches the target again.
// A step that ends past an event (a gap past its bound, a held limit pulling, a locked row past
// its bound, a slipping row past its target) by more than the tolerance is refused and tried
// again shorter, its length from the secant of the event's function over the step, until it ends
// on the event. At each step's start the rows switch (settle) from the state there, so that
// everything the step needs is the held set; it carries from frame to frame (and in saved
// states) while the accurate integrator moves the rows' bodies from the state it left them in.
#pragma once

#include <linx/body.hpp>
#include <linx/row.hpp>

#include "step/constrained_dynamics.hpp"

#include <array>
#include <cstdint>
#include <span>
#include <utility>
#include <vector>

namespace linx::state {
class Archive;
}

namespace linx::step {

/// One switched row's event function at one state; the row keeps its state while it is >= 0:
/// an open limit's gap (m or rad), a held limit's force (N or N m), a locked velocity row's bound
/// less the size of its force, a slipping one's rate short of its target in the direction it
/// pushes (m/s or rad/s).
struct EventValue {
  std::uint64_t key = 0;  ///< the row's
  bool limit = true;      ///< a limit, else a velocity row
  bool held = false;
  double value = 0.0;
  double rate = 0.0;         ///< an open limit's gap rate J u; a velocity row's target less J u
  double force = 0.0;        ///< a held row's (N or N m)
  double bound = kInfinity;  ///< a velocity row's force bound (N or N m)
  std::array<int, 2> bodies{-1, -1};  ///< the bodies the row acts on (-1: none)
};

class RowEvents {
 public:
  /// What the acceleration solve and the projection need: the held rows, the slipping ones'
  /// directions.
  Switches switches() const { return {held_, pushing_}; }

  /// Before a frame: opens (frees) the held rows on a body not flagged in `moving` or flagged in
  /// `unprojected` (a state the accurate integrator did not leave; empty: none), and forgets the
  /// slipping rows' directions (they come from the state at each step's start).
  void keep(std::span<const std::uint8_t> moving, std::span<const std::uint8_t> unprojected);

  /// The event functions at the bodies' state, from the acceleration solve there: of the rows not
  /// held (`open`: ConstrainedDynamics::openRows), and of the held ones among the solve's `rows`
  /// (their `forces`).
  void measure(std::span<const Row> open, std::span<const Row> rows, std::span<const double> forces,
               std::span<const Body> bodies, std::vector<EventValue>& out) const;

  /// At a step's start, from the values there (`now`): lets go of every held limit whose force
  /// pulls and every locked velocity row past its bound (or whose row is gone), adding it to
  /// `released`; holds every open limit on its bound (gap within the tolerance) and not leaving it
  /// (rate <= tolerance), or past it by more than the tolerance, and locks every velocity row at
  /// its target (within the tolerance, or of unbounded force), but those in `released` (switched
  /// at this start already). Then sets each slipping row's direction for the step: towards its
  /// target, or for one just let go the way its force pushed. Appends the first body of each row
  /// it switched to `switched`.
  void settle(std::span<const EventValue> now, double tolerance,
              std::vector<std::uint64_t>& released, std::vector<int>& switched);

  /// For a value at a step's end: 1 where the row kept its state (its function at least minus
  /// the tolerance; of a force, relative to the larger of 1 and its size), else the share of the
  /// step to retry with: where the secant of the function between its value in the step's `start`
  /// values and this one crosses just past zero, or half the step when the value at the start is
  /// unknown or within the tolerance of zero.
  static double share(const EventValue& end, std::span<const EventValue> start, double tolerance);
  /// The smallest share() of the values at a step's end.
  static double share(std::span<const EventValue> end, std::span<const EventValue> start,
                      double tolerance);

  /// Reads or writes the held rows (World::saveState).
  void persist(state::Archive& archive);

 private:
  struct Held {
    std::array<int, 2> bodies{-1, -1};
    double bound = kInfinity;  // a velocity row's force bound; a limit's: infinite
    bool limit = true;
  };
  void hold(const EventValue& v);

  std::vector<std::uint64_t> held_;                        // sorted
  std::vector<Held> held_rows_;                            // of held_[k]
  std::vector<std::pair<std::uint64_t, double>> pushing_;  // sorted by key
};

}  // namespace linx::step
