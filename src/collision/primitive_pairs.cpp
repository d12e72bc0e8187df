// Exact contact points of the round primitive pairs (sphere, capsule) with each other and with a
// box, and of a plane with a sphere, box, capsule or cylinder; box against box is in box_box.cpp.
// Every routine reduces its pair to closed forms: a sphere is a point inflated by its radius and a
// capsule a segment inflated by its radius, so each pair becomes the closest points of a point or
// segment to a point, segment or box, and the depth is (sum of radii) - (distance of the cores).
// Conventions: collision/narrowphase.hpp (normal from a to b, depth > 0 penetration, points while
// depth > -margin, point midway between the two surfaces).
#include "collision/primitive_pairs.hpp"

#include "collision/geometry.hpp"
#include "collision/gjk_epa.hpp"
#include "collision/manifold_reduction.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <memory>

namespace linx::collision {

namespace {

/// Lengths (m) and squared lengths below these are treated as zero (coincident centres,
/// zero-length capsules): the routines then fall back to a fixed direction, never to NaN.
constexpr double kTinyLength = 1e-12;
/// Sine of the largest angle between two capsule axes still handled as "parallel" (about 5.7
/// degrees): the contact is then spanned by the ends of the overlap of the two segments.
constexpr double kParallelSine = 0.1;
/// An extra point is only added to a spanning manifold when it is deeper than the others by more
/// than this (m): nearly flat contacts keep the same points step after step.
constexpr double kDepthTolerance = 1e-9;

double signOf(double x) {
  return x < 0.0 ? -1.0 : 1.0;
}

/// A unit vector perpendicular to v (v nonzero): v crossed with the world axis least aligned with
/// it, so the choice is deterministic.
Vec3 perpendicular(const Vec3& v) {
  const Vec3 m = v.cwiseAbs();
  const Vec3 axis = m.x() <= m.y() && m.x() <= m.z() ? Vec3::UnitX()
                    : m.y() <= m.z()                 ? Vec3::UnitY()
                                                     : Vec3::UnitZ();
  return v.cross(axis).normalized();
}

/// The core segment of a capsule in the world: end 0 at local z = -length/2, end 1 at +length/2.
struct Segment {
  Vec3 p0;
  Vec3 p1;
  Vec3 at(double s) const { return p0 + s * (p1 - p0); }
};

Segment capsuleSegment(const ShapeInstance& capsule) {
  const Vec3 half = capsule.pose.orientation * Vec3(0.0, 0.0, 0.5 * capsule.def->length);
  return {capsule.pose.position - half, capsule.pose.position + half};
}

/// Parameter in [0, 1] of the point of segment [p0, p1] closest to x.
double closestOnSegment(const Vec3& p0, const Vec3& p1, const Vec3& x) {
  const Vec3 d = p1 - p0;
  const double dd = d.squaredNorm();
  if (dd <= kTinyLength * kTinyLength) return 0.0;
  return std::clamp(d.dot(x - p0) / dd, 0.0, 1.0);
}

}  // namespace

/// Parameters (s, t) in [0, 1]^2 of the closest points P(s) = p0 + s d1, Q(t) = q0 + t d2 of two
/// segments. Setting the gradient of |P(s) - Q(t)|^2 to zero gives, with r = p0 - q0,
///   a s - b t = -c,  b s - e t = -f,   a = d1.d1, b = d1.d2, c = d1.r, e = d2.d2, f = d2.r,
/// solved for s (s = (b f - c e) / (a e - b^2), clamped), then t = (b s + f) / e clamped, and s
/// recomputed for that t when t was clamped. Parallel segments (a e - b^2 ~ 0) take s = 0; a
/// degenerate segment (a point) takes its parameter 0.
std::pair<double, double> detail::closestSegmentParams(const Vec3& p0, const Vec3& p1,
                                                       const Vec3& q0, const Vec3& q1) {
  const Vec3 d1 = p1 - p0, d2 = q1 - q0, r = p0 - q0;
  const double a = d1.squaredNorm(), e = d2.squaredNorm(), f = d2.dot(r);
  constexpr double kTiny2 = kTinyLength * kTinyLength;
  if (a <= kTiny2 && e <= kTiny2) return {0.0, 0.0};
  if (a <= kTiny2) return {0.0, std::clamp(f / e, 0.0, 1.0)};
  const double c = d1.dot(r);
  if (e <= kTiny2) return {std::clamp(-c / a, 0.0, 1.0), 0.0};
  const double b = d1.dot(d2);
  const double denom = a * e - b * b;  // = |d1 x d2|^2 >= 0
  double s = denom > 1e-14 * a * e ? std::clamp((b * f - c * e) / denom, 0.0, 1.0) : 0.0;
  double t = (b * s + f) / e;
  if (t < 0.0) {
    t = 0.0;
    s = std::clamp(-c / a, 0.0, 1.0);
  } else if (t > 1.0) {
    t = 1.0;
    s = std::clamp((b - c) / a, 0.0, 1.0);
  }
  return {s, t};
}

namespace {

using detail::closestSegmentParams;

/// Appends the point of two inflated points, core ca with radius ra and core cb with radius rb:
/// normal (cb - ca)/|cb - ca| (from a to b), or `fallback` when the cores coincide; depth
/// ra + rb - |cb - ca|; the point midway between the surface points ca + ra n and cb - rb n.
/// Returns false (appending nothing) when depth <= -margin.
bool appendRoundPoint(const Vec3& ca, double ra, const Vec3& cb, double rb, const Vec3& fallback,
                      double margin, std::uint32_t feature, std::vector<ContactPoint>& out) {
  const Vec3 d = cb - ca;
  const double dist = d.norm();
  const double depth = ra + rb - dist;
  if (!(depth > -margin)) return false;
  const Vec3 n = dist > kTinyLength ? Vec3(d / dist) : fallback;
  out.push_back({0.5 * ((ca + ra * n) + (cb - rb * n)), n, depth, feature});
  return true;
}

double radiusOf(const ShapeInstance& s) {
  return std::max(s.def->radius, 0.0);
}

}  // namespace

// ---------------------------------------------------------------------------------------------
// Sphere and capsule pairs: closest points of the cores.

int collideSphereSphere(const ShapeInstance& a, const ShapeInstance& b, double margin,
                        std::vector<ContactPoint>& out) {
  // Coincident centres: any direction separates them equally; take +z.
  return appendRoundPoint(a.pose.position, radiusOf(a), b.pose.position, radiusOf(b), Vec3::UnitZ(),
                          margin, 0, out)
             ? 1
             : 0;
}

int collideSphereCapsule(const ShapeInstance& a, const ShapeInstance& b, double margin,
                         std::vector<ContactPoint>& out) {
  const Segment seg = capsuleSegment(b);
  const Vec3 c = a.pose.position;
  const double s = closestOnSegment(seg.p0, seg.p1, c);
  // Centre on the axis: push across the axis (a zero-length capsule is a sphere: +z).
  const Vec3 axis = seg.p1 - seg.p0;
  const Vec3 fallback = axis.norm() > kTinyLength ? perpendicular(axis) : Vec3::UnitZ();
  // Feature: which part of the core segment is closest (end 0, end 1 or its interior).
  const std::uint32_t feature = s <= 0.0 ? 0u : s >= 1.0 ? 1u : 2u;
  return appendRoundPoint(c, radiusOf(a), seg.at(s), radiusOf(b), fallback, margin, feature, out)
             ? 1
             : 0;
}

int collideCapsuleCapsule(const ShapeInstance& a, const ShapeInstance& b, double margin,
                          std::vector<ContactPoint>& out) {
  const Segment sa = capsuleSegment(a), sb = capsuleSegment(b);
  const double ra = radiusOf(a), rb = radiusOf(b);
  const Vec3 ua = sa.p1 - sa.p0, ub = sb.p1 - sb.p0;
  const double la = ua.norm(), lb = ub.norm();

  // The direction used when two cores touch: the common perpendicular of the axes (crossed
  // axes), else a perpendicular of one axis (parallel or a zero-length capsule), else +z; turned
  // towards b's centre when that decides it.
  Vec3 fallback = Vec3::UnitZ();
  const Vec3 cross = ua.cross(ub);
  if (la > kTinyLength && lb > kTinyLength && cross.norm() > 1e-9 * la * lb) {
    fallback = cross.normalized();
  } else if (la > kTinyLength) {
    fallback = perpendicular(ua);
  } else if (lb > kTinyLength) {
    fallback = perpendicular(ub);
  }
  if (fallback.dot(b.pose.position - a.pose.position) < 0.0) fallback = -fallback;

  // The closest points of the two cores: the deepest point of the pair (feature 0).
  const auto [s, t] = closestSegmentParams(sa.p0, sa.p1, sb.p0, sb.p1);
  const Vec3 pa = sa.at(s), pb = sb.at(t);
  const Vec3 d = pb - pa;
  const double dist = d.norm();
  const Vec3 n = dist > kTinyLength ? Vec3(d / dist) : fallback;

  // Nearly parallel axes (|ua x ub| < kParallelSine |ua| |ub|): the contact is a line, spanned by
  // the two ends of the overlap of b's core projected on a's axis, [lo, hi] along a's axis from
  // its end 0. Each end is an exact point: the point of a's core there against its closest point
  // on b's core (features 1 for lo, 2 for hi). The closest points are added too (feature 0) when
  // the axes are not quite parallel and they lie deeper than both ends.
  if (la > kTinyLength && lb > kTinyLength && cross.norm() < kParallelSine * la * lb) {
    const Vec3 ea = ua / la;
    const double tb0 = ea.dot(sb.p0 - sa.p0), tb1 = ea.dot(sb.p1 - sa.p0);
    const double lo = std::max(0.0, std::min(tb0, tb1));
    const double hi = std::min(la, std::max(tb0, tb1));
    if (hi - lo > kTinyLength) {
      const std::size_t first = out.size();
      double deepest_end = -kInfinity;
      const std::array<double, 2> ends{lo, hi};
      for (int k = 0; k < 2; ++k) {
        const Vec3 qa = sa.p0 + ends[k] * ea;
        const Vec3 qb = sb.at(closestOnSegment(sb.p0, sb.p1, qa));
        deepest_end = std::max(deepest_end, ra + rb - (qb - qa).norm());
        appendRoundPoint(qa, ra, qb, rb, n, margin, static_cast<std::uint32_t>(k + 1), out);
      }
      const double along = s * la;
      if (ra + rb - dist > deepest_end + kDepthTolerance && along > lo && along < hi) {
        appendRoundPoint(pa, ra, pb, rb, fallback, margin, 0, out);
      }
      return static_cast<int>(out.size() - first);
    }
  }
  return appendRoundPoint(pa, ra, pb, rb, fallback, margin, 0, out) ? 1 : 0;
}

// ---------------------------------------------------------------------------------------------
// Round shapes against a box. Work in the box frame: the box is [-h, h] (h the half extents).

namespace {

/// Code of the box feature holding a point q of the box surface (box frame): per axis 0 when
/// strictly inside the slab, 1 on the -h face, 2 on the +h face; code = c_x + 3 c_y + 9 c_z.
std::uint32_t boxRegion(const Vec3& q, const Vec3& h) {
  std::uint32_t code = 0, scale = 1;
  for (int k = 0; k < 3; ++k) {
    const std::uint32_t c = q[k] >= h[k] ? 2u : q[k] <= -h[k] ? 1u : 0u;
    code += c * scale;
    scale *= 3;
  }
  return code;
}

/// Index of the box face with normal sign * e_k: 2k for -e_k, 2k + 1 for +e_k.
std::uint32_t faceIndex(int k, double sign) {
  return static_cast<std::uint32_t>(2 * k + (sign > 0.0 ? 1 : 0));
}

/// A contact in the box frame: the point, the unit normal from the box towards the round shape,
/// the depth and the feature. Turned into the world (and the normal into a -> b, a being the
/// round shape) by appendFromBox.
struct LocalPoint {
  Vec3 point;
  Vec3 normal;
  double depth;
  std::uint32_t feature;
};

/// At most two local points (a capsule against a box): a fixed array, so no allocation.
struct LocalPoints {
  std::array<LocalPoint, 2> items{};
  int count = 0;
  void push_back(const LocalPoint& p) {
    if (count < 2) items[count++] = p;
  }
};

void appendFromBox(const Pose& box, const LocalPoint& p, std::vector<ContactPoint>& out) {
  out.push_back({box.toWorld(p.point), -(box.orientation * p.normal), p.depth, p.feature});
}

/// Sphere of centre c and radius r (box frame) against the box [-h, h]. Outside the box the
/// normal runs from the closest box point q = clamp(c, -h, h) to c and depth = r - |c - q|.
/// Inside (or on the surface), it is the normal of the nearest face, e_k sign(c_k) with k
/// minimising h_k - |c_k|, and depth = r + (h_k - |c_k|). The point is midway between the sphere
/// point c - r n and the box point q.
bool sphereBoxLocal(const Vec3& c, double r, const Vec3& h, double margin, LocalPoint& result) {
  Vec3 q = c.cwiseMax(-h).cwiseMin(h);
  const double dist = (c - q).norm();
  Vec3 n;
  double depth;
  if (dist > kTinyLength) {
    n = (c - q) / dist;
    depth = r - dist;
  } else {
    int k = 0;
    for (int m = 1; m < 3; ++m) {
      if (h[m] - std::abs(c[m]) < h[k] - std::abs(c[k])) k = m;
    }
    const double sign = signOf(c[k]);
    n = sign * Vec3::Unit(k);
    depth = r + (h[k] - std::abs(c[k]));
    q[k] = sign * h[k];
  }
  if (!(depth > -margin)) return false;
  result = {0.5 * ((c - r * n) + q), n, depth, boxRegion(q, h)};
  return true;
}

/// Clips the segment p0 + t (p1 - p0), t in [0, 1], to the slabs |x_i| <= h_i of every axis but
/// `skip` (-1: all three). False when nothing is left; otherwise [t0, t1] is what remains.
bool clipSegmentToSlabs(const Vec3& p0, const Vec3& p1, const Vec3& h, int skip, double& t0,
                        double& t1) {
  const Vec3 d = p1 - p0;
  t0 = 0.0;
  t1 = 1.0;
  for (int i = 0; i < 3; ++i) {
    if (i == skip) continue;
    if (std::abs(d[i]) <= kTinyLength) {
      if (std::abs(p0[i]) > h[i]) return false;
      continue;
    }
    double ta = (-h[i] - p0[i]) / d[i], tb = (h[i] - p0[i]) / d[i];
    if (ta > tb) std::swap(ta, tb);
    t0 = std::max(t0, ta);
    t1 = std::min(t1, tb);
    if (t0 > t1) return false;
  }
  return true;
}

/// The capsule core [p0, p1] (box frame) against the face sign * e_k of the box, whose outward
/// normal f points towards the capsule: the core is clipped to the prism over the face
/// (|x_i| <= h_i for the two other axes i) and each end of the clipped part is a point, of
/// depth r - height (height = f.x - h_k, its signed height above the face plane) and placed
/// midway between the capsule point x - r f and the face point x - height f. Since the height is
/// linear along the core, the deepest point of the clipped core is one of the two. Features:
/// base + 2 * face + (0 for the end towards p0, 1 towards p1). Returns false when the core does
/// not reach over the face.
bool clipCoreToFace(const Vec3& p0, const Vec3& p1, double r, const Vec3& h, int k, double sign,
                    double margin, std::uint32_t base, LocalPoints& points) {
  const Vec3 d = p1 - p0;
  double t0, t1;
  if (!clipSegmentToSlabs(p0, p1, h, k, t0, t1)) return false;
  const Vec3 f = sign * Vec3::Unit(k);
  const bool single = (t1 - t0) * d.norm() <= kTinyLength;  // the clipped core is a point
  const std::array<double, 2> ts{t0, t1};
  for (int e = 0; e < (single ? 1 : 2); ++e) {
    const Vec3 x = p0 + ts[e] * d;
    const double height = f.dot(x) - h[k];
    const double depth = r - height;
    if (!(depth > -margin)) continue;
    points.push_back({x - 0.5 * (r + height) * f, f, depth,
                      base + 2 * faceIndex(k, sign) + static_cast<std::uint32_t>(e)});
  }
  return true;
}

/// True when the segment [p0, p1] meets the box [-h, h] (slab test on the three axes).
bool segmentMeetsBox(const Vec3& p0, const Vec3& p1, const Vec3& h) {
  double t0, t1;
  return clipSegmentToSlabs(p0, p1, h, -1, t0, t1);
}

/// The two ends of box edge number `edge` (box frame). Edge 4 a + m runs along axis a; bit 0 of m
/// gives the sign of the first other axis (a + 1) % 3, bit 1 that of the second (a + 2) % 3.
std::pair<Vec3, Vec3> boxEdge(int edge, const Vec3& h) {
  const int a = edge / 4, m = edge % 4;
  const int i = (a + 1) % 3, j = (a + 2) % 3;
  Vec3 c = Vec3::Zero();
  c[i] = (m & 1) ? h[i] : -h[i];
  c[j] = (m & 2) ? h[j] : -h[j];
  Vec3 e0 = c, e1 = c;
  e0[a] = -h[a];
  e1[a] = h[a];
  return {e0, e1};
}

/// Feature bases of the capsule-box points, so that the kinds never share an id.
constexpr std::uint32_t kFaceBase = 0;      // 12 ids: face and clipped end
constexpr std::uint32_t kClosestBase = 16;  // 81 ids: box region and core part
constexpr std::uint32_t kEdgeBase = 128;    // 12 ids: box edge crossing the core

/// Capsule core [p0, p1] with radius r (box frame) against the box [-h, h], points appended to
/// `points` with their normals from the box towards the capsule.
void capsuleBoxLocal(const Vec3& p0, const Vec3& p1, double r, const Vec3& h, double margin,
                     LocalPoints& points) {
  const Vec3 d = p1 - p0;
  const double len = d.norm();
  if (len <= kTinyLength) {  // a zero-length capsule is a sphere
    LocalPoint p;
    if (sphereBoxLocal(p0, r, h, margin, p)) points.push_back(p);
    return;
  }

  if (!segmentMeetsBox(p0, p1, h)) {
    // Separated cores: the closest points of the segment and the solid box. f(s) = dist(P(s), box)
    // is convex, and its minimum is at an end of the segment (against its clamp into the box) or
    // at the closest points of the segment and one of the 12 box edges: an interior minimum
    // against a face interior means the segment is parallel to that face, where the minimum is
    // also reached at an end or over an edge.
    double best_s = 0.0;
    Vec3 best_q = p0.cwiseMax(-h).cwiseMin(h);
    double best = (p0 - best_q).squaredNorm();
    const Vec3 q1 = p1.cwiseMax(-h).cwiseMin(h);
    if ((p1 - q1).squaredNorm() < best) {
      best = (p1 - q1).squaredNorm();
      best_s = 1.0;
      best_q = q1;
    }
    for (int edge = 0; edge < 12; ++edge) {
      const auto [e0, e1] = boxEdge(edge, h);
      const auto [s, t] = closestSegmentParams(p0, p1, e0, e1);
      const Vec3 q = e0 + t * (e1 - e0);
      const double dist2 = (p0 + s * d - q).squaredNorm();
      if (dist2 < best) {
        best = dist2;
        best_s = s;
        best_q = q;
      }
    }
    const double dist = std::sqrt(best);
    if (dist > kTinyLength) {
      if (!(r - dist > -margin)) return;
      const Vec3 x = p0 + best_s * d;
      const Vec3 n = (x - best_q) / dist;  // from the box towards the capsule
      // The closest box point on a face interior: n is that face's normal, and the capsule may
      // lie along the face, so the face gives the points (two when it lies flat on it).
      int k = 0;
      n.cwiseAbs().maxCoeff(&k);
      if (std::abs(n[k]) >= 1.0 - 1e-9 &&
          clipCoreToFace(p0, p1, r, h, k, signOf(n[k]), margin, kFaceBase, points)) {
        return;
      }
      const std::uint32_t part = best_s <= 0.0 ? 0u : best_s >= 1.0 ? 1u : 2u;
      points.push_back({0.5 * ((x - r * n) + best_q), n, r - dist,
                        kClosestBase + 3 * boxRegion(best_q, h) + part});
      return;
    }
  }

  // The core touches or crosses the box: separating axis test of the segment and the box, its
  // Minkowski sum being a zonotope with facet normals e_k (box faces) and u x e_k (u the
  // segment direction). Along a unit axis L, with c the segment midpoint and w its half vector,
  //   separation = |L.c| - sum_i h_i |L_i| - |L.w| - r,
  // and the axis of largest separation gives the normal. Face axes win ties, and an edge axis
  // must beat the best face by a small bias (stable face manifolds for a capsule lying flat).
  const Vec3 c = 0.5 * (p0 + p1), w = 0.5 * d, u = d / len;
  int face = 0;
  double face_sep = -kInfinity;
  for (int k = 0; k < 3; ++k) {
    const double sep = std::abs(c[k]) - h[k] - std::abs(w[k]) - r;
    if (sep > face_sep) {
      face_sep = sep;
      face = k;
    }
  }
  int edge_axis = -1;
  double edge_sep = -kInfinity;
  Vec3 edge_normal = Vec3::UnitZ();
  for (int k = 0; k < 3; ++k) {
    const Vec3 cross = u.cross(Vec3::Unit(k));
    if (cross.norm() < 1e-6) continue;  // parallel to the edge: covered by the face axes
    const Vec3 L = cross.normalized();
    const double sep = std::abs(L.dot(c)) - h.dot(L.cwiseAbs()) - r;  // L.w = 0
    if (sep > edge_sep) {
      edge_sep = sep;
      edge_axis = k;
      edge_normal = signOf(L.dot(c)) * L;
    }
  }
  const double bias = 1e-3 * (h.sum() / 3.0 + r);
  if (edge_axis < 0 || edge_sep <= face_sep + bias) {
    if (!(-face_sep > -margin)) return;
    if (clipCoreToFace(p0, p1, r, h, face, signOf(c[face]), margin, kFaceBase, points)) return;
    // Unreachable for a core meeting the box (some point of it lies over the face); kept so a
    // contact within the margin always gives a point: the deepest end along the face normal.
    const Vec3 f = signOf(c[face]) * Vec3::Unit(face);
    const Vec3 x = f.dot(p0) <= f.dot(p1) ? p0 : p1;
    const double height = f.dot(x) - h[face];
    points.push_back(
        {x - 0.5 * (r + height) * f, f, r - height, kFaceBase + 2 * faceIndex(face, f[face])});
    return;
  }
  if (!(-edge_sep > -margin)) return;
  // Edge axis: the box edge along e_k that is extreme along the normal n, against the core.
  const Vec3& n = edge_normal;
  const int i = (edge_axis + 1) % 3, j = (edge_axis + 2) % 3;
  const int edge = 4 * edge_axis + (n[i] >= 0.0 ? 1 : 0) + (n[j] >= 0.0 ? 2 : 0);
  const auto [e0, e1] = boxEdge(edge, h);
  const auto [s, t] = closestSegmentParams(p0, p1, e0, e1);
  const Vec3 x = p0 + s * d, q = e0 + t * (e1 - e0);
  points.push_back(
      {0.5 * ((x - r * n) + q), n, -edge_sep, kEdgeBase + static_cast<std::uint32_t>(edge)});
}

}  // namespace

int collideSphereBox(const ShapeInstance& a, const ShapeInstance& b, double margin,
                     std::vector<ContactPoint>& out) {
  const Vec3 h = 0.5 * b.def->size.cwiseAbs();
  LocalPoint p;
  if (!sphereBoxLocal(b.pose.toLocal(a.pose.position), radiusOf(a), h, margin, p)) return 0;
  appendFromBox(b.pose, p, out);
  return 1;
}

int collideCapsuleBox(const ShapeInstance& a, const ShapeInstance& b, double margin,
                      std::vector<ContactPoint>& out) {
  const Vec3 h = 0.5 * b.def->size.cwiseAbs();
  const Segment seg = capsuleSegment(a);
  LocalPoints points;
  capsuleBoxLocal(b.pose.toLocal(seg.p0), b.pose.toLocal(seg.p1), radiusOf(a), h, margin, points);
  for (int k = 0; k < points.count; ++k) appendFromBox(b.pose, points.items[k], out);
  return points.count;
}

// ---------------------------------------------------------------------------------------------
// Plane against a sphere, box, capsule or cylinder. In the world the plane is n.x = offset with
// n = R normal and offset = offset_local + n.position (R, position: the plane's pose); the signed
// distance of a point y is n.y - offset, and the solid is where it is <= 0. Every candidate
// point y is a point of the other shape's surface, deepest along -n for its feature: its depth
// is offset - n.y and the reported point is midway between y and its projection y - dist n.

int collidePlane(const ShapeInstance& plane, const ShapeInstance& other, double margin,
                 std::vector<ContactPoint>& out) {
  // normal . x = offset in the plane's frame, whatever the normal's length.
  const double length = plane.def->normal.norm();
  if (!(length > kTinyLength)) return 0;
  const Vec3 n = (plane.pose.orientation * plane.def->normal).normalized();
  const double offset = plane.def->offset / length + n.dot(plane.pose.position);
  const std::size_t first = out.size();
  auto depthOf = [&](const Vec3& y) { return offset - n.dot(y); };
  auto candidate = [&](const Vec3& y, std::uint32_t feature) {
    const double depth = depthOf(y);
    if (depth > -margin) out.push_back({y + 0.5 * depth * n, n, depth, feature});
  };

  const ShapeDef& def = *other.def;
  const Pose& pose = other.pose;
  const double r = radiusOf(other);
  switch (def.type) {
    case ShapeType::Sphere:
      candidate(pose.position - r * n, 0);
      break;
    case ShapeType::Capsule: {
      // Both ends of the core, each inflated towards the plane (feature: which end).
      const Segment seg = capsuleSegment(other);
      candidate(seg.p0 - r * n, 0);
      if ((seg.p1 - seg.p0).norm() > kTinyLength) candidate(seg.p1 - r * n, 1);
      break;
    }
    case ShapeType::Box: {
      // The 8 corners; feature bits 0, 1, 2: the corner is on the + side of local x, y, z.
      const Vec3 h = 0.5 * def.size.cwiseAbs();
      for (std::uint32_t v = 0; v < 8; ++v) {
        const Vec3 corner((v & 1) ? h.x() : -h.x(), (v & 2) ? h.y() : -h.y(),
                          (v & 4) ? h.z() : -h.z());
        candidate(pose.toWorld(corner), v);
      }
      break;
    }
    case ShapeType::Cylinder: {
      // The deepest points of a cylinder are on the rims of its caps (centres centre -+ w
      // length/2, w the axis; cap 0 at -w, cap 1 at +w). For the cap facing the plane (outward
      // normal -+w against n) while the axis is within 60 degrees of n (|n.w| >= 1/2), four rim
      // points at the fixed directions +x, +y, -x, -y of the shape frame span the cap standing
      // on the plane (features 5 cap + 0..3). For each cap, the deepest rim point,
      // cap + r g / |g| with g = -(n - (n.w) w) the in-cap direction most against n (feature
      // 5 cap + 4), is added when it lies deeper than those: exact for a cylinder tilted on its
      // rim, and the two ends of the line of contact of one lying on its side.
      const Vec3 w = pose.orientation * Vec3::UnitZ();
      const std::array<Vec3, 4> rim{
          pose.orientation * Vec3::UnitX(), pose.orientation * Vec3::UnitY(),
          -(pose.orientation * Vec3::UnitX()), -(pose.orientation * Vec3::UnitY())};
      const double nw = n.dot(w);
      const Vec3 g = -(n - nw * w);
      const double half = 0.5 * std::max(def.length, 0.0);
      for (int cap = 0; cap < 2; ++cap) {
        const Vec3 centre = pose.position + (cap == 0 ? -half : half) * w;
        const auto base = static_cast<std::uint32_t>(5 * cap);
        const bool facing = cap == 0 ? nw >= 0.5 : nw <= -0.5;
        double deepest_fixed = -kInfinity;
        for (std::uint32_t k = 0; facing && k < 4; ++k) {
          const Vec3 y = centre + r * rim[k];
          deepest_fixed = std::max(deepest_fixed, depthOf(y));
          candidate(y, base + k);
        }
        const double gn = g.norm();
        if (gn > kTinyLength) {
          const Vec3 y = centre + (r / gn) * g;
          if (depthOf(y) > deepest_fixed + kDepthTolerance) candidate(y, base + 4);
        }
      }
      break;
    }
    case ShapeType::Ellipsoid: {
      // Smooth: its one deepest point, the support point against the plane's normal.
      const ConvexSupport support = makeSupport(other);
      candidate(support.support(-n), 0);
      break;
    }
    case ShapeType::Convex: {
      // Every vertex of the hull (feature: its index). A hull without prepared geometry is
      // prepared here: slow (Qhull per call), but correct.
      std::shared_ptr<const Geometry> owned;
      const Geometry* hull = other.geometry;
      if (hull == nullptr) hull = (owned = prepareGeometry(def)).get();
      const std::vector<Vec3>& vertices = hull->vertices();
      for (std::size_t v = 0; v < vertices.size(); ++v)
        candidate(pose.toWorld(vertices[v]), static_cast<std::uint32_t>(v));
      break;
    }
    default:
      return 0;  // a mesh or another plane: no contact with a plane
  }
  reduceManifold(out, first, n);
  return static_cast<int>(out.size() - first);
}

}  // namespace linx::collision
