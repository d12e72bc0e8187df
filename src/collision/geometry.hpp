// Prepared collision data of the shapes that are not closed-form primitives: the convex hull of a
// Convex shape's points, and the triangles of a Mesh shape with an AABB tree over them. Preparing
// is done once per shape (it runs Qhull or builds the tree); the narrowphase then reads the result
// every step through ShapeInstance::geometry (collision/narrowphase.hpp). Everything is in the
// shape's own frame (metres).
//
// Hull: vertices, faces (convex polygons, counter-clockwise seen from outside, coplanar triangles
// merged into one polygon) with outward unit normals n and offsets d (the face plane is n.x = d
// and the solid is n.x <= d), edges with their two faces, and the volume, centroid and inertia
// per unit density of the solid hull.
//
// Mesh: vertices, triangles (counter-clockwise seen from outside), their unit normals, per-edge
// "active" flags (an edge is inactive when the neighbouring triangle is coplanar or bends upwards:
// a contact there must use the face normal, otherwise bodies bump on internal edges), and a
// bounding-volume hierarchy of AABBs with up to kLeafSize triangles per leaf.
#pragma once

#include <linx/shape.hpp>
#include <linx/types.hpp>

#include <array>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "collision/aabb.hpp"

namespace linx::collision {

/// A face of a convex hull: a convex polygon.
struct HullFace {
  std::vector<int> vertices;    ///< indices into Geometry::vertices(), counter-clockwise outside
  Vec3 normal = Vec3::UnitZ();  ///< outward unit normal
  double offset = 0.0;          ///< the face plane is normal . x = offset
};

/// An edge of a convex hull between two faces.
struct HullEdge {
  int a = 0, b = 0;          ///< vertex indices, a < b
  int face0 = 0, face1 = 0;  ///< the two faces sharing it
};

/// A node of the mesh's AABB tree: an inner node has two children, a leaf a range of triangles.
struct BvhNode {
  Aabb box;
  int left = -1, right = -1;  ///< children (inner node), -1 for a leaf
  int first = 0, count = 0;   ///< leaf: Geometry::bvhTriangles()[first, first + count)
};

class Geometry {
 public:
  enum class Kind { Convex, Mesh };
  static constexpr int kLeafSize = 4;

  /// The largest coordinate of a hull's or a mesh's points (m). A hull's second moments grow as
  /// the fifth power of its size (1e250 m^5 here, far from overflow at any sane density), Qhull's
  /// determinants as the cube, a triangle's area vector as the square: beyond it they may not be
  /// representable (1e150 m is already too far for Qhull).
  static constexpr double kMaxCoordinate = 1e50;
  /// The smallest extent of a hull's points along an axis (m): its volume and second moments,
  /// as the cube and the fifth power, underflow before 1e-62 m.
  static constexpr double kMinSize = 1e-50;

  /// The hull of the points. Throws std::invalid_argument unless there are at least 4 finite
  /// points within kMaxCoordinate, at least kMinSize apart, that span a volume (not all on one line
  /// or in one plane, nor within 1e-9 of their extent of it).
  static std::shared_ptr<const Geometry> convexHull(std::span<const Vec3> points);
  /// A triangle mesh. Throws std::invalid_argument for an index out of range, a triangle that
  /// repeats a vertex or is degenerate (zero area), no triangles, non-finite vertices or
  /// coordinates beyond kMaxCoordinate.
  static std::shared_ptr<const Geometry> mesh(std::span<const Vec3> points,
                                              std::span<const std::array<int, 3>> triangles);

  Kind kind() const { return kind_; }
  const std::vector<Vec3>& vertices() const { return vertices_; }

  // --- Convex hull ---
  const std::vector<HullFace>& faces() const { return faces_; }
  const std::vector<HullEdge>& edges() const { return edges_; }
  /// The index of a vertex maximising dir . v (the lowest index among ties).
  int supportVertex(const Vec3& dir) const;
  /// The face whose outward normal is most aligned with dir.
  int supportFace(const Vec3& dir) const;
  double volume() const { return volume_; }           ///< (m^3)
  const Vec3& centroid() const { return centroid_; }  ///< centre of volume, shape frame (m)
  /// The inertia of the solid hull of unit density about its centroid, shape-frame axes (m^5).
  const Mat3& unitInertia() const { return unit_inertia_; }

  // --- Triangle mesh ---
  const std::vector<std::array<int, 3>>& triangles() const { return triangles_; }
  const std::vector<Vec3>& triangleNormals() const { return normals_; }
  /// edgeActive(t)[k]: the edge from vertex k to vertex k+1 of triangle t is a real (convex)
  /// edge or a boundary; false when it is internal to a flat or concave region.
  const std::array<bool, 3>& edgeActive(int t) const { return edge_active_[t]; }
  /// True when the mesh vertex (an index into vertices()) lies on some active edge.
  bool vertexActive(int vertex) const { return vertex_active_[vertex] != 0; }
  const std::vector<BvhNode>& bvh() const { return nodes_; }
  const std::vector<int>& bvhTriangles() const { return tree_triangles_; }
  /// Appends to `out` the triangles whose AABB overlaps `box` (shape frame), in increasing order.
  void queryTriangles(const Aabb& box, std::vector<int>& out) const;

 private:
  Geometry() = default;
  void buildBvh();

  Kind kind_ = Kind::Convex;
  std::vector<Vec3> vertices_;
  std::vector<HullFace> faces_;
  std::vector<HullEdge> edges_;
  double volume_ = 0.0;
  Vec3 centroid_ = Vec3::Zero();
  Mat3 unit_inertia_ = Mat3::Zero();
  std::vector<std::array<int, 3>> triangles_;
  std::vector<Vec3> normals_;
  std::vector<std::array<bool, 3>> edge_active_;
  std::vector<std::uint8_t> vertex_active_;
  std::vector<BvhNode> nodes_;
  std::vector<int> tree_triangles_;
};

/// The prepared geometry of a Convex or Mesh shape; nullptr for the primitives (sphere, box,
/// capsule, cylinder, plane). Throws std::invalid_argument with the reason for bad input.
std::shared_ptr<const Geometry> prepareGeometry(const ShapeDef& shape);

}  // namespace linx::collision
