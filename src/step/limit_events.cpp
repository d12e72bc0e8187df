#include "step/limit_events.hpp"

#include "world/state_archive.hpp"

#include <algorithm>
#include <cmath>
#include <functional>

namespace linx::step {

namespace {

const LimitValue* find(std::span<const LimitValue> values, const LimitValue& like) {
  for (const LimitValue& v : values)
    if (v.key == like.key && v.held == like.held) return &v;
  return nullptr;
}

/// How far past zero a value may end and still count as on it: the tolerance, of a force
/// relative to the larger of 1 and the force at the step's start.
double slack(const LimitValue& end, const LimitValue* start, double tolerance) {
  if (!end.held) return tolerance;
  return tolerance * std::max(1.0, start ? std::abs(start->value) : 0.0);
}

std::array<int, 2> bodiesOf(const Row& r) {
  std::array<int, 2> bodies{-1, -1};
  std::size_t n = 0;
  r.forEachBlock([&](int body, const Vec6&) {
    if (body >= 0 && n < 2) bodies[n++] = body;
  });
  return bodies;
}

bool flagged(int body, std::span<const std::uint8_t> flags) {
  return body >= 0 && static_cast<std::size_t>(body) < flags.size() &&
         flags[static_cast<std::size_t>(body)] != 0;
}

}  // namespace

void LimitEvents::measure(std::span<const Row> open, std::span<const Row> rows,
                          std::span<const double> forces, std::span<const Body> bodies,
                          std::vector<LimitValue>& out) const {
  out.clear();
  for (const Row& r : open) out.push_back({r.key, false, r.phi, rowSpeed(r, bodies), bodiesOf(r)});
  if (held_.empty()) return;
  for (std::size_t k = 0; k < rows.size(); ++k)
    if (std::binary_search(held_.begin(), held_.end(), rows[k].key))
      out.push_back({rows[k].key, true, forces[k], 0.0, bodiesOf(rows[k])});
}

void LimitEvents::keep(std::span<const std::uint8_t> moving,
                       std::span<const std::uint8_t> unprojected) {
  std::size_t kept = 0;
  for (std::size_t k = 0; k < held_.size(); ++k) {
    bool stays = true;
    for (const int body : held_bodies_[k])
      if (body >= 0 && (!flagged(body, moving) || flagged(body, unprojected))) stays = false;
    if (!stays) continue;
    held_[kept] = held_[k];
    held_bodies_[kept++] = held_bodies_[k];
  }
  held_.resize(kept);
  held_bodies_.resize(kept);
}

void LimitEvents::hold(const LimitValue& v) {
  const auto at = std::lower_bound(held_.begin(), held_.end(), v.key) - held_.begin();
  held_.insert(held_.begin() + at, v.key);
  held_bodies_.insert(held_bodies_.begin() + at, v.bodies);
}

void LimitEvents::persist(state::Archive& archive) {
  archive.fields(held_, held_bodies_);
  if (!archive.loading()) return;
  if (held_bodies_.size() != held_.size() ||
      std::adjacent_find(held_.begin(), held_.end(), std::greater_equal<>()) != held_.end())
    throw state::StateError("held limits: keys not sorted, or not one set of bodies each");
  for (const std::array<int, 2>& b : held_bodies_)
    if (b[0] < -1 || b[1] < -1) throw state::StateError("held limits: a negative body index");
}

void LimitEvents::settle(std::span<const LimitValue> now, double tolerance,
                         std::vector<std::uint64_t>& released, std::vector<int>& switched) {
  const auto was = [](const std::vector<std::uint64_t>& keys, std::uint64_t key) {
    return std::find(keys.begin(), keys.end(), key) != keys.end();
  };
  // Let go of the held limits that pull, or whose row is gone.
  std::size_t kept = 0;
  for (std::size_t k = 0; k < held_.size(); ++k) {
    const std::uint64_t key = held_[k];
    const auto it = std::find_if(now.begin(), now.end(),
                                 [&](const LimitValue& v) { return v.held && v.key == key; });
    if (it != now.end() && it->value >= 0.0) {
      held_[kept] = key;
      held_bodies_[kept++] = held_bodies_[k];
      continue;
    }
    released.push_back(key);
    switched.push_back(held_bodies_[k][0]);
  }
  held_.resize(kept);
  held_bodies_.resize(kept);
  // Hold the open limits at their bounds that the motion does not leave, and those past them (a
  // state from elsewhere: the projection brings them back, and a force that pulls lets them go).
  for (const LimitValue& v : now) {
    if (v.held || was(released, v.key)) continue;
    if (v.value > tolerance || (v.rate > tolerance && v.value >= -tolerance)) continue;
    hold(v);
    switched.push_back(v.bodies[0]);
  }
}

double LimitEvents::share(const LimitValue& end, std::span<const LimitValue> start,
                          double tolerance) {
  const LimitValue* before = find(start, end);
  const double allowed = slack(end, before, tolerance);
  if (end.value >= -allowed) return 1.0;
  // Aim half the slack past zero, so that the retry ends within it rather than just short.
  const double f0 = before ? before->value : 0.0;
  if (!(f0 > allowed)) return 0.5;
  const double target = -0.5 * allowed;
  return std::clamp((f0 - target) / (f0 - end.value), 1e-6, 0.99);
}

double LimitEvents::share(std::span<const LimitValue> end, std::span<const LimitValue> start,
                          double tolerance) {
  double s = 1.0;
  for (const LimitValue& v : end) s = std::min(s, share(v, start, tolerance));
  return s;
}

}  // namespace linx::step
