// Checks of a joint definition against what its type takes, shared by creation and the setters.
#pragma once

#include <linx/joint.hpp>

#include <string>
#include <string_view>
#include <vector>

namespace linx::joints {

/// Throws std::invalid_argument naming the field: a non-finite anchor, a zero axis, erp outside
/// [0, 1], a negative cfm, a coordinate the type does not have, and what validateCoordinate
/// refuses.
void validate(const JointTypeInfo& type, const JointDef& def);
/// A serial joint's axes: 1 to kMaxCoordinates, each a finite non-zero direction with a finite
/// anchor (their independence is checked by the joint, which knows the bodies).
void validateAxes(const std::vector<SerialAxis>& axes);
/// Inverted limits, negative friction, and what validateMotor and validateSpring refuse; `prefix`
/// starts the message ("angle1." or nothing).
void validateCoordinate(const CoordinateDef& coordinate, const std::string& prefix);
/// A coordinate that takes limits only (CoordinateInfo::limits_only): anything else on it, a lower
/// bound above zero, an upper one outside [0, pi).
void limitsOnly(const JointTypeInfo& type, const CoordinateDef& coordinate,
                const std::string& prefix);
/// A constant that is not finite, a table whose times do not increase or whose lengths differ;
/// `field` names it in the message.
void validateSignal(const Signal& signal, std::string_view field);
/// A negative max_force, a bad target (validateSignal), negative or non-finite gains, a servo
/// (target_position) without stiffness, a stiffness without a target_position.
void validateMotor(const JointMotor& motor);
/// Negative or non-finite stiffness or damping, a non-finite rest position.
void validateSpring(const JointSpring& spring);

}  // namespace linx::joints
