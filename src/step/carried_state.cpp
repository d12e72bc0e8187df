// What the step carries from one step to the next (step::State::persist, for World::saveState):
// each stage's persist lists its own.
#include "step/step.hpp"

#include "world/state_archive.hpp"

namespace linx::step {

void State::persist(state::Archive& a) {
  a.fields(joint_warm, joint_loads, contact, islands, sleep, stabilization, geometric_stiffness,
           last_joint_impulses, accurate, choice, behind);
  // The state restored is the one the saved pass left: none was set since.
  if (a.loading()) left.clear();
}

}  // namespace linx::step
