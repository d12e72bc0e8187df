// Model files of every format linx reads, told apart by their extension.
#include <linx/import.hpp>

#include "io/joint_warnings.hpp"

#include <algorithm>
#include <cctype>
#include <string>
#include <utility>

namespace linx {

Scene loadModel(const std::filesystem::path& path, const ImportOptions& options) {
  std::string extension = path.extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  Scene scene = extension == ".urdf"  ? importUrdf(path, options)
                : extension == ".xml" ? importMjcf(path, options)
                                      : loadScene(path, options);
  for (std::string& warning : io::jointWarnings(scene))
    scene.warnings.push_back(std::move(warning));
  return scene;
}

}  // namespace linx
