// Triangle meshes from files: Wavefront OBJ (through tinyobjloader; polygons with more than 3
// vertices are fanned into triangles) and STL, binary or ASCII (read here: STL is a flat list of
// triangles, 50 bytes each after an 80-byte header and a 32-bit count in the binary form). STL
// repeats each corner per triangle; identical corners are merged into one vertex so that
// neighbouring triangles share their edges (the mesh collider needs the adjacency to smooth
// internal edges). Triangles keep the file's winding (counter-clockwise seen from outside).
#pragma once

#include <linx/shape.hpp>

#include <string>

namespace linx::io {

/// A Mesh shape (type, points, triangles, file) read from an .obj or .stl file (by extension,
/// case-insensitive). Throws std::runtime_error naming the file and the problem: missing or
/// unreadable, empty, truncated binary STL, malformed ASCII STL or OBJ (with the line, and the
/// file's own words: `OBJ line 4: face index 0 (indices start at 1)`), a vertex index out of
/// range, non-finite coordinates, no triangles, an unknown extension.
ShapeDef loadMeshFile(const std::string& path);

}  // namespace linx::io
