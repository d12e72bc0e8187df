#include "step/sleep.hpp"

#include "world/state_archive.hpp"

#include <algorithm>
#include <stdexcept>

namespace linx::step {

void SleepTracker::resize(int body_count) {
  if (body_count < 0) throw std::invalid_argument("SleepTracker::resize: negative body count");
  timer_.resize(static_cast<std::size_t>(body_count), 0.0);
  asleep_.resize(static_cast<std::size_t>(body_count), 0);
}

void SleepTracker::wake(int body) {
  asleep_[static_cast<std::size_t>(body)] = 0;
  timer_[static_cast<std::size_t>(body)] = 0.0;
}

void SleepTracker::wakeAll() {
  for (std::size_t i = 0; i < asleep_.size(); ++i)
    if (asleep_[i] != 0) wake(static_cast<int>(i));
}

std::span<const std::uint8_t> SleepTracker::wakeIslands(const Islands& islands) {
  if (islands.bodyCount() != size())
    throw std::invalid_argument("SleepTracker::wakeIslands: islands of another body count");
  island_awake_.resize(static_cast<std::size_t>(islands.count()));
  for (int i = 0; i < islands.count(); ++i) {
    const auto bodies = islands.bodies(i);
    const bool awake = std::any_of(bodies.begin(), bodies.end(), [&](int b) { return !asleep(b); });
    if (awake)
      for (const int b : bodies)
        if (asleep(b)) wake(b);
    island_awake_[static_cast<std::size_t>(i)] = awake ? 1 : 0;
  }
  return island_awake_;
}

void SleepTracker::update(const Islands& islands, std::span<const Body> bodies, double h,
                          const SleepSettings& settings, std::span<const std::uint8_t> may_sleep) {
  if (islands.bodyCount() != size() || bodies.size() != asleep_.size())
    throw std::invalid_argument("SleepTracker::update: islands or bodies of another body count");
  if (!settings.enabled) {
    wakeAll();
    return;
  }
  for (int i = 0; i < size(); ++i) {
    if (asleep(i) || islands.islandOf(i) < 0) continue;
    const Body& b = bodies[static_cast<std::size_t>(i)];
    double& t = timer_[static_cast<std::size_t>(i)];
    const bool rests = b.linearVelocity().norm() < settings.linear_velocity &&
                       b.angularVelocity().norm() < settings.angular_velocity;
    t = rests ? t + h : 0.0;
  }
  // The sum of n steps may fall short of n h by round-off: forgive a tiny fraction of a step.
  const double threshold = settings.time - 1e-9 * h;
  for (int i = 0; i < islands.count(); ++i) {
    if (!may_sleep.empty() && !may_sleep[static_cast<std::size_t>(i)]) continue;
    const auto members = islands.bodies(i);
    const bool ready = std::all_of(members.begin(), members.end(), [&](int b) {
      return !asleep(b) && timer_[static_cast<std::size_t>(b)] >= threshold;
    });
    if (ready)
      for (const int b : members) asleep_[static_cast<std::size_t>(b)] = 1;
  }
}

void SleepTracker::persist(state::Archive& a) {
  a.fields(timer_, asleep_, island_awake_);
}

}  // namespace linx::step
