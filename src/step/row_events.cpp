#include "step/row_events.hpp"

#include "world/state_archive.hpp"

#include <algorithm>
#include <cmath>
#include <functional>
#include <utility>

namespace linx::step {

namespace {

const EventValue* find(std::span<const EventValue> values, const EventValue& like) {
  for (const EventValue& v : values)
    if (v.key == like.key && v.held == like.held) return &v;
  return nullptr;
}

/// How far past zero a value may end and still count as on it: the tolerance, of a force
/// relative to the larger of 1 and its size (a held limit's at the step's start, a velocity row's
/// bound).
double slack(const EventValue& end, const EventValue* start, double tolerance) {
  if (!end.held) return tolerance;
  const double size = end.limit ? (start ? std::abs(start->value) : 0.0) : end.bound;
  return tolerance * std::max(1.0, std::isfinite(size) ? size : 1.0);
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

bool listed(const std::vector<std::uint64_t>& keys, std::uint64_t key) {
  return std::find(keys.begin(), keys.end(), key) != keys.end();
}

}  // namespace

void RowEvents::measure(std::span<const Row> open, std::span<const Row> rows,
                        std::span<const double> forces, std::span<const Body> bodies,
                        std::vector<EventValue>& out) const {
  out.clear();
  const Switches now = switches();
  for (const Row& r : open) {
    const double rate = rowSpeed(r, bodies);
    if (isLimit(r)) {
      out.push_back({r.key, true, false, r.phi, rate, 0.0, kInfinity, bodiesOf(r)});
      continue;
    }
    const double slip = r.speed - rate;  // the target (the row's speed) less the rate
    const double push = now.push(r.key, slip >= 0.0 ? 1.0 : -1.0);
    out.push_back({r.key, false, false, push * slip, slip, 0.0, velocityBound(r), bodiesOf(r)});
  }
  for (std::size_t k = 0; k < rows.size(); ++k) {
    const auto it = std::lower_bound(held_.begin(), held_.end(), rows[k].key);
    if (it == held_.end() || *it != rows[k].key) continue;
    const Held& h = held_rows_[static_cast<std::size_t>(it - held_.begin())];
    const double f = forces[k];
    out.push_back({rows[k].key, h.limit, true, h.limit ? f : h.bound - std::abs(f), 0.0, f, h.bound,
                   h.bodies});
  }
}

void RowEvents::keep(std::span<const std::uint8_t> moving,
                     std::span<const std::uint8_t> unprojected) {
  pushing_.clear();
  std::size_t kept = 0;
  for (std::size_t k = 0; k < held_.size(); ++k) {
    bool stays = true;
    for (const int body : held_rows_[k].bodies)
      if (body >= 0 && (!flagged(body, moving) || flagged(body, unprojected))) stays = false;
    if (!stays) continue;
    held_[kept] = held_[k];
    held_rows_[kept++] = held_rows_[k];
  }
  held_.resize(kept);
  held_rows_.resize(kept);
}

void RowEvents::hold(const EventValue& v) {
  const auto at = std::lower_bound(held_.begin(), held_.end(), v.key) - held_.begin();
  held_.insert(held_.begin() + at, v.key);
  held_rows_.insert(held_rows_.begin() + at, Held{v.bodies, v.bound, v.limit});
}

void RowEvents::persist(state::Archive& archive) {
  archive(held_);
  archive.each(held_rows_,
               [](state::Archive& a, Held& h) { a.fields(h.bodies, h.bound, h.limit); });
  if (!archive.loading()) return;
  if (held_rows_.size() != held_.size() ||
      std::adjacent_find(held_.begin(), held_.end(), std::greater_equal<>()) != held_.end())
    throw state::StateError("held rows: keys not sorted, or not one row each");
  for (const Held& h : held_rows_)
    if (h.bodies[0] < -1 || h.bodies[1] < -1 || !(h.bound >= 0.0))
      throw state::StateError("held rows: a negative body index or force bound");
  pushing_.clear();
}

void RowEvents::settle(std::span<const EventValue> now, double tolerance,
                       std::vector<std::uint64_t>& released, std::vector<int>& switched) {
  // Let go of the held rows whose function went below zero, or whose row is gone.
  std::size_t kept = 0;
  for (std::size_t k = 0; k < held_.size(); ++k) {
    const std::uint64_t key = held_[k];
    const auto it = std::find_if(now.begin(), now.end(),
                                 [&](const EventValue& v) { return v.held && v.key == key; });
    if (it != now.end() && it->value >= 0.0) {
      held_[kept] = key;
      held_rows_[kept++] = held_rows_[k];
      continue;
    }
    released.push_back(key);
    switched.push_back(held_rows_[k].bodies[0]);
  }
  held_.resize(kept);
  held_rows_.resize(kept);
  // Hold the open limits at their bounds that the motion does not leave, and those past them (a
  // state from elsewhere: the projection brings them back, and a force that pulls lets them go);
  // lock the velocity rows at their targets.
  for (const EventValue& v : now) {
    if (v.held || listed(released, v.key)) continue;
    const bool meets = v.limit
                           ? v.value <= tolerance && (v.rate <= tolerance || v.value < -tolerance)
                           : std::abs(v.rate) <= tolerance || !std::isfinite(v.bound);
    if (!meets) continue;
    hold(v);
    switched.push_back(v.bodies[0]);
  }
  // The slipping rows' directions over the step: towards the target; a row let go at this start
  // (now, or in an earlier round of it) on as its force pushed, which its rate, still on the
  // target, does not tell.
  const Switches before = switches();
  std::vector<std::pair<std::uint64_t, double>> pushing;
  for (const EventValue& v : now) {
    if (v.limit || std::binary_search(held_.begin(), held_.end(), v.key)) continue;
    double push = v.rate >= 0.0 ? 1.0 : -1.0;
    if (v.held)
      push = v.force >= 0.0 ? 1.0 : -1.0;
    else if (listed(released, v.key))
      push = before.push(v.key, push);
    pushing.emplace_back(v.key, push);
  }
  std::sort(pushing.begin(), pushing.end());
  pushing_ = std::move(pushing);
}

double RowEvents::share(const EventValue& end, std::span<const EventValue> start,
                        double tolerance) {
  const EventValue* before = find(start, end);
  const double allowed = slack(end, before, tolerance);
  if (end.value >= -allowed) return 1.0;
  // Aim half the slack past zero, so that the retry ends within it rather than just short.
  const double f0 = before ? before->value : 0.0;
  if (!(f0 > allowed)) return 0.5;
  const double target = -0.5 * allowed;
  return std::clamp((f0 - target) / (f0 - end.value), 1e-6, 0.99);
}

double RowEvents::share(std::span<const EventValue> end, std::span<const EventValue> start,
                        double tolerance) {
  double s = 1.0;
  for (const EventValue& v : end) s = std::min(s, share(v, start, tolerance));
  return s;
}

}  // namespace linx::step
