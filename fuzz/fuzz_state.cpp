// World::restoreState on arbitrary bytes (a damaged checkpoint past its checksum), into a world of
// joints and contacts, then two steps: a restore either takes the state or throws
// std::invalid_argument leaving the world as it was; the steps either run or stop on a fault.
#include <linx/linx.hpp>

#include <cstddef>
#include <cstdint>
#include <stdexcept>

namespace {

linx::World makeWorld() {
  linx::World world;
  linx::BodyDef ground;
  ground.name = "ground";
  ground.is_static = true;
  ground.shapes.push_back(linx::ShapeDef{.type = linx::ShapeType::Plane});
  world.createBody(ground);
  linx::BodyDef box;
  box.name = "box";
  box.mass = 1.0;
  box.position = linx::Vec3(0.0, 0.0, 0.5);
  box.shapes.push_back(
      linx::ShapeDef{.type = linx::ShapeType::Box, .size = linx::Vec3(0.4, 0.4, 0.4)});
  const linx::BodyId b = world.createBody(box);
  linx::BodyDef bob = box;
  bob.name = "bob";
  bob.position = linx::Vec3(1.0, 0.0, 2.0);
  const linx::BodyId p = world.createBody(bob);
  linx::JointDef hinge;
  hinge.name = "pivot";
  hinge.body1 = p;
  hinge.anchor = linx::Vec3(0.0, 0.0, 2.0);
  hinge.axis = linx::Vec3::UnitY();
  world.createJoint("hinge", hinge);
  (void)b;
  for (int i = 0; i < 5; ++i) world.step();
  return world;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const linx::WorldState seed = makeWorld().saveState();
  linx::World world = makeWorld();
  // Half the inputs are the real state with the input written over it from its first byte's
  // offset: the checks deep inside the state are reached, not only its header.
  linx::WorldState state;
  if (size > 0 && data[0] % 2 == 0) {
    state = seed;
    const std::size_t at = size > 1 ? data[1] * state.bytes.size() / 256 : 0;
    for (std::size_t i = 2; i < size && at + i - 2 < state.bytes.size(); ++i)
      state.bytes[at + i - 2] = static_cast<std::byte>(data[i]);
  } else {
    const auto* p = reinterpret_cast<const std::byte*>(data);
    state.bytes.assign(p, p + size);
  }
  try {
    world.restoreState(state);
    world.step();
    world.step();
  } catch (const std::invalid_argument&) {
  } catch (const linx::StepFault&) {
  }
  return 0;
}
