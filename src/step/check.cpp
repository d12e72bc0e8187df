#include "step/check.hpp"

#include <linx/bounds.hpp>

#include "dynamics/energy.hpp"
#include "world/state_archive.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

namespace linx::step {

namespace {

/// The first body whose state is not finite, and what of it; -1 for none.
int nonFiniteBody(std::span<const Body> bodies, const char*& what) {
  for (std::size_t i = 0; i < bodies.size(); ++i) {
    const Body& b = bodies[i];
    what = !b.position().allFinite()               ? "position"
           : !b.orientation().coeffs().allFinite() ? "orientation"
           : !b.linearVelocity().allFinite()       ? "linear velocity"
           : !b.angularVelocity().allFinite()      ? "angular velocity"
                                                   : nullptr;
    if (what) return static_cast<int>(i);
  }
  return -1;
}

double kineticEnergy(const Body& b) {
  const Vec3 w = b.angularVelocity();
  return 0.5 * b.mass() * b.linearVelocity().squaredNorm() + 0.5 * w.dot(b.inertiaWorld() * w);
}

}  // namespace

void FaultCheck::begin(std::span<const Body> bodies, const Vec3& gravity) {
  const Energy before = dynamics::computeEnergy(bodies, gravity);
  before_ = before.total();
  if (std::isfinite(before.kinetic)) kinetic_peak_ = std::max(kinetic_peak_, before.kinetic);
  loaded_ = std::any_of(bodies.begin(), bodies.end(), [](const Body& b) {
    return !b.force().isZero(0) || !b.torque().isZero(0);
  });
}

void FaultCheck::end(std::span<const Body> bodies, const Vec3& gravity,
                     const FaultSettings& settings, bool motors, std::int64_t step, double time) {
  const char* what = nullptr;
  if (const int i = nonFiniteBody(bodies, what); i >= 0)
    throw NonFiniteState(
        fmt::format("bodies[{}] ({}): {} is not finite after step {} (t = {} s)", i,
                    bodies[static_cast<std::size_t>(i)].name(), what, step, time),
        i, step, time);
  // An energy that is not finite stops the run. A bound passed names its cause better (a body at
  // 1e200 m/s), but with faults.stop false the bound's fault is kept and the world would step on.
  const Energy after = dynamics::computeEnergy(bodies, gravity);
  const bool finite = std::isfinite(after.total());
  if (finite || settings.stop) {
    checkSpeeds(bodies, settings, step, time);
    checkPositions(bodies, step, time);
  }
  if (!finite) throwNonFiniteEnergy(bodies, gravity, step, time);
  if (!settings.energy) return;
  if (std::isfinite(after.kinetic)) kinetic_peak_ = std::max(kinetic_peak_, after.kinetic);
  // Driven, its energy may rise; an energy too large for a double is left to the state check.
  if (loaded_ || motors || !std::isfinite(after.total()) || !std::isfinite(before_)) return;
  produced_ += after.total() - before_;
  lowest_ = std::min(lowest_, produced_);
  const double rise = produced_ - lowest_;
  double allowance = 0.0;  // position correction may lift every body or push it to a speed
  for (const Body& b : bodies)
    if (b.isDynamic())
      allowance +=
          b.mass() * (gravity.norm() * settings.height + 0.5 * settings.speed * settings.speed);
  const double bound = settings.kinetic_fraction * kinetic_peak_ + allowance;
  if (rise <= bound) return;
  int fastest = -1;
  double most = -1.0;
  for (std::size_t i = 0; i < bodies.size(); ++i) {
    if (!bodies[i].isDynamic()) continue;
    const double k = kineticEnergy(bodies[i]);
    if (k > most) {
      most = k;
      fastest = static_cast<int>(i);
    }
  }
  const std::string body =
      fastest < 0 ? std::string("no body")
                  : fmt::format("bodies[{}] ({}) has the most kinetic energy, {:.3g} J", fastest,
                                bodies[static_cast<std::size_t>(fastest)].name(), most);
  throw EnergyGrowth(
      fmt::format(
          "the steps made {:.3g} J of energy while nothing drove the world (bound {:.3g} "
          "J: faults.kinetic_fraction of the largest kinetic energy plus the allowance for "
          "position correction) after step {} (t = {} s); {}: the solve is unstable (a smaller "
          "timestep or more solver.substeps help; docs/solver.md)",
          rise, bound, step, time, body),
      fastest, step, time, rise, bound);
}

void FaultCheck::throwNonFiniteEnergy(std::span<const Body> bodies, const Vec3& gravity,
                                      std::int64_t step, double time) {
  for (std::size_t i = 0; i < bodies.size(); ++i) {
    const Body& b = bodies[i];
    if (!b.isDynamic()) continue;
    const double kinetic = kineticEnergy(b), potential = -b.mass() * gravity.dot(b.position());
    if (std::isfinite(kinetic + potential)) continue;
    throw NonFiniteState(
        fmt::format("bodies[{}] ({}): energy is not finite (kinetic {:.6g} J, potential {:.6g} J "
                    "at {:.6g} m from the origin) after step {} (t = {} s)",
                    i, b.name(), kinetic, potential, b.position().stableNorm(), step, time),
        static_cast<int>(i), step, time);
  }
  throw NonFiniteState(fmt::format("the world's energy is not finite (the bodies' sum is beyond "
                                   "a double) after step {} (t = {} s)",
                                   step, time),
                       -1, step, time);
}

void FaultCheck::checkPositions(std::span<const Body> bodies, std::int64_t step, double time) {
  for (std::size_t i = 0; i < bodies.size(); ++i) {
    const Body& b = bodies[i];
    if (b.isStatic() || !(b.position().cwiseAbs().maxCoeff() > kMaxExtent)) continue;
    throw BoundExceeded(
        fmt::format("bodies[{}] ({}): position {:.6g} m from the origin is beyond {:g} m, where "
                    "doubles are too coarse to resolve a contact within the slop, after step {} "
                    "(t = {} s)",
                    i, b.name(), b.position().stableNorm(), kMaxExtent, step, time),
        static_cast<int>(i), -1, step, time);
  }
}

void FaultCheck::checkSpeeds(std::span<const Body> bodies, const FaultSettings& settings,
                             std::int64_t step, double time) {
  const double v2 = settings.max_speed * settings.max_speed,
               w2 = settings.max_angular_speed * settings.max_angular_speed;
  for (std::size_t i = 0; i < bodies.size(); ++i) {
    const Body& b = bodies[i];
    const bool linear = b.linearVelocity().squaredNorm() > v2;
    if (!linear && !(b.angularVelocity().squaredNorm() > w2)) continue;
    throw BoundExceeded(
        linear ? fmt::format("bodies[{}] ({}): speed {:.6g} m/s is above faults.max_speed ({} "
                             "m/s) after step {} (t = {} s)",
                             i, b.name(), b.linearVelocity().stableNorm(), settings.max_speed, step,
                             time)
               : fmt::format("bodies[{}] ({}): angular speed {:.6g} rad/s is above "
                             "faults.max_angular_speed ({} rad/s) after step {} (t = {} s)",
                             i, b.name(), b.angularVelocity().stableNorm(),
                             settings.max_angular_speed, step, time),
        static_cast<int>(i), -1, step, time);
  }
}

void FaultCheck::persist(state::Archive& a) {
  a(produced_);
  a(lowest_);
  a(kinetic_peak_);
}

}  // namespace linx::step
