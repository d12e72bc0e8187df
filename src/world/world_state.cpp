// World::saveState and restoreState (docs/reliability.md, "Checkpoints"): the world's state between
// steps, each part listed once in a persist(state::Archive&) of its own, behind a description of
// the world's structure that a restore checks first.
#include <linx/world.hpp>

#include "world/state_archive.hpp"
#include "world/world_impl.hpp"

#include <fmt/format.h>

#include <stdexcept>
#include <string>

namespace linx {

namespace {

constexpr std::uint32_t kStateMagic = 0x7473'786c;  // "lxst" in little-endian bytes
constexpr std::uint32_t kStateVersion =
    4;  // 2: the accurate integrator's step size; 3: auto's waits; 4: the held limits

// What a state must match to be put in a world: its bodies (slot and name), its joints (slot,
// type and name) and its standing loads.
std::string structure(const World& world) {
  std::string text = fmt::format("{} body slots:", world.bodyCount());
  for (const BodyId id : world.bodyIds())
    text += fmt::format(" {}={}", id.index, world.body(id).name());
  text += fmt::format("; {} joint slots:", world.jointCount());
  for (const JointId id : world.jointIds())
    text += fmt::format(" {}={}:{}", id.index, world.joint(id).type(), world.joint(id).name());
  return text + fmt::format("; {} loads", world.loadCount());
}

}  // namespace

void World::persist(state::Archive& a) {
  a(time_);
  a(steps_);
  a(clock_origin_);
  a(clock_step_);
  a(clock_steps_);
  a(report_.rows);
  a(report_.iterations);
  a(report_.residual);
  a(report_.redundant_rows);
  a(report_.converged);
  std::uint64_t breaks = breaks_.size();
  a(breaks);
  if (a.loading()) breaks_.resize(a.checkedCount(breaks, 1));
  for (JointBreak& b : breaks_) {
    a(b.joint.index);
    a(b.joint.generation);
    a(b.step);
    a(b.time);
    a(b.reaction.force);
    a(b.reaction.torque);
  }
  a.fields(faults_, fault_count_);
  for (Body& b : bodies_) {
    a(b.pose_);
    a(b.v_);
    a(b.w_);
    a(b.force_);
    a(b.torque_);
  }
  for (std::unique_ptr<Joint>& j : joints_) a(*j);
  a(impl_->check);
  a(impl_->step);
}

WorldState World::saveState() const {
  WorldState state;
  state::Archive a = state::Archive::writer(state.bytes);
  std::uint32_t magic = kStateMagic, version = kStateVersion;
  std::string shape = structure(*this);
  a(magic);
  a(version);
  a(shape);
  const_cast<World*>(this)->persist(a);  // a writer only reads the world
  return state;
}

void World::restoreState(const WorldState& state) {
  // Read into a copy of the state's parts first, so that a damaged state leaves the world as it
  // was: the world's own state is saved, then put back if reading fails.
  const WorldState before = saveState();
  try {
    state::Archive a = state::Archive::reader(state.bytes);
    std::uint32_t magic = 0, version = 0;
    std::string shape;
    a(magic);
    a(version);
    if (magic != kStateMagic) throw state::StateError("not a linx world state");
    if (version != kStateVersion)
      throw state::StateError(
          fmt::format("a state of version {}; this linx reads version {}", version, kStateVersion));
    a(shape);
    if (shape != structure(*this))
      throw state::StateError(fmt::format("the state is of another world ({}); this one has {}",
                                          shape, structure(*this)));
    persist(a);
    if (!a.atEnd()) throw state::StateError("the state has more in it than this world holds");
  } catch (const state::StateError& e) {
    state::Archive back = state::Archive::reader(before.bytes);
    std::uint32_t skip = 0;
    std::string shape;
    back(skip);
    back(skip);
    back(shape);
    persist(back);
    throw std::invalid_argument(fmt::format("restoreState: {}", e.what()));
  }
}

}  // namespace linx
