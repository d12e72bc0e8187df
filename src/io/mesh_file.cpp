// Reading OBJ and STL meshes (io/mesh_file.hpp).
#include "io/mesh_file.hpp"

#include "io/input_file.hpp"

#include <fmt/format.h>
#include <tiny_obj_loader.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <iterator>
#include <map>
#include <sstream>
#include <stdexcept>
#include <vector>

namespace linx::io {

namespace {

[[noreturn]] void fail(const std::string& path, const std::string& problem) {
  throw std::runtime_error(fmt::format("mesh file {}: {}", path, problem));
}

std::string lowerExtension(const std::string& path) {
  const auto dot = path.find_last_of('.');
  const auto slash = path.find_last_of("/\\");
  if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) return {};
  std::string ext = path.substr(dot + 1);
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return ext;
}

std::string readAll(const std::string& path) {
  std::string bytes;
  try {
    bytes = readInputFile(path, kMeshLimit, "a mesh");
  } catch (const std::runtime_error& e) {
    fail(path, e.what());
  }
  if (bytes.empty()) fail(path, "the file is empty");
  return bytes;
}

/// Merges identical corners into shared vertices.
class VertexWelder {
 public:
  int index(const Vec3& p) {
    const std::array<double, 3> key{p.x(), p.y(), p.z()};
    const auto [it, inserted] = ids_.emplace(key, static_cast<int>(points.size()));
    if (inserted) points.push_back(p);
    return it->second;
  }
  std::vector<Vec3> points;

 private:
  std::map<std::array<double, 3>, int> ids_;
};

void checkFinite(const std::string& path, const Vec3& p, std::size_t triangle) {
  if (!p.allFinite()) fail(path, fmt::format("triangle {} has a non-finite coordinate", triangle));
}

void readBinaryStl(const std::string& path, const std::string& bytes, ShapeDef& mesh) {
  std::uint32_t count = 0;
  std::memcpy(&count, bytes.data() + 80, 4);  // little-endian on the platforms we build for
  const std::uint64_t expected = 84 + 50ull * count;
  if (bytes.size() < expected)
    fail(path, fmt::format("truncated binary STL: {} triangles need {} bytes, the file has {}",
                           count, expected, bytes.size()));
  VertexWelder welder;
  for (std::uint32_t t = 0; t < count; ++t) {
    const char* record = bytes.data() + 84 + 50ull * t;  // normal, 3 corners, attribute
    std::array<int, 3> tri{};
    for (int k = 0; k < 3; ++k) {
      float xyz[3];
      std::memcpy(xyz, record + 12 + 12 * k, 12);
      const Vec3 p(xyz[0], xyz[1], xyz[2]);
      checkFinite(path, p, t);
      tri[k] = welder.index(p);
    }
    mesh.triangles.push_back(tri);
  }
  mesh.points = std::move(welder.points);
}

void readAsciiStl(const std::string& path, const std::string& text, ShapeDef& mesh) {
  std::istringstream in(text);
  std::string word;
  VertexWelder welder;
  std::vector<int> corners;
  bool ended = false;
  while (in >> word) {
    if (word == "vertex") {
      double x = 0, y = 0, z = 0;
      if (!(in >> x >> y >> z))
        fail(path, fmt::format("ASCII STL: vertex {} is not three numbers", corners.size()));
      const Vec3 p(x, y, z);
      checkFinite(path, p, corners.size() / 3);
      corners.push_back(welder.index(p));
    } else if (word == "endloop") {
      if (corners.size() % 3 != 0)
        fail(path, fmt::format("ASCII STL: facet {} does not have 3 vertices", corners.size() / 3));
    } else if (word == "endsolid") {
      ended = true;
      break;
    }
  }
  if (!ended) fail(path, "ASCII STL: truncated (no endsolid)");
  if (corners.size() % 3 != 0) fail(path, "ASCII STL: the vertex count is not a multiple of 3");
  for (std::size_t i = 0; i < corners.size(); i += 3)
    mesh.triangles.push_back({corners[i], corners[i + 1], corners[i + 2]});
  mesh.points = std::move(welder.points);
}

void readStl(const std::string& path, ShapeDef& mesh) {
  const std::string bytes = readAll(path);
  // Binary when the size matches its triangle count; ASCII starts with "solid" (some binary
  // files do too, hence the size test first).
  if (bytes.size() >= 84) {
    std::uint32_t count = 0;
    std::memcpy(&count, bytes.data() + 80, 4);
    if (bytes.size() == 84 + 50ull * count) return readBinaryStl(path, bytes, mesh);
  }
  const auto first = bytes.find_first_not_of(" \t\r\n");
  if (first != std::string::npos && bytes.compare(first, 5, "solid") == 0 &&
      bytes.find("facet") != std::string::npos)
    return readAsciiStl(path, bytes, mesh);
  if (bytes.size() < 84)
    fail(path,
         fmt::format("truncated binary STL: {} bytes, less than the 84-byte header", bytes.size()));
  readBinaryStl(path, bytes, mesh);  // reports the size mismatch
}

/// tinyobjloader reads a coordinate it cannot parse (`v nan 0 0`, `v a b c`) as 0: each vertex
/// line's numbers are checked first, so a bad one is refused with its line.
void checkObjVertices(const std::string& path, const std::string& bytes) {
  std::istringstream lines(bytes);
  std::string line;
  for (int number = 1; std::getline(lines, line); ++number) {
    std::istringstream words(line);
    std::string tag;
    if (!(words >> tag) || tag != "v") continue;
    std::string word;
    while (words >> word) {
      double value = 0.0;
      const char* begin = word.data() + (word.front() == '+' ? 1 : 0);  // from_chars takes no '+'
      const char* end = word.data() + word.size();
      const auto [stop, error] = std::from_chars(begin, end, value);
      if (error != std::errc{} || stop != end || !std::isfinite(value))
        fail(path, fmt::format("OBJ: line {}: vertex coordinate '{}' is not a finite number",
                               number, word));
    }
  }
}

void readObj(const std::string& path, ShapeDef& mesh) {
  const std::string text = readAll(path);
  checkObjVertices(path, text);  // missing / empty, bad numbers: with our messages
  tinyobj::ObjReader reader;
  tinyobj::ObjReaderConfig config;
  config.triangulate = true;
  config.vertex_color = false;
  // From the text read (the file checked is the file parsed); materials are not used.
  if (!reader.ParseFromString(text, "", config)) {
    std::string error = reader.Error();
    while (!error.empty() && (error.back() == '\n' || error.back() == '\r')) error.pop_back();
    fail(path, fmt::format("OBJ: {}", error.empty() ? "cannot parse it" : error));
  }
  const auto& v = reader.GetAttrib().vertices;
  const int count = static_cast<int>(v.size() / 3);
  for (int i = 0; i < count; ++i) {
    const Vec3 p(v[3 * i], v[3 * i + 1], v[3 * i + 2]);
    if (!p.allFinite()) fail(path, fmt::format("OBJ: vertex {} is not finite", i + 1));
    mesh.points.push_back(p);
  }
  for (const tinyobj::shape_t& shape : reader.GetShapes()) {
    const auto& indices = shape.mesh.indices;
    std::size_t next = 0;
    for (std::size_t f = 0; f < shape.mesh.num_face_vertices.size(); ++f) {
      const std::size_t n = shape.mesh.num_face_vertices[f];
      if (n < 3 || next + n > indices.size())
        fail(path, fmt::format("OBJ: face {} of '{}' has {} vertices", f + 1, shape.name, n));
      std::vector<int> face;
      for (std::size_t k = 0; k < n; ++k) {
        const int index = indices[next + k].vertex_index;
        if (index < 0 || index >= count)
          fail(path, fmt::format("OBJ: face {} of '{}' has vertex index {} out of range [1, {}]",
                                 f + 1, shape.name, index + 1, count));
        face.push_back(index);
      }
      next += n;
      for (std::size_t k = 1; k + 1 < face.size(); ++k)  // a fan, should any polygon remain
        mesh.triangles.push_back({face[0], face[k], face[k + 1]});
    }
  }
}

}  // namespace

ShapeDef loadMeshFile(const std::string& path) {
  ShapeDef mesh;
  mesh.type = ShapeType::Mesh;
  mesh.file = path;
  const std::string ext = lowerExtension(path);
  if (ext == "obj")
    readObj(path, mesh);
  else if (ext == "stl")
    readStl(path, mesh);
  else
    fail(path, fmt::format("unknown extension '{}' (expected .obj or .stl)", ext));
  if (mesh.triangles.empty()) fail(path, "no triangles");
  return mesh;
}

}  // namespace linx::io
