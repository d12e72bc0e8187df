#include "world/actuators.hpp"

#include <linx/world.hpp>

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace linx {
namespace {

bool finite(const Signal& s) {
  return std::all_of(s.values.begin(), s.values.end(), [](double v) { return std::isfinite(v); });
}

void checkRange(const std::optional<ActuatorRange>& r, const char* name, bool holds_zero) {
  if (!r) return;
  if (std::isnan(r->lower) || std::isnan(r->upper) || !(r->lower <= r->upper))
    throw std::invalid_argument(
        fmt::format("{}: lower must be <= upper, got [{}, {}]", name, r->lower, r->upper));
  if (holds_zero && !(r->lower <= 0.0 && r->upper >= 0.0))
    throw std::invalid_argument(
        fmt::format("{}: must contain zero, got [{}, {}]", name, r->lower, r->upper));
}

// Whether p u + q <= 0 for every control u of the range (all u when there is none): an affine
// function is largest at an end.
bool neverPushes(double p, double q, const std::optional<ActuatorRange>& range) {
  const ActuatorRange r = range.value_or(ActuatorRange{});
  if (p == 0.0) return q <= 0.0;
  const double end = p > 0.0 ? r.upper : r.lower;
  return std::isfinite(end) && p * end + q <= 0.0;
}

}  // namespace

ActuatorId Actuators::add(const ActuatorDef& def, World& world) {
  const auto fail = [](const std::string& problem) { throw std::invalid_argument(problem); };
  if (def.name.empty()) fail("name: must not be empty");
  if (names_.count(def.name)) fail(fmt::format("name: a second actuator named '{}'", def.name));
  if (!world.contains(def.joint)) fail("joint: not a joint of this world");
  const Joint& joint = world.joint(def.joint);
  if (def.coordinate < 0 || def.coordinate >= joint.freeCoordinates())
    fail(fmt::format("coordinate: joint '{}' has {} free coordinates, got {}", joint.name(),
                     joint.freeCoordinates(), def.coordinate));
  if (!(std::isfinite(def.gear) && def.gear != 0.0)) fail("gear: must be finite and not zero");
  for (const auto& [value, name] : {std::pair{def.gain, "gain"},
                                    {def.gain_length, "gain_length"},
                                    {def.gain_velocity, "gain_velocity"},
                                    {def.bias, "bias"},
                                    {def.bias_length, "bias_length"},
                                    {def.bias_velocity, "bias_velocity"}})
    if (!std::isfinite(value)) fail(fmt::format("{}: must be finite, got {}", name, value));
  checkRange(def.control_range, "control_range", false);
  checkRange(def.force_range, "force_range", true);
  if (!finite(def.control)) fail("control: must be finite");
  if (!neverPushes(def.gain_length, def.bias_length, def.control_range) ||
      !neverPushes(def.gain_velocity, def.bias_velocity, def.control_range))
    fail(
        "pushes away from where it is at some control (gain_length u + bias_length, or "
        "gain_velocity u + bias_velocity, above 0): such an actuator makes energy without bound "
        "(bound the control with control_range)");

  auto group = std::find_if(coordinates_.begin(), coordinates_.end(), [&](const Coordinate& c) {
    return c.joint == def.joint && c.coordinate == def.coordinate;
  });
  if (group == coordinates_.end()) {
    const CoordinateDef& own = joint.def().coordinates[static_cast<std::size_t>(def.coordinate)];
    if (own.motor || own.force)
      fail(
          fmt::format("coordinate: joint '{}' coordinate {} has a motor or force of its own (an "
                      "actuator drives it alone)",
                      joint.name(), def.coordinate));
    coordinates_.push_back(Coordinate{def.joint, def.coordinate, {}, false, std::nullopt, 0.0});
    group = coordinates_.end() - 1;
  } else if (def.isServo() &&
             std::any_of(group->actuators.begin(), group->actuators.end(),
                         [&](int i) { return defs_[static_cast<std::size_t>(i)].isServo(); })) {
    fail(
        fmt::format("coordinate: joint '{}' coordinate {} has a servo or damper already (forces "
                    "of several actuators add, servos do not)",
                    joint.name(), def.coordinate));
  }
  const int index = count();
  group->actuators.push_back(index);
  group->set = false;
  defs_.push_back(def);
  controls_.push_back(def.control.at(0.0));
  scheduled_.push_back(!def.control.times.empty());
  names_.emplace(def.name, index);
  apply(world, world.time());
  return ActuatorId{index};
}

std::size_t Actuators::checked(ActuatorId id) const {
  if (id.index < 0 || id.index >= count())
    throw std::out_of_range(fmt::format("no actuator {} (there are {})", id.index, count()));
  return static_cast<std::size_t>(id.index);
}

const ActuatorDef& Actuators::def(ActuatorId id) const {
  return defs_[checked(id)];
}

std::optional<ActuatorId> Actuators::find(std::string_view name) const {
  const auto it = names_.find(std::string(name));
  if (it == names_.end()) return std::nullopt;
  return ActuatorId{it->second};
}

void Actuators::setControl(ActuatorId id, double value) {
  const std::size_t i = checked(id);
  if (!std::isfinite(value))
    throw std::invalid_argument(
        fmt::format("actuator '{}': control must be finite, got {}", defs_[i].name, value));
  controls_[i] = value;
  scheduled_[i] = false;
}

double Actuators::clampedControl(std::size_t i) const {
  const auto& r = defs_[i].control_range;
  return r ? std::clamp(controls_[i], r->lower, r->upper) : controls_[i];
}

Actuators::Terms Actuators::terms(std::size_t i) const {
  const ActuatorDef& d = defs_[i];
  const double u = clampedControl(i);
  return {d.gain * u + d.bias, d.gain_length * u + d.bias_length,
          d.gain_velocity * u + d.bias_velocity};
}

void Actuators::apply(World& world, double t) {
  for (std::size_t i = 0; i < defs_.size(); ++i) {
    if (scheduled_[i]) controls_[i] = defs_[i].control.at(t);
    if (!std::isfinite(controls_[i]))
      throw std::invalid_argument(fmt::format("actuator '{}': control must be finite, got {}",
                                              defs_[i].name, controls_[i]));
  }
  for (Coordinate& c : coordinates_) {
    if (!world.contains(c.joint)) continue;
    std::optional<JointMotor> motor;
    double force = 0.0;
    for (const int a : c.actuators) {
      const auto i = static_cast<std::size_t>(a);
      const ActuatorDef& d = defs_[i];
      const Terms k = terms(i);
      const double g = d.gear;
      const ActuatorRange bounds = d.force_range.value_or(ActuatorRange{});
      if (k.length == 0.0 && k.velocity == 0.0) {
        force += g * std::clamp(k.constant, bounds.lower, bounds.upper);
        continue;
      }
      JointMotor m;
      m.max_force = std::abs(g) * std::max(-bounds.lower, bounds.upper);
      m.damping = -k.velocity * g * g;
      if (k.length < 0.0) {
        m.stiffness = -k.length * g * g;
        m.target_position = Signal(-k.constant / (k.length * g));
      } else {
        m.target_velocity = Signal(-k.constant / (k.velocity * g));
      }
      motor = m;
    }
    if (c.set && motor == c.motor && force == c.force) continue;
    Joint& joint = world.joint(c.joint);
    joint.setMotor(motor, c.coordinate);
    joint.setForce(Signal(force), c.coordinate);
    c.set = true;
    c.motor = motor;
    c.force = force;
  }
}

double Actuators::force(ActuatorId id, const World& world) const {
  const std::size_t i = checked(id);
  const ActuatorDef& d = defs_[i];
  if (!world.contains(d.joint)) return 0.0;
  const auto c = static_cast<Eigen::Index>(d.coordinate);
  const double reference =
      world.joint(d.joint).def().coordinates[static_cast<std::size_t>(d.coordinate)].reference;
  const double length = d.gear * (world.jointCoordinates(d.joint)[c] + reference);
  const double rate = d.gear * world.jointRates(d.joint)[c];
  const Terms k = terms(i);
  const ActuatorRange bounds = d.force_range.value_or(ActuatorRange{});
  return std::clamp(k.constant + k.length * length + k.velocity * rate, bounds.lower, bounds.upper);
}

}  // namespace linx
