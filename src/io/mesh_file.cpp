// Reading OBJ and STL meshes (io/mesh_file.hpp).
#include "io/mesh_file.hpp"

#include "io/input_file.hpp"
#include "io/quoting.hpp"
#include "io/text_number.hpp"

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
#include <limits>
#include <map>
#include <optional>
#include <stdexcept>
#include <string_view>
#include <vector>

namespace linx::io {

namespace {

[[noreturn]] void fail(const std::string& path, const std::string& problem) {
  throw std::runtime_error(fmt::format("mesh file {}: {}", visible(path), problem));
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

/// The lines of a text, split at "\n", "\r\n" or a lone "\r" (as tinyobjloader splits an OBJ's, so
/// that the line numbers agree).
std::vector<std::string_view> textLines(std::string_view text) {
  std::vector<std::string_view> lines;
  std::size_t begin = 0;
  while (begin < text.size()) {
    const std::size_t end = std::min(text.find_first_of("\r\n", begin), text.size());
    lines.push_back(text.substr(begin, end - begin));
    begin = end + 1;
    if (end + 1 < text.size() && text[end] == '\r' && text[end + 1] == '\n') ++begin;
  }
  return lines;
}

/// A line's words, split at spaces and tabs.
std::vector<std::string_view> lineWords(std::string_view line) {
  std::vector<std::string_view> words;
  std::size_t begin = line.find_first_not_of(" \t");
  while (begin != std::string_view::npos) {
    const std::size_t end = std::min(line.find_first_of(" \t", begin), line.size());
    words.push_back(line.substr(begin, end - begin));
    begin = line.find_first_not_of(" \t", end);
  }
  return words;
}

void checkFinite(const std::string& path, const Vec3& p, std::size_t triangle) {
  if (!p.allFinite()) fail(path, fmt::format("triangle {} has a non-finite coordinate", triangle));
}

void readBinaryStl(const std::string& path, const std::string& bytes, ShapeDef& mesh) {
  std::uint32_t count = 0;
  std::memcpy(&count, bytes.data() + 80, 4);  // little-endian on the platforms we build for
  const std::uint64_t expected = 84 + 50ull * count;
  if (bytes.size() < expected)
    fail(path,
         fmt::format("truncated binary STL: {} triangle{} need{} {} bytes, the file has {}", count,
                     count == 1 ? "" : "s", count == 1 ? "s" : "", expected, bytes.size()));
  if (bytes.size() > expected)  // a count short of the data: which of the two is wrong is unknown
    fail(path,
         fmt::format("binary STL: {} triangle{} need{} {} bytes (84 + 50 per triangle), "
                     "the file has {}: the triangle count does not match the data",
                     count, count == 1 ? "" : "s", count == 1 ? "s" : "", expected, bytes.size()));
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
  VertexWelder welder;
  std::vector<int> corners;
  std::size_t loop_start = 0;  // corners before the current facet's loop
  bool ended = false;
  const std::vector<std::string_view> lines = textLines(text);
  for (std::size_t number = 1; number <= lines.size() && !ended; ++number) {
    const auto words = lineWords(lines[number - 1]);
    if (words.empty()) continue;
    const auto bad = [&](const std::string& problem) {
      fail(path, fmt::format("ASCII STL line {}: {}", number, problem));
    };
    if (words[0] == "vertex") {
      if (words.size() != 4)
        bad(fmt::format("a vertex needs 3 coordinates, got {}", words.size() - 1));
      Vec3 p;
      for (int k = 0; k < 3; ++k) {
        const auto x = finiteNumber(words[static_cast<std::size_t>(k) + 1]);
        if (!x)
          bad(fmt::format("vertex coordinate '{}' is not a finite number",
                          words[static_cast<std::size_t>(k) + 1]));
        p[k] = *x;
      }
      corners.push_back(welder.index(p));
    } else if (words[0] == "endloop") {
      if (corners.size() - loop_start != 3)
        bad(fmt::format("a facet needs 3 vertices, got {}", corners.size() - loop_start));
      loop_start = corners.size();
    } else if (words[0] == "endsolid") {
      ended = true;
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
      (bytes.find("facet") != std::string::npos || bytes.find("endsolid") != std::string::npos))
    return readAsciiStl(path, bytes, mesh);
  if (bytes.size() < 84)
    fail(path,
         fmt::format("truncated binary STL: {} bytes, less than the 84-byte header", bytes.size()));
  readBinaryStl(path, bytes, mesh);  // refuses the size mismatch
}

/// An OBJ index: an integer, '+' allowed as atoi allows it. One beyond long long is clamped (it is
/// out of range whatever the file); not an integer: nullopt.
std::optional<long long> objIndex(std::string_view word) {
  if (!word.empty() && word.front() == '+') word.remove_prefix(1);
  long long value = 0;
  const char* end = word.data() + word.size();
  const auto [stop, error] = std::from_chars(word.data(), end, value);
  if (word.empty() || stop != end) return std::nullopt;
  if (error == std::errc::result_out_of_range)
    return word.front() == '-' ? std::numeric_limits<long long>::min()
                               : std::numeric_limits<long long>::max();
  if (error != std::errc{}) return std::nullopt;
  return value;
}

/// tinyobjloader reads a coordinate it cannot parse (`v nan 0 0`, `v a b c`) as 0 and a missing
/// one (`v 0 0`) as 0, stops with its own text at a face index of 0 or a word (`f a b c`), and
/// wraps an index beyond an int (`f 1 2 4294967299` is vertex 3): each vertex and face line is
/// checked here first, so that a bad one is refused with its line and the file's own words.
/// Positive indices may name vertices further down (tinyobjloader checks them at the end);
/// negative ones count back from the vertices before the face.
void checkObjLines(const std::string& path, std::string_view text) {
  const std::vector<std::string_view> lines = textLines(text);
  long long total = 0;
  for (std::string_view line : lines) {
    const auto words = lineWords(line);
    total += !words.empty() && words[0] == "v";
  }
  long long before = 0;  // vertices above the current line
  for (std::size_t number = 1; number <= lines.size(); ++number) {
    const auto words = lineWords(lines[number - 1]);
    if (words.empty()) continue;
    const auto bad = [&](const std::string& problem) {
      fail(path, fmt::format("OBJ line {}: {}", number, problem));
    };
    if (words[0] == "v") {
      for (std::size_t k = 1; k < words.size(); ++k)
        if (!finiteNumber(words[k]))
          bad(fmt::format("vertex coordinate '{}' is not a finite number", words[k]));
      if (words.size() < 4)
        bad(fmt::format("a vertex needs 3 coordinates, got {}", words.size() - 1));
      ++before;
    } else if (words[0] == "f") {
      if (words.size() < 4)
        bad(fmt::format("a face needs at least 3 vertices, got {}", words.size() - 1));
      if (words.size() - 1 > kMaxObjFaceVertices)
        bad(
            fmt::format("a face of {} vertices, above the limit of {} (triangulating a face takes "
                        "time growing with the square of its vertices); split it into smaller "
                        "faces",
                        words.size() - 1, kMaxObjFaceVertices));
      std::vector<long long> corners;
      for (std::size_t k = 1; k < words.size(); ++k) {
        const std::string_view word = words[k];
        // v, v/vt, v//vn or v/vt/vn
        std::vector<std::string_view> parts;
        for (std::size_t begin = 0;;) {
          const std::size_t slash = word.find('/', begin);
          parts.push_back(
              word.substr(begin, slash == std::string_view::npos ? slash : slash - begin));
          if (slash == std::string_view::npos) break;
          begin = slash + 1;
        }
        const bool shaped = parts.size() <= 3 && !parts[0].empty() &&
                            (parts.size() != 2 || !parts[1].empty()) &&
                            (parts.size() != 3 || !parts[2].empty());
        std::array<std::optional<long long>, 3> index{};
        for (std::size_t p = 0; shaped && p < parts.size(); ++p)
          if (!parts[p].empty()) index[p] = objIndex(parts[p]);
        const bool integers = shaped && index[0] &&
                              (parts.size() < 2 || parts[1].empty() || index[1]) &&
                              (parts.size() < 3 || index[2]);
        if (!integers) bad(fmt::format("'{}' is not a vertex index", word));
        static constexpr std::array<const char*, 3> kWhat{"face", "texture coordinate", "normal"};
        for (std::size_t p = 0; p < 3; ++p)
          if (index[p] && *index[p] == 0)
            bad(fmt::format("{} index 0 (indices start at 1)", kWhat[p]));
        const long long v = *index[0];
        if (v > 0 && v > total)
          bad(total == 0 ? fmt::format("vertex index {}, but the file has no vertices", parts[0])
                         : fmt::format("vertex index {} out of range [1, {}]", parts[0], total));
        if (v < 0 && v < -before)
          bad(before == 0
                  ? fmt::format("vertex index {} counts back from no vertex (none comes before it)",
                                parts[0])
                  : fmt::format("vertex index {} out of range [-{}, -1] (counting back from the "
                                "{} vertices before it)",
                                parts[0], before, before));
        const long long corner = v > 0 ? v - 1 : before + v;
        if (std::find(corners.begin(), corners.end(), corner) != corners.end())
          bad(fmt::format("the face repeats vertex {}", corner + 1));
        corners.push_back(corner);
      }
    }
  }
}

void readObj(const std::string& path, ShapeDef& mesh, ObjPolygons polygons) {
  const std::string text = readAll(path);
  checkObjLines(path, text);  // bad numbers and indices: with our messages
  tinyobj::ObjReader reader;
  tinyobj::ObjReaderConfig config;
  config.triangulate = polygons == ObjPolygons::EarClipped;
  config.vertex_color = false;
  // From the text read (the file checked is the file parsed); materials are not used.
  if (!reader.ParseFromString(text, "", config)) {
    // Not its text (it speaks of its own parser): the line it names, if any.
    const std::string& error = reader.Error();
    const auto at = error.find("line");
    const auto digits = error.find_first_of("0123456789", at);
    if (at == std::string::npos || digits == std::string::npos) fail(path, "OBJ: cannot read it");
    const auto end = error.find_first_not_of("0123456789", digits);
    fail(path, fmt::format("OBJ line {}: cannot read it", error.substr(digits, end - digits)));
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
      // Checked line by line above: these are the library's result not matching that check.
      const std::string of = shape.name.empty() ? "" : fmt::format(" of '{}'", shape.name);
      if (n < 3 || next + n > indices.size())
        fail(path, fmt::format("OBJ: face {}{} has {} vertices", f + 1, of, n));
      std::vector<int> face;
      for (std::size_t k = 0; k < n; ++k) {
        const int index = indices[next + k].vertex_index;
        if (index < 0 || index >= count)
          fail(path, fmt::format("OBJ: face {}{} has vertex index {} out of range [1, {}]", f + 1,
                                 of, index + 1, count));
        face.push_back(index);
      }
      next += n;
      for (std::size_t k = 1; k + 1 < face.size(); ++k)  // a fan (ObjPolygons::Fanned)
        mesh.triangles.push_back({face[0], face[k], face[k + 1]});
    }
  }
}

}  // namespace

ShapeDef loadMeshFile(const std::string& path, ObjPolygons polygons) {
  ShapeDef mesh;
  mesh.type = ShapeType::Mesh;
  mesh.file = path;
  const std::string ext = lowerExtension(path);
  if (ext == "obj")
    readObj(path, mesh, polygons);
  else if (ext == "stl")
    readStl(path, mesh);
  else
    fail(path, fmt::format("unknown extension '{}' (expected .obj or .stl)", ext));
  if (mesh.triangles.empty()) fail(path, "no triangles");
  return mesh;
}

}  // namespace linx::io
