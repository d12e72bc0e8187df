// A World's actuators (linx/actuator.hpp): their definitions, their controls, and what they make
// of the coordinates they act on. At each step's start a control given as a table takes its
// value; then each actuated coordinate's motor and force are set from its actuators at their
// clamped controls (Joint::setMotor and setForce), where that changed since the last step.
#pragma once

#include <linx/actuator.hpp>

#include <cstddef>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <unordered_map>
#include <vector>

namespace linx {

class World;

class Actuators {
 public:
  /// Checks `def` against the world (throws std::invalid_argument) and adds it.
  ActuatorId add(const ActuatorDef& def, World& world);
  int count() const { return static_cast<int>(defs_.size()); }
  /// Throws std::out_of_range for an id that is not one of these.
  const ActuatorDef& def(ActuatorId id) const;
  std::optional<ActuatorId> find(std::string_view name) const;
  std::span<double> controls() { return controls_; }
  std::span<const double> controls() const { return controls_; }
  void setControl(ActuatorId id, double value);
  /// Before a step at time t: tables' controls, then the coordinates' motors and forces. Throws
  /// std::invalid_argument for a control that is not finite.
  void apply(World& world, double t);
  /// F at the world's current state and the actuator's control (0 once its joint is removed).
  double force(ActuatorId id, const World& world) const;

 private:
  // The terms of F at one control: F = constant + length L + velocity L'.
  struct Terms {
    double constant = 0.0, length = 0.0, velocity = 0.0;
  };
  // The actuators on one coordinate, and what was last set on it.
  struct Coordinate {
    JointId joint;
    int coordinate = 0;
    std::vector<int> actuators;
    bool set = false;
    std::optional<JointMotor> motor;
    double force = 0.0;
  };

  std::size_t checked(ActuatorId id) const;
  double clampedControl(std::size_t i) const;
  Terms terms(std::size_t i) const;

  std::vector<ActuatorDef> defs_;
  std::vector<double> controls_;
  std::vector<bool> scheduled_;  // the control follows its table
  std::vector<Coordinate> coordinates_;
  std::unordered_map<std::string, int> names_;
};

}  // namespace linx
