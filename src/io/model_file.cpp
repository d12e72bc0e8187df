// Model files of every format linx reads, told apart by their extension.
#include <linx/import.hpp>

#include <algorithm>
#include <cctype>
#include <string>

namespace linx {

Scene loadModel(const std::filesystem::path& path, const ImportOptions& options) {
  std::string extension = path.extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (extension == ".urdf") return importUrdf(path, options);
  if (extension == ".xml") return importMjcf(path, options);
  return loadScene(path, options);
}

}  // namespace linx
