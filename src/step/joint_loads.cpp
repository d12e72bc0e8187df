#include "step/joint_loads.hpp"

#include "world/state_archive.hpp"

namespace linx::step {

void JointLoads::measure(std::span<const Row> rows, std::span<const double> lambda, double h,
                         std::span<const std::unique_ptr<Joint>> joints,
                         std::span<const Body> bodies, bool add) {
  // J^T lambda / h on body1: its force, and its torque about body1's centre of mass...
  if (!add || loads_.size() != joints.size()) loads_.assign(joints.size(), JointReaction{});
  measured_.assign(joints.size(), JointReaction{});
  for (std::size_t k = 0; k < rows.size(); ++k) {
    const std::size_t owner = static_cast<std::size_t>(rows[k].key >> 8);
    if (owner == 0 || owner > joints.size()) continue;  // not a joint's row
    JointReaction& load = measured_[owner - 1];
    const double f = lambda[k] / h;
    load.force += f * rows[k].Ja.head<3>();
    load.torque += f * rows[k].Ja.tail<3>();
  }
  // ... taken about the anchor instead: tau_anchor = tau_centre - r x F, r = anchor - centre.
  for (std::size_t j = 0; j < joints.size(); ++j) {
    const Body& body1 = bodies[static_cast<std::size_t>(joints[j]->body1().index)];
    const Vec3 arm = body1.orientation() * joints[j]->anchor1();
    loads_[j].force += measured_[j].force;
    loads_[j].torque += measured_[j].torque - arm.cross(measured_[j].force);
  }
}

void JointLoads::persist(state::Archive& a) {
  const auto reaction = [](state::Archive& a, JointReaction& r) { a.fields(r.force, r.torque); };
  a.each(loads_, reaction);
  a.each(measured_, reaction);
}

}  // namespace linx::step
