// The scene reader and the world builder on arbitrary text: every input either builds a world or
// is refused with SceneError (or std::invalid_argument from the engine, named by the reader);
// anything else (a crash, a sanitizer report, another exception) is a finding.
#include <linx/linx.hpp>

#include "fuzz_input.hpp"

#include <cstddef>
#include <cstdint>
#include <string_view>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const std::string file = (linx::fuzz::folder() / "scene.json").string();
  try {
    const linx::Scene scene =
        linx::parseScene(std::string_view(reinterpret_cast<const char*>(data), size), file);
    linx::World world = linx::buildWorld(scene);
    world.step();
  } catch (const linx::SceneError&) {
  } catch (const linx::StepFault&) {
  }
  return 0;
}
