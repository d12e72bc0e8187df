// URDF (through urdfdom) and MJCF import on arbitrary text (the first byte picks the format), then
// the world built from what they read: a world, or a SceneError.
#include <linx/linx.hpp>

#include "fuzz_input.hpp"

#include <cstddef>
#include <cstdint>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  const bool urdf = data[0] % 2 == 0;
  const auto path = linx::fuzz::asFile(data + 1, size - 1, urdf ? "model.urdf" : "model.xml");
  try {
    const linx::Scene scene = urdf ? linx::importUrdf(path) : linx::importMjcf(path);
    linx::World world = linx::buildWorld(scene);
    world.step();
  } catch (const linx::SceneError&) {
  } catch (const linx::StepFault&) {
  }
  return 0;
}
