// Shapes as triangle surfaces, for pictures and files that draw a run (docs/visualization.md,
// "ParaView"): every shape type becomes points, unit normals (one per point) and triangles,
// counter-clockwise seen from outside, in the shape's own frame.
#pragma once

#include <linx/shape.hpp>
#include <linx/types.hpp>

#include <array>
#include <vector>

namespace linx::viz {

struct Surface {
  std::vector<Vec3> points;
  std::vector<Vec3> normals;  ///< unit outward normal at each point
  std::vector<std::array<int, 3>> triangles;
};

struct TessellationOptions {
  /// Spheres are icospheres: an icosahedron whose triangles are split in four this many times
  /// (2: 162 points, 320 triangles). Every point lies on the sphere.
  int sphere_subdivisions = 2;
  /// Points around the circles of capsules and cylinders, and per quarter circle of a capsule's
  /// cap (divided by four, at least two).
  int segments = 24;
  /// Planes are drawn as a square of this half edge length centred on the point of the plane
  /// nearest to `plane_center` (shape frame).
  double plane_half_size = 1.0;
  Vec3 plane_center = Vec3::Zero();
};

/// The surface of `shape` in its shape frame (apply shape.position and shape.orientation to get
/// the body frame). Spheres, capsules and cylinders are smooth (normals of the exact surface);
/// boxes, convex hulls, meshes and planes are flat (a point per triangle corner or face corner,
/// with the face's normal). Convex hulls and meshes use their `points` and `triangles` as given.
Surface tessellate(const ShapeDef& shape, const TessellationOptions& options = {});

}  // namespace linx::viz
