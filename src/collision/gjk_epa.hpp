// GJK and EPA: distance and penetration between any two convex shapes given by support mappings.
//
// A convex shape is described by its support function s(d) = argmax_{x in shape} d . x. The
// Minkowski difference Z = A - B = {a - b} has support s_Z(d) = s_A(d) - s_B(-d), and
// - the shapes are separated iff the origin is outside Z; their distance is the distance from
//   the origin to Z, and the closest point v = a - b of Z gives the witness points a and b
//   (GJK: Gilbert, Johnson, Keerthi 1988, in van den Bergen's formulation);
// - when they overlap, the penetration depth is the distance from the origin to the boundary of
//   Z, and the boundary point p = depth n gives the normal: translating B by p separates them
//   (EPA: van den Bergen 2001, expanding a polytope inside Z towards the origin's nearest face).
//
// Spheres and capsules are a "core" (a point, a segment) inflated by a radius: GJK runs on the
// cores, which is exact and fast for the rounded shapes (the distance of the shapes is the
// cores' distance minus the radii). Only when the cores overlap does EPA run: on the cores when
// their difference is solid (the inflated difference is the cores' grown by r_a + r_b, so the
// depth is the cores' depth plus the radii, along the same normal), else on the full shapes.
// Boxes, cylinders, hulls and triangles have no radius. Everything here is in the world frame.
#pragma once

#include <linx/types.hpp>

#include <array>

#include "collision/narrowphase.hpp"

namespace linx::collision {

class Geometry;

/// A convex shape placed in the world, seen through its support function.
struct ConvexSupport {
  enum class Core { Point, Segment, Box, Cylinder, Hull, Triangle, Ellipsoid };
  Core core = Core::Point;
  double radius = 0.0;  ///< added around the core (sphere, capsule), else 0 (m)
  /// Box half extents; segment (0, 0, L/2); cylinder (r, r, L/2); an ellipsoid's semi-axes.
  Vec3 half = Vec3::Zero();
  const Geometry* hull = nullptr;  ///< Core::Hull
  std::array<Vec3, 3> triangle{};  ///< Core::Triangle, in the shape frame
  Vec3 position = Vec3::Zero();    ///< the shape frame in the world
  Mat3 rotation = Mat3::Identity();
  Vec3 centre = Vec3::Zero();  ///< a world point inside the core (its centre)
  double size = 0.0;           ///< a bound on the distance from `centre` to any point (m)

  /// The world point of the core maximising dir . x (dir need not be unit).
  Vec3 coreSupport(const Vec3& dir) const;
  /// The world point of the full shape (core + radius) maximising dir . x.
  Vec3 support(const Vec3& dir) const;
};

/// The support mapping of a sphere, box, capsule, cylinder or convex shape at its pose. Throws
/// std::invalid_argument for a plane or a mesh, or a convex without prepared geometry.
ConvexSupport makeSupport(const ShapeInstance& shape);
/// A triangle with the given world vertices (zero thickness).
ConvexSupport makeTriangleSupport(const Vec3& a, const Vec3& b, const Vec3& c);

struct GjkResult {
  bool overlap = false;   ///< the shapes intersect (or touch within the tolerance)
  bool beyond = false;    ///< proven farther apart than max_distance: distance is a lower bound
  double distance = 0.0;  ///< when !overlap (m)
  Vec3 point_a = Vec3::Zero(), point_b = Vec3::Zero();  ///< closest points, world (m)
};

/// Distance between a and b. With `cores`, between their cores (radii ignored). Stops early once
/// the distance is proven larger than max_distance.
GjkResult gjkDistance(const ConvexSupport& a, const ConvexSupport& b, bool cores,
                      double max_distance = kInfinity);

struct Penetration {
  bool valid = false;           ///< false when the expansion failed (degenerate input)
  Vec3 normal = Vec3::UnitZ();  ///< unit, from a towards b: translating b by depth n separates
  double depth = 0.0;           ///< (m) >= 0
  Vec3 point_a = Vec3::Zero(), point_b = Vec3::Zero();  ///< deepest points on each surface
};

/// Penetration of two overlapping full shapes by EPA.
Penetration epaPenetration(const ConvexSupport& a, const ConvexSupport& b);

/// The signed distance between two shapes, the one query the contact routines need.
struct ContactQuery {
  bool hit = false;             ///< separation < max_separation
  double separation = 0.0;      ///< distance (> 0) or minus the penetration depth (m)
  Vec3 normal = Vec3::UnitZ();  ///< unit, from a towards b
  Vec3 point_a = Vec3::Zero(), point_b = Vec3::Zero();  ///< witness points on the surfaces
};

/// GJK on the cores, then EPA on the full shapes when the cores overlap; a fallback along the
/// centre line when EPA fails, so the result is never NaN.
ContactQuery queryContact(const ConvexSupport& a, const ConvexSupport& b, double max_separation);

}  // namespace linx::collision
