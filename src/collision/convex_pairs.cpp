// General convex contact manifolds (collision/convex_pairs.hpp).
//
// 1. queryContact (GJK/EPA) gives the signed distance s and the unit normal n from a to b.
// 2. Each shape's supporting feature along the normal: a's in direction +n, b's in -n. A box or
//    hull gives its face whose outward normal is most aligned with the direction; a capsule its
//    segment (inflated by the radius) when lying across n, a cylinder its cap (as a regular
//    octagon fixed in the cylinder's frame, so ids are stable) when n is within 2 degrees of the
//    axis or its side line when n is within 2 degrees of perpendicular; otherwise one point.
// 3. With a face on one side (the reference, the face best aligned with n) and a face or segment
//    on the other (incident), the incident polygon is clipped by the reference's side planes,
//    each containing a reference edge and the direction n. A clipped point p of the incident
//    surface meets the reference plane (normal m, point r0) along n at q = p + t n with
//    t = (r0 - p) . m / (n . m); the depth is (p_a - p_b) . n and the point (p_a + p_b) / 2.
//    Two parallel segments (capsules side by side) overlap on an interval: its two ends.
//    Otherwise, or when clipping leaves nothing, the single GJK/EPA point.
// 4. Points with depth <= -margin are dropped; the rest are reduced to the deepest one (the
//    one farthest from the centroid among equally deep ones), the one farthest from it, and the
//    two that add the most area (if they add any), which keeps a resting box's four corners.
//
// A plane is collidePlane's (collision/primitive_pairs.cpp), for hulls too: every vertex with its
// exact depth below the plane.
#include "collision/convex_pairs.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <memory>
#include <numbers>

#include "collision/geometry.hpp"
#include "collision/gjk_epa.hpp"
#include "collision/manifold_reduction.hpp"
#include "collision/primitive_pairs.hpp"

namespace linx::collision {

namespace {

// Within 2 degrees: a capsule or cylinder side lies across the normal, a cylinder cap faces it.
const double kSideSin = std::sin(2.0 * std::numbers::pi / 180.0);
const double kCapCos = std::cos(2.0 * std::numbers::pi / 180.0);
constexpr int kCapSides = 8;  // a cylinder cap's polygon, inscribed in its circle

std::uint32_t mix(std::uint32_t h, std::uint32_t v) {
  h ^= v + 0x9e3779b9u + (h << 6) + (h >> 2);
  return h;
}

struct FeatureVertex {
  Vec3 p;            // world, on the shape's surface
  std::uint32_t id;  // stable within the shape
};

struct Feature {
  std::vector<FeatureVertex> points;  // 1: a point, 2: a segment, >= 3: a face polygon
  Vec3 normal = Vec3::UnitZ();        // a face's outward unit normal (world)
  std::uint32_t id = 0;               // which face / segment / point
};

/// Vertices of the cylinder cap z = sign * h as an octagon, in the shape frame.
Vec3 capVertex(const ConvexSupport& s, int k, double sign) {
  const double angle = 2.0 * std::numbers::pi * k / kCapSides;
  return Vec3(s.half.x() * std::cos(angle), s.half.x() * std::sin(angle), sign * s.half.z());
}

/// The feature of shape s that supports direction dir (world, unit): see step 2 above.
Feature supportingFeature(const ConvexSupport& s, const Vec3& dir) {
  using Core = ConvexSupport::Core;
  Feature f;
  const Vec3 axis = s.rotation.col(2);
  switch (s.core) {
    case Core::Point:
    case Core::Ellipsoid:  // smooth: the one point where it touches (the witness)
      break;
    case Core::Segment: {
      const double c = axis.dot(dir);
      if (std::abs(c) < kSideSin) {
        const Vec3 across = (dir - c * axis).normalized();
        f.points.push_back({s.position - s.half.z() * axis + s.radius * across, 1});
        f.points.push_back({s.position + s.half.z() * axis + s.radius * across, 2});
        f.id = 1;
        return f;
      }
      break;
    }
    case Core::Box: {
      const Vec3 d = s.rotation.transpose() * dir;
      int i = 0;
      d.cwiseAbs().maxCoeff(&i);
      const double sign = d[i] >= 0.0 ? 1.0 : -1.0;
      const int j = (i + 1) % 3, k = (i + 2) % 3;
      // Corners counter-clockwise about +e_i; reversed for the face -e_i.
      const double corners[4][2] = {{1, 1}, {-1, 1}, {-1, -1}, {1, -1}};
      for (int c = 0; c < 4; ++c) {
        const int cc = sign > 0.0 ? c : 3 - c;
        Vec3 local;
        local[i] = sign * s.half[i];
        local[j] = corners[cc][0] * s.half[j];
        local[k] = corners[cc][1] * s.half[k];
        const std::uint32_t id =
            (local.x() > 0 ? 1u : 0u) | (local.y() > 0 ? 2u : 0u) | (local.z() > 0 ? 4u : 0u);
        f.points.push_back({s.position + s.rotation * local, id});
      }
      Vec3 n = Vec3::Zero();
      n[i] = sign;
      f.normal = s.rotation * n;
      f.id = static_cast<std::uint32_t>(2 * i + (sign > 0.0 ? 1 : 0));
      return f;
    }
    case Core::Cylinder: {
      const double c = axis.dot(dir);
      if (std::abs(c) >= kCapCos) {
        const double sign = c > 0.0 ? 1.0 : -1.0;
        for (int k = 0; k < kCapSides; ++k) {
          const int kk = sign > 0.0 ? k : kCapSides - 1 - k;
          f.points.push_back({s.position + s.rotation * capVertex(s, kk, sign),
                              static_cast<std::uint32_t>((sign > 0.0 ? kCapSides : 0) + kk)});
        }
        f.normal = sign * axis;
        f.id = sign > 0.0 ? 1u : 0u;
        return f;
      }
      if (std::abs(c) <= kSideSin) {
        const Vec3 across = (dir - c * axis).normalized();
        f.points.push_back({s.position - s.half.z() * axis + s.half.x() * across, 100});
        f.points.push_back({s.position + s.half.z() * axis + s.half.x() * across, 101});
        f.id = 2;
        return f;
      }
      break;
    }
    case Core::Hull: {
      const int face = s.hull->supportFace(s.rotation.transpose() * dir);
      const HullFace& hf = s.hull->faces()[face];
      for (int v : hf.vertices)
        f.points.push_back(
            {s.position + s.rotation * s.hull->vertices()[v], static_cast<std::uint32_t>(v)});
      f.normal = s.rotation * hf.normal;
      f.id = static_cast<std::uint32_t>(face);
      return f;
    }
    case Core::Triangle: {
      const auto& t = s.triangle;
      const Vec3 n = (t[1] - t[0]).cross(t[2] - t[0]).normalized();
      if (n.dot(dir) >= 0.0) {
        f.points = {{t[0], 0}, {t[1], 1}, {t[2], 2}};
        f.normal = n;
        f.id = 0;
      } else {
        f.points = {{t[0], 0}, {t[2], 2}, {t[1], 1}};
        f.normal = -n;
        f.id = 1;
      }
      return f;
    }
  }
  f.points.push_back({s.support(dir), 0xffffu});
  f.id = 0xffffu;
  return f;
}

/// Sutherland-Hodgman: keeps the part of `poly` (a polygon, or a segment when it has 2 points)
/// on the positive side of the plane m . (x - r) >= 0; new vertices get ids from their edge.
std::vector<FeatureVertex> clipByPlane(const std::vector<FeatureVertex>& poly, const Vec3& m,
                                       const Vec3& r, std::uint32_t plane_id) {
  std::vector<FeatureVertex> out;
  const std::size_t n = poly.size();
  const std::size_t edges = n == 2 ? 1 : n;
  auto cut = [&](const FeatureVertex& P, const FeatureVertex& Q, double dp, double dq) {
    const double t = dp / (dp - dq);
    const std::uint32_t lo = std::min(P.id, Q.id), hi = std::max(P.id, Q.id);
    return FeatureVertex{P.p + t * (Q.p - P.p), mix(mix(mix(0x51u, lo), hi), plane_id)};
  };
  if (n == 2) {
    const double d0 = m.dot(poly[0].p - r), d1 = m.dot(poly[1].p - r);
    if (d0 >= 0.0) out.push_back(poly[0]);
    if ((d0 > 0.0 && d1 < 0.0) || (d0 < 0.0 && d1 > 0.0))
      out.push_back(cut(poly[0], poly[1], d0, d1));
    if (d1 >= 0.0) out.push_back(poly[1]);
    return out;
  }
  for (std::size_t i = 0; i < edges; ++i) {
    const FeatureVertex& P = poly[i];
    const FeatureVertex& Q = poly[(i + 1) % n];
    const double dp = m.dot(P.p - r), dq = m.dot(Q.p - r);
    if (dp >= 0.0) out.push_back(P);
    if ((dp > 0.0 && dq < 0.0) || (dp < 0.0 && dq > 0.0)) out.push_back(cut(P, Q, dp, dq));
  }
  return out;
}

/// Merges points that coincide (same place within 1e-9 m, same normal), keeping the first.
void mergeDuplicates(std::vector<ContactPoint>& pts) {
  std::vector<ContactPoint> kept;
  for (const ContactPoint& p : pts) {
    bool dup = false;
    for (const ContactPoint& k : kept)
      if ((k.point - p.point).squaredNorm() <= 1e-18 && k.normal.dot(p.normal) > 1.0 - 1e-9 &&
          std::abs(k.depth - p.depth) <= 1e-9)
        dup = true;
    if (!dup) kept.push_back(p);
  }
  pts.swap(kept);
}

/// The contact points of a and b given the GJK/EPA query q (q.hit): steps 2 to 4.
void buildManifold(const ConvexSupport& A, const ConvexSupport& B, const ContactQuery& q,
                   double margin, std::vector<ContactPoint>& pts) {
  const Vec3 n = q.normal;
  const Feature fa = supportingFeature(A, n);
  const Feature fb = supportingFeature(B, -n);
  pts.clear();
  auto add = [&](const Vec3& pa, const Vec3& pb, std::uint32_t id) {
    const double depth = (pa - pb).dot(n);
    if (!(depth > -margin)) return;
    pts.push_back(ContactPoint{0.5 * (pa + pb), n, depth, id});
  };
  const std::size_t na = fa.points.size(), nb = fb.points.size();
  if (na >= 2 && nb >= 2 && (na >= 3 || nb >= 3)) {
    // Reference: a face, the better aligned with n if both are faces.
    bool ref_is_a = na >= 3;
    if (na >= 3 && nb >= 3) ref_is_a = fa.normal.dot(n) >= -fb.normal.dot(n);
    const Feature& ref = ref_is_a ? fa : fb;
    const Feature& inc = ref_is_a ? fb : fa;
    const double along = n.dot(ref.normal);
    if (std::abs(along) > 1e-3) {
      Vec3 centre = Vec3::Zero();
      for (const FeatureVertex& v : ref.points) centre += v.p;
      centre /= static_cast<double>(ref.points.size());
      std::vector<FeatureVertex> poly = inc.points;
      for (std::size_t k = 0; k < ref.points.size() && !poly.empty(); ++k) {
        const Vec3& r0 = ref.points[k].p;
        const Vec3& r1 = ref.points[(k + 1) % ref.points.size()].p;
        Vec3 m = n.cross(r1 - r0);
        if (m.squaredNorm() <= 1e-30) continue;
        if (m.dot(centre - r0) < 0.0) m = -m;
        poly = clipByPlane(poly, m, r0, 0x1000u + static_cast<std::uint32_t>(k));
      }
      const Vec3& r0 = ref.points[0].p;
      const std::uint32_t base =
          mix(mix(mix(ref_is_a ? 1u : 2u, ref.id), inc.id), static_cast<std::uint32_t>(na));
      for (const FeatureVertex& v : poly) {
        const double t = (r0 - v.p).dot(ref.normal) / along;
        const Vec3 on_ref = v.p + t * n;
        if (ref_is_a)
          add(on_ref, v.p, mix(base, v.id));
        else
          add(v.p, on_ref, mix(base, v.id));
      }
    }
  } else if (na == 2 && nb == 2) {
    // Two segments: parallel ones touch along the overlap of their extents.
    const Vec3 da = fa.points[1].p - fa.points[0].p, db = fb.points[1].p - fb.points[0].p;
    if (da.cross(db).norm() <= kSideSin * da.norm() * db.norm()) {
      const Vec3 u = da.normalized();
      std::vector<FeatureVertex> seg = fb.points;
      seg = clipByPlane(seg, u, fa.points[0].p, 0x2000u);
      if (!seg.empty()) seg = clipByPlane(seg, -u, fa.points[1].p, 0x2001u);
      const std::uint32_t base = mix(mix(3u, fa.id), fb.id);
      for (const FeatureVertex& v : seg) {
        const Vec3 on_a = fa.points[0].p + u * u.dot(v.p - fa.points[0].p);
        add(on_a, v.p, mix(base, v.id));
      }
    }
  }
  // The GJK/EPA point when there is no manifold, or when the manifold misses the deepest point
  // (a feature approximated, as a cylinder's cap by its octagon).
  double deepest = -kInfinity;
  for (const ContactPoint& p : pts) deepest = std::max(deepest, p.depth);
  const double depth = -q.separation;
  if (pts.empty() || deepest < depth - 1e-6 - 1e-3 * std::abs(depth))
    add(q.point_a, q.point_b, mix(mix(4u, fa.id), fb.id));
  mergeDuplicates(pts);
  reduceManifold(pts, 0, n);
}

int appendPoints(const std::vector<ContactPoint>& pts, std::vector<ContactPoint>& out) {
  out.insert(out.end(), pts.begin(), pts.end());
  return static_cast<int>(pts.size());
}

int flipped(int (*routine)(const ShapeInstance&, const ShapeInstance&, double,
                           std::vector<ContactPoint>&),
            const ShapeInstance& a, const ShapeInstance& b, double margin,
            std::vector<ContactPoint>& out) {
  const std::size_t first = out.size();
  const int count = routine(b, a, margin, out);
  for (std::size_t k = first; k < out.size(); ++k) out[k].normal = -out[k].normal;
  return count;
}

/// Barycentric weights of p (on the triangle's plane) in triangle (a, b, c).
Vec3 barycentric(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 v0 = b - a, v1 = c - a, v2 = p - a;
  const double d00 = v0.dot(v0), d01 = v0.dot(v1), d11 = v1.dot(v1);
  const double d20 = v2.dot(v0), d21 = v2.dot(v1);
  const double denom = d00 * d11 - d01 * d01;
  if (!(denom > 0.0)) return Vec3(1.0 / 3.0, 1.0 / 3.0, 1.0 / 3.0);
  const double v = (d11 * d20 - d01 * d21) / denom;
  const double w = (d00 * d21 - d01 * d20) / denom;
  return Vec3(1.0 - v - w, v, w);
}

}  // namespace

int collideConvex(const ShapeInstance& a, const ShapeInstance& b, double margin,
                  std::vector<ContactPoint>& out) {
  const ShapeType ta = a.def->type, tb = b.def->type;
  if (isStaticOnly(ta) && isStaticOnly(tb)) return 0;
  if (tb == ShapeType::Mesh) return collideMesh(a, b, margin, out);
  if (ta == ShapeType::Mesh) return flipped(&collideMesh, a, b, margin, out);
  if (ta == ShapeType::Plane) return collidePlane(a, b, margin, out);
  if (tb == ShapeType::Plane) return flipped(&collidePlane, a, b, margin, out);

  // A hull without prepared geometry is prepared here: slow (Qhull per call), but correct.
  std::shared_ptr<const Geometry> own_a, own_b;
  ShapeInstance ia = a, ib = b;
  if (ta == ShapeType::Convex && ia.geometry == nullptr)
    ia.geometry = (own_a = prepareGeometry(*a.def)).get();
  if (tb == ShapeType::Convex && ib.geometry == nullptr)
    ib.geometry = (own_b = prepareGeometry(*b.def)).get();
  const ConvexSupport A = makeSupport(ia), B = makeSupport(ib);
  const ContactQuery q = queryContact(A, B, margin);
  if (!q.hit) return 0;
  std::vector<ContactPoint> pts;
  buildManifold(A, B, q, margin, pts);
  return appendPoints(pts, out);
}

int collideMesh(const ShapeInstance& a, const ShapeInstance& mesh, double margin,
                std::vector<ContactPoint>& out) {
  if (isStaticOnly(a.def->type)) return 0;
  std::shared_ptr<const Geometry> owned;
  const Geometry* g = mesh.geometry;
  if (g == nullptr || g->kind() != Geometry::Kind::Mesh) {
    owned = prepareGeometry(*mesh.def);  // unprepared mesh: slow, but correct
    g = owned.get();
    if (g == nullptr || g->kind() != Geometry::Kind::Mesh) return 0;
  }
  std::shared_ptr<const Geometry> owned_a;
  ShapeInstance ia = a;
  if (a.def->type == ShapeType::Convex && a.geometry == nullptr)
    ia.geometry = (owned_a = prepareGeometry(*a.def)).get();
  const ConvexSupport A = makeSupport(ia);
  const Mat3 R = mesh.pose.orientation.normalized().toRotationMatrix();
  const Vec3& origin = mesh.pose.position;

  // a's box in the mesh frame, from its support along the mesh's axes, grown by the margin.
  Aabb box;
  for (int i = 0; i < 3; ++i) {
    const Vec3 e = R.col(i);
    box.max[i] = e.dot(A.support(e) - origin);
    box.min[i] = e.dot(A.support(-e) - origin);
  }
  box = box.expanded(std::max(margin, 0.0));
  std::vector<int> candidates;
  g->queryTriangles(box, candidates);

  std::vector<ContactPoint> all, pts;
  for (int t : candidates) {
    const auto& tri = g->triangles()[t];
    const Vec3 v[3] = {origin + R * g->vertices()[tri[0]], origin + R * g->vertices()[tri[1]],
                       origin + R * g->vertices()[tri[2]]};
    const ConvexSupport T = makeTriangleSupport(v[0], v[1], v[2]);
    const Vec3 tn = R * g->triangleNormals()[t];
    // The face normal on a's side of the triangle (a's centre in front or behind).
    const Vec3 f = (A.centre - v[0]).dot(tn) >= 0.0 ? tn : Vec3(-tn);
    ContactQuery q = queryContact(A, T, margin);
    if (!q.hit) continue;
    // Decide whether the normal must be the face normal: m = -n points from the triangle to a.
    const Vec3 m = -q.normal;
    // The witness point's feature on the triangle decides: the face region (which includes a
    // normal pushing a through the back), an inactive edge or an inactive vertex take f; an
    // active edge or vertex keeps the GJK/EPA normal.
    bool snap = false;
    if (m.dot(f) < 1.0 - 1e-12) {
      const Vec3 l = barycentric(q.point_b, v[0], v[1], v[2]);
      const double tol = 1e-7;
      const int zeros = (l[0] <= tol) + (l[1] <= tol) + (l[2] <= tol);
      if (zeros == 0) {
        snap = true;
      } else if (zeros == 1) {
        // Edge k runs from vertex k to k + 1; its opposite vertex k + 2 has weight ~0.
        int k = 0;
        for (int i = 0; i < 3; ++i)
          if (l[(i + 2) % 3] <= tol) k = i;
        snap = !g->edgeActive(t)[k];
      } else {
        int k = 0;
        for (int i = 0; i < 3; ++i)
          if (l[i] > tol) k = i;
        snap = !g->vertexActive(tri[k]);
      }
    }
    if (snap) {
      // The triangle as a plane with normal f: a's deepest point below it.
      const Vec3 p = A.support(-f);
      const double depth = (v[0] - p).dot(f);
      if (!(depth > -margin)) continue;
      q.normal = -f;
      q.separation = -depth;
      q.point_a = p;
      q.point_b = p + depth * f;
    }
    buildManifold(A, T, q, margin, pts);
    for (ContactPoint& p : pts)
      p.feature = mix(mix(0x7u, static_cast<std::uint32_t>(t)), p.feature);
    all.insert(all.end(), pts.begin(), pts.end());
  }
  mergeDuplicates(all);
  // Coplanar groups (the same normal from neighbouring triangles) reduce to 4 points each.
  std::vector<ContactPoint> result;
  std::vector<char> used(all.size(), 0);
  for (std::size_t i = 0; i < all.size(); ++i) {
    if (used[i]) continue;
    std::vector<ContactPoint> group;
    for (std::size_t j = i; j < all.size(); ++j)
      if (!used[j] && all[j].normal.dot(all[i].normal) > 1.0 - 1e-9) {
        used[j] = 1;
        group.push_back(all[j]);
      }
    reduceManifold(group, 0, all[i].normal);
    result.insert(result.end(), group.begin(), group.end());
  }
  return appendPoints(result, out);
}

}  // namespace linx::collision
