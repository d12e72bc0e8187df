// The one reduction of a contact manifold to the points that span it, for every pair routine
// (box-box, plane, convex and mesh): a resting box keeps its four corners, and points that add no
// area are dropped.
#pragma once

#include <cstddef>
#include <vector>

#include "collision/narrowphase.hpp"

namespace linx::collision {

/// Keeps at most kMaxPointsPerPair of the points of one manifold from index `first` of `points`
/// on, erasing the rest; areas are measured across the normal n. Kept: 1. the deepest (within
/// 1e-6 m; among those the farthest from the centroid), 2. the farthest from it, 3. the one
/// making the largest triangle with those two, 4. the one adding the most area outside that
/// triangle. A third or fourth point that adds no area (below 1e-8 of the squared span of the
/// first two: collinear with or inside the others, as where two triangles' manifolds meet) is
/// dropped, whatever the count. The kept points stay in their original order.
void reduceManifold(std::vector<ContactPoint>& points, std::size_t first, const Vec3& n);

}  // namespace linx::collision
