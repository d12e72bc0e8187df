// Exact narrowphase routines for the primitive pairs: spheres, capsules and boxes against each
// other, and a plane against every convex shape. They follow the conventions of
// collision/narrowphase.hpp (normal from a towards b, depth > 0 penetration, points while
// depth > -margin, point midway between the surfaces, at most kMaxPointsPerPair points, feature
// ids from the touching features). "Exact" means closed forms rather than an iterative convex
// solver: the depth and normal of every point are those of the real geometry, so a resting stack
// sits at zero depth, not at a solver tolerance.
//
// Each routine takes a of the first-named type and b of the second, appends its points to `out`
// and returns how many it appended. The dispatcher (collision/narrowphase.cpp) calls them with
// swapped arguments for the other order of two types.
#pragma once

#include <cstddef>
#include <utility>
#include <vector>

#include "collision/narrowphase.hpp"

namespace linx::collision {

int collideSphereSphere(const ShapeInstance& a, const ShapeInstance& b, double margin,
                        std::vector<ContactPoint>& out);
int collideSphereCapsule(const ShapeInstance& a, const ShapeInstance& b, double margin,
                         std::vector<ContactPoint>& out);
int collideCapsuleCapsule(const ShapeInstance& a, const ShapeInstance& b, double margin,
                          std::vector<ContactPoint>& out);
int collideSphereBox(const ShapeInstance& a, const ShapeInstance& b, double margin,
                     std::vector<ContactPoint>& out);
int collideCapsuleBox(const ShapeInstance& a, const ShapeInstance& b, double margin,
                      std::vector<ContactPoint>& out);
/// Box against box: separating axis test on the 15 axes, then the incident face clipped against
/// the reference face (collision/box_box.cpp).
int collideBoxBox(const ShapeInstance& a, const ShapeInstance& b, double margin,
                  std::vector<ContactPoint>& out);
/// A plane against a sphere, box, capsule, cylinder or convex hull: the one plane routine (a mesh
/// or another plane appends nothing). The normal is the plane's outward normal (from the plane
/// towards the other shape).
int collidePlane(const ShapeInstance& plane, const ShapeInstance& other, double margin,
                 std::vector<ContactPoint>& out);

namespace detail {
/// Parameters (s, t) in [0, 1]^2 of the closest points p0 + s (p1 - p0) and q0 + t (q1 - q0) of
/// two segments; deterministic for parallel and zero-length segments.
std::pair<double, double> closestSegmentParams(const Vec3& p0, const Vec3& p1, const Vec3& q0,
                                               const Vec3& q1);
}  // namespace detail

}  // namespace linx::collision
