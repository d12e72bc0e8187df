// Triangle meshes from files: Wavefront OBJ (through tinyobjloader; polygons with more than 3
// vertices are fanned into triangles) and STL, binary or ASCII (read here: STL is a flat list of
// triangles, 50 bytes each after an 80-byte header and a 32-bit count in the binary form). STL
// repeats each corner per triangle; identical corners are merged into one vertex so that
// neighbouring triangles share their edges (the mesh collider needs the adjacency to smooth
// internal edges). Triangles keep the file's winding (counter-clockwise seen from outside).
#pragma once

#include <linx/shape.hpp>

#include <cstddef>
#include <string>

namespace linx::io {

/// The most vertices an OBJ face may have: tinyobjloader's ear clipping takes time growing with
/// the square of a face's vertices, so that one face of 400,000 took minutes; with this bound the
/// time to read a file grows linearly with its size. Larger faces are refused with their line.
inline constexpr std::size_t kMaxObjFaceVertices = 64;

/// A Mesh shape (type, points, triangles, file) read from an .obj or .stl file (by extension,
/// case-insensitive). Throws std::runtime_error naming the file and the problem: missing or
/// unreadable, empty, a binary STL whose size is not 84 + 50 per triangle counted, malformed ASCII
/// STL or OBJ (with the line, and the file's own words: `OBJ line 4: face index 0 (indices start at
/// 1)`), a vertex index out of range, a face of more than kMaxObjFaceVertices vertices, non-finite
/// coordinates, no triangles, an unknown extension.
///
/// `polygons`: how an OBJ polygon of more than three corners becomes triangles: by tinyobjloader's
/// ear clipping (right for concave polygons), or as a fan from its first corner, as MuJoCo splits
/// quads (0 1 2, 0 2 3; the same solid, but MuJoCo's single-precision inertia sums depend on it).
enum class ObjPolygons { EarClipped, Fanned };
ShapeDef loadMeshFile(const std::string& path, ObjPolygons polygons = ObjPolygons::EarClipped);

}  // namespace linx::io
