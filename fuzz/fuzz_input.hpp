// What every fuzz harness shares: the input written to a file of its own (the readers take
// paths), in a folder of the process's own, so that paths the input names stay inside it.
#pragma once

#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>

namespace linx::fuzz {

/// This process's own folder under /tmp.
inline const std::filesystem::path& folder() {
  static const std::filesystem::path f = [] {
    std::filesystem::path made = std::filesystem::temp_directory_path() /
                                 ("linx-fuzz-" + std::to_string(::getpid()));
    std::filesystem::create_directories(made);
    return made;
  }();
  return f;
}

/// The input as the file `name` in folder(); returns its path.
inline std::filesystem::path asFile(const std::uint8_t* data, std::size_t size,
                                    const std::string& name) {
  const std::filesystem::path path = folder() / name;
  std::ofstream(path, std::ios::binary | std::ios::trunc)
      .write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  return path;
}

}  // namespace linx::fuzz
