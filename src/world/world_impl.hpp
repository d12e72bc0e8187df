// What a World keeps beyond its bodies and joints: slots, the step's state, the fault check,
// name lookups, standing loads, kinematic paths, the force callback and the actuators (world.cpp, and
// world_state.cpp for saveState and restoreState).
#pragma once

#include <linx/world.hpp>

#include "step/check.hpp"
#include "step/step.hpp"
#include "world/actuators.hpp"
#include "world/applied_loads.hpp"
#include "world/slots.hpp"

#include <functional>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

namespace linx {

struct World::Impl {
  Slots body_slots, joint_slots;
  step::State step;
  step::FaultCheck check;
  // Names to indices: a scene of 64,000 bodies would otherwise spend seconds in duplicate checks.
  std::unordered_map<std::string, int> body_names, joint_names;
  AppliedLoads loads;
  std::vector<std::pair<int, VectorSignal>> paths;  // kinematic bodies' paths
  std::function<void(World&)> force_callback;
  Actuators actuators;
};

}  // namespace linx
