// Checks of a joint definition against what its type takes, shared by creation and the setters.
#pragma once

#include <linx/joint.hpp>

namespace linx::joints {

/// Throws std::invalid_argument naming the field: a non-finite anchor, a zero axis, erp outside
/// [0, 1], a negative cfm, limits or a motor on a type without a coordinate, inverted limits, a
/// negative or non-finite motor force.
void validate(const JointTypeInfo& type, const JointDef& def);

}  // namespace linx::joints
