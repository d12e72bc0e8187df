// The OBJ and STL readers on arbitrary bytes (the first byte picks the format): a mesh, or a
// std::runtime_error naming the file and the problem.
#include "io/mesh_file.hpp"

#include "fuzz_input.hpp"

#include <cstddef>
#include <cstdint>
#include <stdexcept>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  const char* name = data[0] % 2 == 0 ? "mesh.obj" : "mesh.stl";
  const auto path = linx::fuzz::asFile(data + 1, size - 1, name);
  try {
    linx::io::loadMeshFile(path.string());
  } catch (const std::runtime_error&) {
  }
  return 0;
}
