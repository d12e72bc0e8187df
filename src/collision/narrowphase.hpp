// Narrowphase: the contact points between two shapes placed in the world (DESIGN.md section 6:
// broadphase -> narrowphase -> contacts). Every routine is stateless: the same poses give the same
// points, and a point's feature id names the pair of features (vertex, edge, face) that made it,
// so that it stays the same across steps while the same features touch (warm starting matches
// contact impulses by it).
//
// Conventions, for every pair routine:
// - The normal is a world unit vector pointing from shape a towards shape b: pushing b along +n
//   and a along -n separates them.
// - depth > 0 is penetration (m); depth < 0 is a gap of -depth. Points are reported while
//   depth > -margin (speculative contacts), so a contact exists a step before the shapes touch.
// - The point is in the world frame, midway between the two surfaces along the normal.
// - A routine appends at most kMaxPointsPerPair points per call for convex pairs (a manifold of
//   up to 4 points that spans the contact area); a mesh may append more (one manifold per
//   touching triangle).
#pragma once

#include <linx/shape.hpp>
#include <linx/types.hpp>

#include <cstdint>
#include <memory>
#include <vector>

namespace linx::collision {

class Geometry;  // prepared data of a convex hull or a triangle mesh (collision/geometry.hpp)

/// A shape placed in the world for one step.
struct ShapeInstance {
  const ShapeDef* def = nullptr;
  const Geometry* geometry = nullptr;  ///< prepared hull or mesh; nullptr for primitives
  Pose pose;  ///< the shape frame in the world: body pose composed with the shape's local pose
};

struct ContactPoint {
  Vec3 point = Vec3::Zero();    ///< world (m)
  Vec3 normal = Vec3::UnitZ();  ///< world unit normal, from a towards b
  double depth = 0.0;           ///< penetration (m), negative for a gap
  std::uint32_t feature = 0;    ///< stable id of the touching features within this pair
};

inline constexpr int kMaxPointsPerPair = 4;

/// Appends to `out` the contact points of a and b with depth > -margin and returns how many it
/// appended. Supports every pair of shape types except two static-only shapes (plane, mesh),
/// which never need to collide: those append nothing.
int collide(const ShapeInstance& a, const ShapeInstance& b, double margin,
            std::vector<ContactPoint>& out);

}  // namespace linx::collision
