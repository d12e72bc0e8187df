// Sleeping: islands that have been at rest for a while stop being simulated, until something
// wakes them.
//
// Protocol, once per step (the world's step does this):
//   1. build the islands of this step from its joints and contacts (Islands::build);
//   2. tracker.wakeIslands(islands): an island with at least one awake body is awake and wakes its
//      sleeping bodies (their rest timers restart from 0); an island whose bodies all sleep stays
//      asleep. The returned flags (one per island) are what solveIslands takes;
//   3. solve the awake islands (solveIslands); rows of sleeping islands keep their impulses;
//   4. integrate only the awake bodies; sleeping bodies keep their pose and have their velocities
//      set to zero;
//   5. tracker.update(islands, bodies, h, settings): timers of awake bodies advance, and islands
//      that have rested long enough fall asleep as a whole.
// Anything that changes a body from outside (a new velocity, a force, a pose) should wake it with
// wake(body); its island then wakes at the next wakeIslands.
#pragma once

#include <linx/body.hpp>
#include <linx/contact.hpp>

#include "step/islands.hpp"

#include <cstdint>
#include <span>
#include <vector>

namespace linx::state {
class Archive;
}

namespace linx::step {

/// Rest timers and sleep flags of the bodies of a world.
class SleepTracker {
 public:
  /// Tracks body_count bodies: bodies kept from before keep their state, new ones are awake with
  /// a rest timer of 0.
  void resize(int body_count);
  int size() const { return static_cast<int>(asleep_.size()); }

  bool asleep(int body) const { return asleep_[static_cast<std::size_t>(body)] != 0; }
  /// Time (s) the body has been at rest, as of the last update.
  double restTime(int body) const { return timer_[static_cast<std::size_t>(body)]; }
  /// Wakes a body and restarts its rest timer; its whole island wakes at the next wakeIslands.
  void wake(int body);
  /// Wakes every body.
  void wakeAll();

  /// Step 2 of the protocol: one flag per island, 1 awake. An island with any awake body is awake
  /// and all its bodies are woken (rest timers of the woken ones reset to 0); an island whose
  /// bodies are all asleep stays asleep. The span stays valid until the next call.
  /// Requires size() == islands.bodyCount() (std::invalid_argument otherwise).
  std::span<const std::uint8_t> wakeIslands(const Islands& islands);
  /// The flags of the last wakeIslands.
  std::span<const std::uint8_t> islandAwake() const { return island_awake_; }

  /// Step 5 of the protocol, after the step's integration, with the bodies' new velocities. For
  /// every awake movable body, the rest timer grows by h while |v| < linear_velocity and
  /// |w| < angular_velocity, and restarts from 0 otherwise. Then every island whose bodies all
  /// have rest timers >= time falls asleep (all its bodies): after exactly ceil(time / h) steps at
  /// rest (the comparison allows for round-off in the sum of the steps). Sleeping bodies' timers
  /// are left as they are. With settings.enabled false nothing falls asleep and sleeping bodies
  /// are woken. Non-movable bodies (in no island) never sleep. When may_sleep is given (one flag
  /// per island), only flagged islands may fall asleep.
  void update(const Islands& islands, std::span<const Body> bodies, double h,
              const SleepSettings& settings, std::span<const std::uint8_t> may_sleep = {});

  /// Reads or writes what carries to the next step (World::saveState).
  void persist(state::Archive& archive);

 private:
  std::vector<double> timer_;
  std::vector<std::uint8_t> asleep_;
  std::vector<std::uint8_t> island_awake_;
};

}  // namespace linx::step
