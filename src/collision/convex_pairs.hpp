// General convex contact: any two of {sphere, box, capsule, cylinder, convex hull}, a plane
// against any of them, and any of them against a triangle mesh. They follow the conventions of
// collision/narrowphase.hpp (normal from a towards b, depth > 0 penetration, points while
// depth > -margin, point midway between the surfaces, stable feature ids).
//
// The normal comes from GJK/EPA (collision/gjk_epa.hpp); the points from the two shapes'
// supporting features along it (a face, an edge or a single point): the incident feature is
// clipped against the side planes of the reference face (Sutherland-Hodgman), so a hull or a
// cylinder resting flat on a box gets 3-4 points spanning the contact area rather than one point
// that would let it rock. Every point is a pair of surface points on one line along the normal,
// so its depth is the true penetration (or gap) there.
#pragma once

#include <vector>

#include "collision/narrowphase.hpp"

namespace linx::collision {

/// a and b each a sphere, box, capsule, cylinder or convex (convex needs its prepared geometry),
/// or one of them a plane. Appends at most kMaxPointsPerPair points and returns how many. A mesh
/// on either side is passed on to collideMesh; two planes append nothing.
int collideConvex(const ShapeInstance& a, const ShapeInstance& b, double margin,
                  std::vector<ContactPoint>& out);

/// a (sphere, box, capsule, cylinder or convex) against the triangles of `mesh` near it (the
/// mesh's AABB tree queried with a's box grown by the margin). Each touching triangle is a convex
/// of zero thickness giving at most 4 points; contacts on edges internal to a flat or concave
/// region (and on the back of a triangle) take the triangle's face normal, so bodies slide over
/// internal edges without bumps; points that coincide across triangles are merged and coplanar
/// groups are reduced to 4. Feature id: a hash of (triangle index, point feature).
int collideMesh(const ShapeInstance& a, const ShapeInstance& mesh, double margin,
                std::vector<ContactPoint>& out);

}  // namespace linx::collision
