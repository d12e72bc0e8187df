// Actuators: a force on one joint coordinate that a control value sets (MuJoCo's actuators with a
// joint transmission). docs/joints.md, "Actuators".
#pragma once

#include <linx/joint.hpp>
#include <linx/signal.hpp>

#include <optional>
#include <string>

namespace linx {

/// A closed interval; either end may be infinite.
struct ActuatorRange {
  double lower = -kInfinity;
  double upper = kInfinity;
  friend bool operator==(const ActuatorRange&, const ActuatorRange&) = default;
};

/// An actuator on free coordinate `coordinate` of a joint (its value x, with the coordinate's
/// reference). Its length is L = gear x; its force, at control u,
///   F = (gain + gain_length L + gain_velocity L') u + bias + bias_length L + bias_velocity L',
/// bounded by force_range, acts on the coordinate as gear F (N or N m). u is the control clamped to
/// control_range. A position servo of stiffness kp and damping kv is gain kp, bias_length -kp,
/// bias_velocity -kv (towards x = u / gear); a velocity servo gain kv, bias_velocity -kv; a motor
/// gain 1. Terms that grow with L or L' must not push away (the coefficient of L and of L' is <= 0
/// at every control): they act as a spring and damper, integrated implicitly like a JointMotor
/// servo (stable at any gain). The actuator owns its coordinate's motor and force: the
/// coordinate must have neither, and carries at most one actuator with length or velocity terms
/// (forces of several add).
struct ActuatorDef {
  std::string name{};
  JointId joint{};  ///< in a Scene: the index of the joint in Scene::joints
  int coordinate = 0;
  double gear = 1.0;
  double gain = 1.0, gain_length = 0.0, gain_velocity = 0.0;
  double bias = 0.0, bias_length = 0.0, bias_velocity = 0.0;
  std::optional<ActuatorRange> control_range = std::nullopt;
  std::optional<ActuatorRange> force_range = std::nullopt;
  /// The control: a number (its value until World::setControl changes it), or a table in time
  /// (taken at each step's start, until setControl replaces it by a number).
  Signal control = 0.0;

  /// Whether its force changes with its length or rate (a servo or damper, not a force alone).
  bool isServo() const {
    return gain_length != 0.0 || gain_velocity != 0.0 || bias_length != 0.0 || bias_velocity != 0.0;
  }
};

/// An actuator of a World: its place in the order of creation (the order of World::controls).
struct ActuatorId {
  int index = -1;
  friend bool operator==(ActuatorId, ActuatorId) = default;
};

}  // namespace linx
