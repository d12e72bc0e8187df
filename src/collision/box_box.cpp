// Box against box, exactly: the separating axis test on the 15 candidate axes (3 face normals of
// each box, 9 cross products of an edge direction of a with one of b) gives the normal and the
// depth, then the contact is either a face manifold (the incident face of one box clipped against
// the side planes of the reference face of the other, Sutherland-Hodgman, reduced to at most 4
// points) or a single edge-edge point. Why clipping: a box resting on a box touches over an area,
// and only points spanning that area (not one deepest point) let it rest without rocking.
// Conventions: collision/narrowphase.hpp (normal from a to b, depth > 0 penetration, points while
// depth > -margin, point midway between the surfaces).
#include "collision/manifold_reduction.hpp"
#include "collision/primitive_pairs.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <utility>
#include <vector>

namespace linx::collision {

namespace {

/// A box in the world: its centre, its unit axes (the columns of the rotation) and half extents.
struct Box {
  Vec3 centre;
  Mat3 axes;
  Vec3 half;
};

Box boxOf(const ShapeInstance& s) {
  return {s.pose.position, s.pose.orientation.toRotationMatrix(), 0.5 * s.def->size.cwiseAbs()};
}

double signOf(double x) {
  return x < 0.0 ? -1.0 : 1.0;
}

/// Half width of the box's projection on the unit axis L: sum_k h_k |L.axis_k|.
double projectedRadius(const Box& box, const Vec3& L) {
  return box.half.dot((box.axes.transpose() * L).cwiseAbs());
}

/// Index of the face with outward normal sign * axis_k: 2k for -axis_k, 2k + 1 for +axis_k.
std::uint32_t faceIndex(int k, double sign) {
  return static_cast<std::uint32_t>(2 * k + (sign > 0.0 ? 1 : 0));
}

/// Index of the edge along axis k whose other coordinates have the signs of `dir` on the two
/// other axes: 4 k + (bit 0: + on axis (k + 1) % 3) + (bit 1: + on axis (k + 2) % 3).
int edgeIndex(const Box& box, int k, const Vec3& dir) {
  const int i = (k + 1) % 3, j = (k + 2) % 3;
  return 4 * k + (dir.dot(box.axes.col(i)) >= 0.0 ? 1 : 0) +
         (dir.dot(box.axes.col(j)) >= 0.0 ? 2 : 0);
}

/// The vertex of the box furthest along dir (ties to the + side).
Vec3 supportPoint(const Box& box, const Vec3& dir) {
  Vec3 p = box.centre;
  for (int k = 0; k < 3; ++k) p += signOf(dir.dot(box.axes.col(k))) * box.half[k] * box.axes.col(k);
  return p;
}

/// A vertex of the clipped polygon with the two edges meeting there, as tags: 0..3 the edges of
/// the incident face (edge m runs from its vertex m to m + 1), 4..7 the side planes of the
/// reference face. `in` is the edge arriving at the vertex, `out` the edge leaving it.
struct ClipVertex {
  Vec3 p;
  int in;
  int out;
};

/// A convex polygon of at most 8 vertices: a quadrilateral clipped by 4 planes gains at most one
/// vertex per plane. A fixed array, so that clipping allocates nothing.
struct Polygon {
  std::array<ClipVertex, 8> v{};
  std::size_t size = 0;
  void push(const ClipVertex& c) {
    if (size < v.size()) v[size++] = c;
  }
};

/// Sutherland-Hodgman step: keeps the part of the polygon with w.p <= o. A new vertex where the
/// edge P -> Q (tag P.out) crosses the plane joins that edge and the plane (tag `plane`).
Polygon clipPolygon(const Polygon& poly, const Vec3& w, double o, int plane) {
  Polygon result;
  const std::size_t n = poly.size;
  for (std::size_t m = 0; m < n; ++m) {
    const ClipVertex& P = poly.v[m];
    const ClipVertex& Q = poly.v[(m + 1) % n];
    const double dp = w.dot(P.p) - o, dq = w.dot(Q.p) - o;
    const bool p_in = dp <= 0.0, q_in = dq <= 0.0;
    if (p_in) result.push(P);
    if (p_in != q_in) {
      const Vec3 x = P.p + (dp / (dp - dq)) * (Q.p - P.p);
      if (p_in) {
        result.push({x, P.out, plane});  // leaving: arrives on the edge, leaves on the plane
      } else {
        result.push({x, plane, P.out});  // entering: arrives on the plane, leaves on the edge
      }
    }
  }
  return result;
}

/// The face manifold: reference face i of box `ref` (normal nr pointing towards `inc`), incident
/// face of `inc` the one most anti-parallel to nr. Each vertex p of the clipped incident face is
/// a point with separation sep = nr.(p - f), f the reference face centre (depth -sep), placed
/// midway between p and its projection p - sep nr on the reference face. The normal from a to b
/// is nr when the reference box is a, -nr when it is b. Feature: reference box and face (bits
/// 12..15), incident face (8..11), the unordered pair of edge tags at the vertex (4..7, 0..3).
int faceContact(const Box& ref, const Box& inc, int i, bool ref_is_b, double margin,
                std::vector<ContactPoint>& out) {
  const Vec3 t = inc.centre - ref.centre;
  const double sigma = signOf(ref.axes.col(i).dot(t));
  const Vec3 nr = sigma * ref.axes.col(i);
  const Vec3 face_centre = ref.centre + ref.half[i] * nr;
  const Vec3 normal = ref_is_b ? Vec3(-nr) : nr;

  // Incident face: axis j of inc with the largest |nr . axis_j|, on the side facing ref.
  int j = 0;
  (inc.axes.transpose() * nr).cwiseAbs().maxCoeff(&j);
  const double sj = -signOf(nr.dot(inc.axes.col(j)));
  const Vec3 inc_centre = inc.centre + sj * inc.half[j] * inc.axes.col(j);
  const int k = (j + 1) % 3, l = (j + 2) % 3;
  const Vec3 u = inc.half[k] * inc.axes.col(k), v = inc.half[l] * inc.axes.col(l);
  Polygon poly;
  poly.push({inc_centre + u + v, 3, 0});
  poly.push({inc_centre - u + v, 0, 1});
  poly.push({inc_centre - u - v, 1, 2});
  poly.push({inc_centre + u - v, 2, 3});

  // Side planes of the reference face: +-axis_a . (p - centre) <= h_a for its two other axes,
  // pushed out by a round-off allowance (1e-6 of the mean half extent) so that a box stacked
  // flush on an equal one keeps its own corners, and their ids, under tiny motions.
  const int a1 = (i + 1) % 3, a2 = (i + 2) % 3;
  const std::array<int, 2> side_axes{a1, a2};
  const double allowance = 1e-6 * ref.half.sum() / 3.0;
  int tag = 4;
  for (const int a : side_axes) {
    for (const double s : {1.0, -1.0}) {
      const Vec3 w = s * ref.axes.col(a);
      poly = clipPolygon(poly, w, w.dot(ref.centre) + ref.half[a] + allowance, tag++);
    }
  }

  const std::uint32_t ref_code = (ref_is_b ? 8u : 0u) | faceIndex(i, sigma);
  const std::uint32_t head = (ref_code << 12) | (faceIndex(j, sj) << 8);
  const std::size_t first = out.size();
  for (std::size_t m = 0; m < poly.size; ++m) {
    const ClipVertex& c = poly.v[m];
    const double sep = nr.dot(c.p - face_centre);
    if (!(sep < margin)) continue;
    const auto lo = static_cast<std::uint32_t>(std::min(c.in, c.out));
    const auto hi = static_cast<std::uint32_t>(std::max(c.in, c.out));
    out.push_back({c.p - 0.5 * sep * nr, normal, -sep, head | (lo << 4) | hi});
  }
  if (poly.size == 0) {
    // Only when the incident face misses the reference face entirely (deep, unusual overlaps):
    // the deepest vertex of inc along -nr, so that an overlap always yields a point.
    const Vec3 p = supportPoint(inc, -nr);
    const double sep = nr.dot(p - face_centre);
    if (sep < margin) out.push_back({p - 0.5 * sep * nr, normal, -sep, head | 0xffu});
  }
  reduceManifold(out, first, normal);
  return static_cast<int>(out.size() - first);
}

}  // namespace

int collideBoxBox(const ShapeInstance& a, const ShapeInstance& b, double margin,
                  std::vector<ContactPoint>& out) {
  const Box A = boxOf(a), B = boxOf(b);
  const Vec3 t = B.centre - A.centre;
  // Separation of the boxes along a unit axis L: |L.t| - rA(L) - rB(L); negative = overlap.
  auto separation = [&](const Vec3& L) {
    return std::abs(L.dot(t)) - projectedRadius(A, L) - projectedRadius(B, L);
  };
  double largest = -kInfinity;  // largest separation over all axes: > margin means no contact

  int face_a = 0, face_b = 0;
  double sep_a = -kInfinity, sep_b = -kInfinity;
  for (int k = 0; k < 3; ++k) {
    const double sa = separation(A.axes.col(k));
    if (sa > sep_a) {
      sep_a = sa;
      face_a = k;
    }
    const double sb = separation(B.axes.col(k));
    if (sb > sep_b) {
      sep_b = sb;
      face_b = k;
    }
  }
  largest = std::max(sep_a, sep_b);

  // Edge axes L = a_i x b_j / |a_i x b_j|, skipped for (nearly) parallel edges: then L is not
  // defined and the face axes already cover the direction.
  int edge_i = -1, edge_j = -1;
  double sep_e = -kInfinity;
  Vec3 edge_axis = Vec3::UnitZ();
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      const Vec3 cross = A.axes.col(i).cross(B.axes.col(j));
      const double len = cross.norm();
      if (len < 1e-6) continue;
      const Vec3 L = cross / len;
      const double s = separation(L);
      if (s > sep_e) {
        sep_e = s;
        edge_i = i;
        edge_j = j;
        edge_axis = L;
      }
    }
  }
  largest = std::max(largest, sep_e);
  if (!(largest < margin)) return 0;

  // Axis choice with a bias for stable manifolds: b's face must beat a's by kFaceBias, and an
  // edge pair must beat the best face by kEdgeBias (both scaled by the mean half extent), so a
  // resting box keeps the same reference face and a face manifold rather than flipping on
  // round-off. The reported depth is then at most the bias below the exact penetration.
  const double scale = (A.half.sum() + B.half.sum()) / 6.0;
  const double face_bias = 1e-4 * scale, edge_bias = 1e-3 * scale;
  const bool use_b = sep_b > sep_a + face_bias;
  const double sep_face = use_b ? sep_b : sep_a;
  if (edge_i < 0 || sep_e <= sep_face + edge_bias) {
    return use_b ? faceContact(B, A, face_b, true, margin, out)
                 : faceContact(A, B, face_a, false, margin, out);
  }

  // Edge-edge: n = L oriented from a to b. The edge of a along a_i furthest along n and the edge
  // of b along b_j furthest along -n; the point is midway between their closest points.
  const Vec3 n = signOf(edge_axis.dot(t)) * edge_axis;
  auto edgeEnds = [](const Box& box, int k, const Vec3& dir) {
    Vec3 c = box.centre;
    for (int m = 0; m < 3; ++m) {
      if (m != k) c += signOf(dir.dot(box.axes.col(m))) * box.half[m] * box.axes.col(m);
    }
    const Vec3 e = box.half[k] * box.axes.col(k);
    return std::pair<Vec3, Vec3>{c - e, c + e};
  };
  const auto [pa0, pa1] = edgeEnds(A, edge_i, n);
  const auto [pb0, pb1] = edgeEnds(B, edge_j, -n);
  const auto [s, u] = detail::closestSegmentParams(pa0, pa1, pb0, pb1);
  const Vec3 pa = pa0 + s * (pa1 - pa0), pb = pb0 + u * (pb1 - pb0);
  const auto ea = static_cast<std::uint32_t>(edgeIndex(A, edge_i, n));
  const auto eb = static_cast<std::uint32_t>(edgeIndex(B, edge_j, -n));
  out.push_back({0.5 * (pa + pb), n, -sep_e, (1u << 16) | (ea << 4) | eb});
  return 1;
}

}  // namespace linx::collision
