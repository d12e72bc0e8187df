#include "collision/manifold_reduction.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace linx::collision {

void reduceManifold(std::vector<ContactPoint>& points, std::size_t first, const Vec3& n) {
  if (first >= points.size() || points.size() - first <= 2) return;
  const std::size_t count = points.size() - first;
  const auto at = [&](std::size_t k) -> const ContactPoint& { return points[first + k]; };
  const auto flat = [&](const Vec3& x) { return Vec3(x - n * n.dot(x)); };  // across n
  constexpr std::size_t kNone = std::numeric_limits<std::size_t>::max();
  Vec3 centroid = Vec3::Zero();
  double max_depth = -std::numeric_limits<double>::infinity();
  for (std::size_t k = 0; k < count; ++k) {
    centroid += at(k).point;
    max_depth = std::max(max_depth, at(k).depth);
  }
  centroid /= static_cast<double>(count);
  // 1. The deepest (within 1e-6 m), farthest from the centroid among ties.
  std::size_t i0 = kNone;
  double best = -1.0;
  for (std::size_t k = 0; k < count; ++k) {
    if (at(k).depth < max_depth - 1e-6) continue;
    const double d = flat(at(k).point - centroid).squaredNorm();
    if (d > best) {
      best = d;
      i0 = k;
    }
  }
  // Non-finite points (a state that overflowed) compare with nothing: keep one, and leave the
  // state to the step's checks, which name it.
  if (i0 == kNone) i0 = 0;
  // 2. The farthest from it.
  std::size_t i1 = kNone;
  best = -1.0;
  for (std::size_t k = 0; k < count; ++k) {
    if (k == i0) continue;
    const double d = flat(at(k).point - at(i0).point).squaredNorm();
    if (d > best) {
      best = d;
      i1 = k;
    }
  }
  if (i1 == kNone) {
    points[first] = ContactPoint(at(i0));
    points.resize(first + 1);
    return;
  }
  const Vec3 p0 = at(i0).point, p1 = at(i1).point;
  // (m^2) areas below this add nothing: a point within ~1e-8 spans of the line or triangle.
  const double tiny = std::max(1e-8 * flat(p1 - p0).squaredNorm(), 1e-24);
  // 3. The largest triangle with them, on either side.
  std::size_t i2 = kNone, i3 = kNone;
  double signed_area = 0.0;
  best = tiny;
  for (std::size_t k = 0; k < count; ++k) {
    if (k == i0 || k == i1) continue;
    const double a = n.dot((p1 - p0).cross(at(k).point - p0));
    if (std::abs(a) > best) {
      best = std::abs(a);
      signed_area = a;
      i2 = k;
    }
  }
  if (i2 != kNone) {
    // 4. The point adding the most area outside the triangle's edges (oriented as the triangle).
    const double orient = signed_area > 0.0 ? 1.0 : -1.0;
    const Vec3 triangle[3] = {p0, p1, at(i2).point};
    best = tiny;
    for (std::size_t k = 0; k < count; ++k) {
      if (k == i0 || k == i1 || k == i2) continue;
      for (int e = 0; e < 3; ++e) {
        const Vec3& u = triangle[e];
        const Vec3& v = triangle[(e + 1) % 3];
        const double outside = -orient * n.dot((v - u).cross(at(k).point - u));
        if (outside > best) {
          best = outside;
          i3 = k;
        }
      }
    }
  }
  // Compact the kept points to the front, in their original order (k >= kept: no overwrite).
  std::size_t kept = 0;
  for (std::size_t k = 0; k < count; ++k)
    if (k == i0 || k == i1 || k == i2 || k == i3) points[first + kept++] = points[first + k];
  points.resize(first + kept);
}

}  // namespace linx::collision
