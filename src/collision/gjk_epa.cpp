// GJK and EPA (collision/gjk_epa.hpp).
//
// GJK keeps a simplex of up to 4 points w_i = a_i - b_i of Z = A - B and the point v of the
// simplex closest to the origin, with barycentric weights l_i (v = sum l_i w_i, so the witness
// points are a = sum l_i a_i and b = sum l_i b_i). Each step takes the support point w = s_Z(-v);
// v . w / |v| is a lower bound of the distance and |v| an upper bound, so it stops when
// |v| - v.w/|v| <= eps (converged), when w adds nothing new, when |v| stops decreasing (roundoff),
// or when the lower bound exceeds the distance of interest. The closest point of a segment,
// triangle or tetrahedron is found by its Voronoi regions (Ericson, Real-Time Collision
// Detection, 5.1), keeping only the vertices of the feature that holds it; a degenerate
// (collinear, coplanar) simplex falls back to its sub-simplices, so no division by ~0 occurs.
//
// EPA starts from a tetrahedron around the origin (GJK's final simplex, blown up along extra
// support directions when GJK stopped on a lower-dimensional one), then repeatedly takes the face
// nearest to the origin, with unit outward normal n at distance d, adds w = s_Z(n) and stops
// when n . w - d <= eps: that face is on the boundary of Z, the depth is d and the normal n. To
// add w, the faces w sees are removed (a flood fill from the nearest face, so the removed region
// stays connected) and the horizon edges are joined to w. Faces are oriented away from a point
// inside the first tetrahedron (which stays inside the growing polytope).
#include "collision/gjk_epa.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <queue>
#include <stdexcept>
#include <unordered_map>
#include <vector>

#include "collision/geometry.hpp"

namespace linx::collision {

// --- Support functions ---

Vec3 ConvexSupport::coreSupport(const Vec3& dir) const {
  const Vec3 d = rotation.transpose() * dir;  // into the shape frame
  Vec3 local = Vec3::Zero();
  switch (core) {
    case Core::Point:
      break;
    case Core::Segment:
      local.z() = d.z() >= 0.0 ? half.z() : -half.z();
      break;
    case Core::Box:
      for (int i = 0; i < 3; ++i) local[i] = d[i] >= 0.0 ? half[i] : -half[i];
      break;
    case Core::Cylinder: {
      // The rim point: radius along the direction's component across the axis, the cap it faces.
      const double rho = std::hypot(d.x(), d.y());
      if (rho > 1e-12 * d.norm()) {
        local.x() = half.x() * d.x() / rho;
        local.y() = half.x() * d.y() / rho;
      }
      local.z() = d.z() >= 0.0 ? half.z() : -half.z();
      break;
    }
    case Core::Hull:
      local = hull->vertices()[hull->supportVertex(d)];
      break;
    case Core::Ellipsoid: {
      // The point of x^T D^-2 x = 1 (D = diag(half), the semi-axes) whose normal is d:
      // x = D^2 d / |D d|.
      const Vec3 scaled = half.cwiseProduct(d);
      const double length = scaled.norm();
      if (length > 0.0) local = half.cwiseProduct(scaled) / length;
      break;
    }
    case Core::Triangle: {
      int best = 0;
      for (int i = 1; i < 3; ++i)
        if (triangle[i].dot(d) > triangle[best].dot(d)) best = i;
      local = triangle[best];
      break;
    }
  }
  return position + rotation * local;
}

Vec3 ConvexSupport::support(const Vec3& dir) const {
  const Vec3 p = coreSupport(dir);
  if (radius == 0.0) return p;
  const double len = dir.norm();
  return len > 0.0 ? Vec3(p + radius / len * dir) : p;
}

ConvexSupport makeSupport(const ShapeInstance& shape) {
  const ShapeDef& def = *shape.def;
  ConvexSupport s;
  s.position = shape.pose.position;
  s.rotation = shape.pose.orientation.normalized().toRotationMatrix();
  s.centre = s.position;
  switch (def.type) {
    case ShapeType::Sphere:
      s.core = ConvexSupport::Core::Point;
      s.radius = def.radius;
      s.size = def.radius;
      break;
    case ShapeType::Capsule:
      s.core = ConvexSupport::Core::Segment;
      s.radius = def.radius;
      s.half = Vec3(0.0, 0.0, 0.5 * def.length);
      s.size = def.radius + 0.5 * def.length;
      break;
    case ShapeType::Box:
      s.core = ConvexSupport::Core::Box;
      s.half = 0.5 * def.size;
      s.size = s.half.norm();
      break;
    case ShapeType::Cylinder:
      s.core = ConvexSupport::Core::Cylinder;
      s.half = Vec3(def.radius, def.radius, 0.5 * def.length);
      s.size = std::hypot(def.radius, 0.5 * def.length);
      break;
    case ShapeType::Ellipsoid:
      s.core = ConvexSupport::Core::Ellipsoid;
      s.half = def.radii.cwiseAbs();
      s.size = s.half.maxCoeff();
      break;
    case ShapeType::Convex: {
      if (shape.geometry == nullptr)
        throw std::invalid_argument("convex shape without prepared geometry (prepareGeometry)");
      s.core = ConvexSupport::Core::Hull;
      s.hull = shape.geometry;
      const Vec3 c = shape.geometry->centroid();
      s.centre = s.position + s.rotation * c;
      for (const Vec3& v : shape.geometry->vertices()) s.size = std::max(s.size, (v - c).norm());
      break;
    }
    case ShapeType::Plane:
    case ShapeType::Mesh:
      throw std::invalid_argument("a plane or mesh has no support function");
  }
  return s;
}

ConvexSupport makeTriangleSupport(const Vec3& a, const Vec3& b, const Vec3& c) {
  ConvexSupport s;
  s.core = ConvexSupport::Core::Triangle;
  s.triangle = {a, b, c};
  s.centre = (a + b + c) / 3.0;
  for (const Vec3& p : s.triangle) s.size = std::max(s.size, (p - s.centre).norm());
  return s;
}

namespace {

struct SupportPoint {
  Vec3 w, a, b;  // w = a - b
};

SupportPoint supportZ(const ConvexSupport& A, const ConvexSupport& B, const Vec3& d, bool cores) {
  SupportPoint p;
  p.a = cores ? A.coreSupport(d) : A.support(d);
  p.b = cores ? B.coreSupport(-d) : B.support(-d);
  p.w = p.a - p.b;
  return p;
}

/// A simplex with the barycentric weights of its closest point to the origin.
struct Simplex {
  SupportPoint p[4];
  double l[4] = {0, 0, 0, 0};
  int n = 0;

  Vec3 closest() const {
    Vec3 v = Vec3::Zero();
    for (int i = 0; i < n; ++i) v += l[i] * p[i].w;
    return v;
  }
  void witnesses(Vec3& a, Vec3& b) const {
    a.setZero();
    b.setZero();
    for (int i = 0; i < n; ++i) {
      a += l[i] * p[i].a;
      b += l[i] * p[i].b;
    }
  }
  /// Keeps the listed vertices with their weights.
  void keep(std::initializer_list<std::pair<int, double>> kept) {
    SupportPoint q[4];
    double m[4];
    int k = 0;
    for (const auto& [i, w] : kept) {
      q[k] = p[i];
      m[k] = w;
      ++k;
    }
    for (int i = 0; i < k; ++i) {
      p[i] = q[i];
      l[i] = m[i];
    }
    n = k;
  }
};

/// Closest point of segment (p[i], p[j]) to the origin: (squared distance, weight of j).
double segmentClosest(const Vec3& a, const Vec3& b, double& t) {
  const Vec3 ab = b - a;
  const double len2 = ab.squaredNorm();
  t = len2 > 0.0 ? std::clamp(-a.dot(ab) / len2, 0.0, 1.0) : 0.0;
  return (a + t * ab).squaredNorm();
}

void reduceSegment(Simplex& s) {
  double t = 0.0;
  segmentClosest(s.p[0].w, s.p[1].w, t);
  if (t <= 0.0)
    s.keep({{0, 1.0}});
  else if (t >= 1.0)
    s.keep({{1, 1.0}});
  else
    s.keep({{0, 1.0 - t}, {1, t}});
}

/// Ericson's closest point of triangle (a, b, c) to the origin by Voronoi regions; returns the
/// squared distance and the simplex reduced to the feature holding it.
void reduceTriangle(Simplex& s, int i0 = 0, int i1 = 1, int i2 = 2) {
  const Vec3 a = s.p[i0].w, b = s.p[i1].w, c = s.p[i2].w;
  const Vec3 ab = b - a, ac = c - a;
  const Vec3 normal = ab.cross(ac);
  const double scale2 = std::max(ab.squaredNorm(), ac.squaredNorm());
  if (normal.squaredNorm() <= 1e-24 * scale2 * scale2) {
    // Degenerate (collinear) triangle: the best of its three sides.
    const int pairs[3][2] = {{i0, i1}, {i1, i2}, {i0, i2}};
    int best = 0;
    double best_d = kInfinity, best_t = 0.0;
    for (int k = 0; k < 3; ++k) {
      double t = 0.0;
      const double d = segmentClosest(s.p[pairs[k][0]].w, s.p[pairs[k][1]].w, t);
      if (d < best_d) {
        best_d = d;
        best_t = t;
        best = k;
      }
    }
    s.keep({{pairs[best][0], 1.0 - best_t}, {pairs[best][1], best_t}});
    if (s.l[1] <= 0.0)
      s.keep({{0, 1.0}});
    else if (s.l[0] <= 0.0)
      s.keep({{1, 1.0}});
    return;
  }
  const double d1 = -ab.dot(a), d2 = -ac.dot(a);
  if (d1 <= 0.0 && d2 <= 0.0) return s.keep({{i0, 1.0}});
  const double d3 = -ab.dot(b), d4 = -ac.dot(b);
  if (d3 >= 0.0 && d4 <= d3) return s.keep({{i1, 1.0}});
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) {
    const double t = d1 / (d1 - d3);
    return s.keep({{i0, 1.0 - t}, {i1, t}});
  }
  const double d5 = -ab.dot(c), d6 = -ac.dot(c);
  if (d6 >= 0.0 && d5 <= d6) return s.keep({{i2, 1.0}});
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) {
    const double t = d2 / (d2 - d6);
    return s.keep({{i0, 1.0 - t}, {i2, t}});
  }
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0.0 && d4 - d3 >= 0.0 && d5 - d6 >= 0.0) {
    const double t = (d4 - d3) / ((d4 - d3) + (d5 - d6));
    return s.keep({{i1, 1.0 - t}, {i2, t}});
  }
  const double denom = 1.0 / (va + vb + vc);
  const double v = vb * denom, w = vc * denom;
  s.keep({{i0, 1.0 - v - w}, {i1, v}, {i2, w}});
}

/// The tetrahedron's closest point: inside it (returns true) or on the nearest face the origin
/// is outside of. A face whose plane also holds the opposite vertex (flat tetrahedron) counts as
/// one the origin may be outside of.
bool reduceTetrahedron(Simplex& s) {
  static const int faces[4][4] = {{0, 1, 2, 3}, {0, 2, 3, 1}, {0, 3, 1, 2}, {1, 3, 2, 0}};
  bool outside_any = false;
  Simplex best;
  double best_d = kInfinity;
  for (const auto& f : faces) {
    const Vec3& a = s.p[f[0]].w;
    const Vec3 n = (s.p[f[1]].w - a).cross(s.p[f[2]].w - a);
    const double side_origin = -n.dot(a);
    const double side_opposite = n.dot(s.p[f[3]].w - a);
    const double scale = n.norm() * (s.p[f[3]].w - a).norm();
    const bool flat = std::abs(side_opposite) <= 1e-12 * scale;
    if (!flat && side_origin * side_opposite >= 0.0) continue;  // origin on the inner side
    outside_any = true;
    Simplex t = s;
    reduceTriangle(t, f[0], f[1], f[2]);
    const double d = t.closest().squaredNorm();
    if (d < best_d) {
      best_d = d;
      best = t;
    }
  }
  if (!outside_any) {
    // The origin is inside: the weights no longer matter for the witnesses.
    return true;
  }
  s = best;
  return false;
}

struct GjkState {
  Simplex simplex;
  Vec3 v = Vec3::Zero();
  bool overlap = false;
  bool beyond = false;
};

GjkState runGjk(const ConvexSupport& A, const ConvexSupport& B, bool cores, double max_distance) {
  const double scale = std::max(A.size + B.size, 1e-9);
  const double abs_tol = 1e-12 * scale;  // distance tolerance (m)
  const double touch = 1e-10 * scale;    // below this the shapes touch: overlap
  GjkState st;
  Simplex& s = st.simplex;
  Vec3 v = A.centre - B.centre;
  if (v.squaredNorm() <= touch * touch) v = Vec3::UnitX() * scale;
  double vv = kInfinity;  // |v|^2 of the simplex's closest point (none yet)
  for (int iter = 0; iter < 128; ++iter) {
    const SupportPoint w = supportZ(A, B, -v, cores);
    const double vlen = v.norm();
    const double vw = v.dot(w.w);
    if (vw > 0.0 && vw > vlen * max_distance) {
      st.beyond = true;  // the lower bound v.w/|v| already exceeds max_distance
      break;
    }
    if (s.n > 0) {
      if (vlen - vw / vlen <= 1e-10 * vlen + abs_tol) break;  // converged
      bool duplicate = false;
      for (int i = 0; i < s.n; ++i)
        if ((s.p[i].w - w.w).squaredNorm() <= abs_tol * abs_tol) duplicate = true;
      if (duplicate) break;
    }
    s.p[s.n] = w;
    s.l[s.n] = 1.0;
    ++s.n;
    const Simplex before = s;
    if (s.n == 2) reduceSegment(s);
    if (s.n == 3) reduceTriangle(s);
    if (s.n == 4 && reduceTetrahedron(s)) {
      st.overlap = true;
      st.v = Vec3::Zero();
      return st;
    }
    const Vec3 next = s.closest();
    const double next2 = next.squaredNorm();
    if (next2 <= touch * touch) {
      st.overlap = true;
      st.v = next;
      return st;
    }
    if (next2 >= vv) {
      // No progress (roundoff): keep the previous simplex and stop.
      s = before;
      s.n = before.n - 1;
      break;
    }
    vv = next2;
    v = next;
  }
  st.v = s.n > 0 ? s.closest() : v;
  return st;
}

}  // namespace

GjkResult gjkDistance(const ConvexSupport& a, const ConvexSupport& b, bool cores,
                      double max_distance) {
  const GjkState st = runGjk(a, b, cores, max_distance);
  GjkResult r;
  r.overlap = st.overlap;
  r.beyond = st.beyond;
  if (st.simplex.n > 0) st.simplex.witnesses(r.point_a, r.point_b);
  r.distance = r.overlap ? 0.0 : st.v.norm();
  return r;
}

// --- EPA ---

namespace {

struct EpaFace {
  int v[3];
  Vec3 n;
  double dist;
  bool alive;
  bool degenerate;
};

class Polytope {
 public:
  // A polytope approximating a curved Z improves by about one vertex per iteration; these caps
  // bound the cost of deep curved contacts (their depth is then good to ~1e-4 relative).
  static constexpr int kMaxIterations = 128;
  static constexpr std::size_t kMaxPoints = 256;

  /// With `cores`, the polytope grows in the difference of the cores (radii ignored).
  Polytope(const ConvexSupport& A, const ConvexSupport& B, bool cores)
      : A_(A), B_(B), cores_(cores) {
    scale_ = std::max(A.size + B.size, 1e-9);
    edges_.reserve(1024);
    points_.reserve(kMaxPoints);
  }

  /// Builds the first tetrahedron from GJK's simplex; false when Z is flat (cannot happen for
  /// solids, but a defensive exit keeps us from NaN).
  bool init(const Simplex& simplex) {
    for (int i = 0; i < simplex.n; ++i) points_.push_back(simplex.p[i]);
    const double eps = 1e-9 * scale_;
    if (points_.empty()) points_.push_back(supportZ(A_, B_, Vec3::UnitX(), cores_));
    if (points_.size() == 1) {
      const Vec3 dirs[6] = {Vec3::UnitX(),  -Vec3::UnitX(), Vec3::UnitY(),
                            -Vec3::UnitY(), Vec3::UnitZ(),  -Vec3::UnitZ()};
      for (const Vec3& d : dirs) {
        const SupportPoint p = supportZ(A_, B_, d, cores_);
        if ((p.w - points_[0].w).norm() > eps) {
          points_.push_back(p);
          break;
        }
      }
      if (points_.size() < 2) return false;
    }
    if (points_.size() == 2) {
      const Vec3 axis = (points_[1].w - points_[0].w).normalized();
      Vec3 least = Vec3::Zero();
      int k = 0;
      axis.cwiseAbs().minCoeff(&k);
      least[k] = 1.0;
      const Vec3 perp = axis.cross(least).normalized();
      // Search around the segment in steps of 60 degrees for a point off its line.
      for (int step = 0; step < 6 && points_.size() < 3; ++step) {
        const Vec3 d = Eigen::AngleAxisd(step * 3.14159265358979323846 / 3.0, axis) * perp;
        const SupportPoint p = supportZ(A_, B_, d, cores_);
        const Vec3 off = (p.w - points_[0].w) - axis * axis.dot(p.w - points_[0].w);
        if (off.norm() > eps) points_.push_back(p);
      }
      if (points_.size() < 3) return false;
    }
    if (points_.size() == 3) {
      const Vec3 n = (points_[1].w - points_[0].w).cross(points_[2].w - points_[0].w);
      if (n.squaredNorm() == 0.0) return false;
      const Vec3 un = n.normalized();
      SupportPoint p = supportZ(A_, B_, un, cores_);
      if (std::abs(un.dot(p.w - points_[0].w)) <= eps) p = supportZ(A_, B_, -un, cores_);
      if (std::abs(un.dot(p.w - points_[0].w)) <= eps) return false;
      points_.push_back(p);
    }
    const Vec3 e1 = points_[1].w - points_[0].w, e2 = points_[2].w - points_[0].w,
               e3 = points_[3].w - points_[0].w;
    const double det = e3.dot(e1.cross(e2));
    if (std::abs(det) <= 1e-15 * scale_ * scale_ * scale_) return false;
    // Faces (0,1,2), (0,3,1), (0,2,3), (1,3,2) point outwards when det(e1, e2, e3) < 0.
    if (det > 0.0) std::swap(points_[1], points_[2]);
    interior_ = 0.25 * (points_[0].w + points_[1].w + points_[2].w + points_[3].w);
    addFace(0, 1, 2);
    addFace(0, 3, 1);
    addFace(0, 2, 3);
    addFace(1, 3, 2);
    return !broken_;
  }

  /// Expands until the nearest face is on Z's boundary; the result's face index, or -1.
  int expand() {
    const double abs_tol = 1e-10 * scale_;
    int best = -1;
    for (int iter = 0; iter < kMaxIterations && !broken_; ++iter) {
      best = nearest();
      if (best < 0) return -1;
      const EpaFace face = faces_[best];
      const SupportPoint w = supportZ(A_, B_, face.n, cores_);
      const double gain = face.n.dot(w.w) - face.dist;
      if (gain <= abs_tol + 1e-9 * std::abs(face.dist)) return best;  // converged
      if (points_.size() >= kMaxPoints) return best;
      // Is w new? A duplicate would make zero-area faces forever.
      for (const SupportPoint& p : points_)
        if ((p.w - w.w).squaredNorm() <= abs_tol * abs_tol) return best;
      const int wi = static_cast<int>(points_.size());
      points_.push_back(w);
      if (!addPoint(best, wi)) return best;
    }
    return best;
  }

  const EpaFace& face(int f) const { return faces_[f]; }
  const SupportPoint& point(int i) const { return points_[i]; }

 private:
  static std::uint64_t key(int i, int j) {
    return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(i)) << 32) |
           static_cast<std::uint32_t>(j);
  }

  void addFace(int i, int j, int k) {
    const Vec3 a = points_[i].w, b = points_[j].w, c = points_[k].w;
    Vec3 n = (b - a).cross(c - a);
    const double len = n.norm();
    const double scale2 = std::max({(b - a).squaredNorm(), (c - a).squaredNorm(), 1e-300});
    EpaFace f{{i, j, k}, Vec3::UnitZ(), kInfinity, true, false};
    if (len <= 1e-14 * scale2) {
      f.degenerate = true;  // kept for the topology, never chosen as nearest
    } else {
      n /= len;
      if (n.dot(a - interior_) < 0.0) {
        // Orientation must agree with the neighbours; a flip here means roundoff broke it.
        broken_ = true;
      }
      f.n = n;
      f.dist = n.dot(a);
    }
    const int index = static_cast<int>(faces_.size());
    for (int e = 0; e < 3; ++e) {
      // A directed edge already present: non-manifold; give up with the best face so far.
      if (!edges_.emplace(key(f.v[e], f.v[(e + 1) % 3]), index).second) broken_ = true;
    }
    faces_.push_back(f);
    if (!f.degenerate) queue_.emplace(f.dist, index);
  }

  /// The live face nearest to the origin (lowest index among ties); dead faces leave the heap
  /// lazily.
  int nearest() {
    while (!queue_.empty() && !faces_[queue_.top().second].alive) queue_.pop();
    return queue_.empty() ? -1 : queue_.top().second;
  }

  bool sees(const EpaFace& f, const Vec3& w) const {
    if (f.degenerate) return true;  // removed with any visible neighbour
    return f.n.dot(w - points_[f.v[0]].w) > 1e-12 * scale_;
  }

  /// Removes the faces visible from point wi (connected to `start`) and fans the horizon to wi.
  bool addPoint(int start, int wi) {
    const Vec3& w = points_[wi].w;
    std::vector<int> visible{start};
    std::vector<char> seen(faces_.size(), 0);
    seen[start] = 1;
    std::vector<std::pair<int, int>> horizon;
    for (std::size_t q = 0; q < visible.size(); ++q) {
      const EpaFace& f = faces_[visible[q]];
      for (int e = 0; e < 3; ++e) {
        const int i = f.v[e], j = f.v[(e + 1) % 3];
        const auto it = edges_.find(key(j, i));
        if (it == edges_.end()) return false;
        const int g = it->second;
        if (seen[g] == 1) continue;
        if (sees(faces_[g], w)) {
          seen[g] = 1;
          visible.push_back(g);
        }
      }
    }
    for (int f : visible) {
      const EpaFace& face = faces_[f];
      for (int e = 0; e < 3; ++e) {
        const int i = face.v[e], j = face.v[(e + 1) % 3];
        const int g = edges_.at(key(j, i));
        if (seen[g] != 1) horizon.emplace_back(i, j);
      }
    }
    for (int f : visible) {
      faces_[f].alive = false;
      for (int e = 0; e < 3; ++e) edges_.erase(key(faces_[f].v[e], faces_[f].v[(e + 1) % 3]));
    }
    for (const auto& [i, j] : horizon) addFace(i, j, wi);
    return !broken_;
  }

  const ConvexSupport& A_;
  const ConvexSupport& B_;
  bool cores_ = false;
  double scale_ = 1.0;
  Vec3 interior_ = Vec3::Zero();
  std::vector<SupportPoint> points_;
  std::vector<EpaFace> faces_;
  std::unordered_map<std::uint64_t, int> edges_;  // directed edge -> face holding it
  std::priority_queue<std::pair<double, int>, std::vector<std::pair<double, int>>, std::greater<>>
      queue_;  // (distance, face) of the faces that may be nearest
  bool broken_ = false;
};

/// Barycentric weights of the projection of p on triangle (a, b, c), clamped to the triangle.
Eigen::Vector3d barycentric(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 v0 = b - a, v1 = c - a, v2 = p - a;
  const double d00 = v0.dot(v0), d01 = v0.dot(v1), d11 = v1.dot(v1);
  const double d20 = v2.dot(v0), d21 = v2.dot(v1);
  const double denom = d00 * d11 - d01 * d01;
  if (!(std::abs(denom) > 0.0)) return Eigen::Vector3d(1.0, 0.0, 0.0);
  double v = (d11 * d20 - d01 * d21) / denom;
  double w = (d00 * d21 - d01 * d20) / denom;
  double u = 1.0 - v - w;
  u = std::max(u, 0.0);
  v = std::max(v, 0.0);
  w = std::max(w, 0.0);
  const double sum = u + v + w;
  return sum > 0.0 ? Eigen::Vector3d(u / sum, v / sum, w / sum) : Eigen::Vector3d(1.0, 0.0, 0.0);
}

}  // namespace

namespace {

/// EPA on the full shapes or on their cores, from GJK's final simplex of the same shapes.
Penetration runEpa(const ConvexSupport& a, const ConvexSupport& b, bool cores, const GjkState& st) {
  Penetration r;
  Polytope poly(a, b, cores);
  if (!poly.init(st.simplex)) return r;
  const int f = poly.expand();
  if (f < 0) return r;
  const EpaFace& face = poly.face(f);
  if (!face.n.allFinite() || !std::isfinite(face.dist)) return r;
  const SupportPoint& p0 = poly.point(face.v[0]);
  const SupportPoint& p1 = poly.point(face.v[1]);
  const SupportPoint& p2 = poly.point(face.v[2]);
  const Eigen::Vector3d l = barycentric(face.dist * face.n, p0.w, p1.w, p2.w);
  r.valid = true;
  r.normal = face.n;
  r.depth = std::max(face.dist, 0.0);
  r.point_a = l[0] * p0.a + l[1] * p1.a + l[2] * p2.a;
  r.point_b = l[0] * p0.b + l[1] * p1.b + l[2] * p2.b;
  return r;
}

}  // namespace

Penetration epaPenetration(const ConvexSupport& a, const ConvexSupport& b) {
  Penetration r;
  const GjkState st = runGjk(a, b, false, kInfinity);
  if (!st.overlap) {
    // Separated after all: report the (negative) depth along the GJK direction.
    Vec3 pa, pb;
    st.simplex.witnesses(pa, pb);
    const double d = st.v.norm();
    if (d > 0.0) {
      r.valid = true;
      r.normal = -st.v / d;
      r.depth = -d;
      r.point_a = pa;
      r.point_b = pb;
    }
    return r;
  }
  return runEpa(a, b, false, st);
}

ContactQuery queryContact(const ConvexSupport& a, const ConvexSupport& b, double max_separation) {
  ContactQuery q;
  const double radii = a.radius + b.radius;
  const double scale = std::max(a.size + b.size, 1e-9);
  const GjkState st = runGjk(a, b, true, max_separation + radii);
  if (st.beyond) return q;
  if (!st.overlap) {
    const double d = st.v.norm();
    if (d > 1e-9 * scale) {
      Vec3 pa, pb;
      st.simplex.witnesses(pa, pb);
      q.normal = -st.v / d;  // v = a - b: the normal from a to b is -v / |v|
      q.separation = d - radii;
      q.point_a = pa + a.radius * q.normal;
      q.point_b = pb - b.radius * q.normal;
      q.hit = q.separation < max_separation;
      return q;
    }
  }
  // The cores overlap (or touch). The difference of the inflated shapes is the cores'
  // difference Z grown by r = r_a + r_b, so the depth is Z's own depth plus r along the same
  // normal: EPA on the cores when Z is solid (it is flat for two points, a point and a segment,
  // two segments), else EPA on the full shapes.
  Penetration p;
  if (radii > 0.0 && st.overlap) {
    if (a.core == ConvexSupport::Core::Point && b.core == ConvexSupport::Core::Point) {
      // Concentric spheres (within the tolerance): any direction; the centre line if any.
      const Vec3 d = b.centre - a.centre;
      p.valid = true;
      p.normal = d.norm() > 0.0 ? Vec3(d.normalized()) : Vec3::UnitZ();
      p.depth = radii - d.norm();
      p.point_a = a.centre + a.radius * p.normal;
      p.point_b = b.centre - b.radius * p.normal;
    } else {
      p = runEpa(a, b, true, st);
      if (p.valid) {
        p.depth += radii;
        p.point_a += a.radius * p.normal;
        p.point_b -= b.radius * p.normal;
      }
    }
  }
  if (!p.valid) p = epaPenetration(a, b);
  if (p.valid && p.normal.allFinite()) {
    q.normal = p.normal;
    q.separation = -p.depth;
    q.point_a = p.point_a;
    q.point_b = p.point_b;
  } else {
    // Fallback: the centre line, with the overlap of the supports along it.
    Vec3 n = b.centre - a.centre;
    n = n.norm() > 1e-12 * scale ? Vec3(n.normalized()) : Vec3::UnitZ();
    q.normal = n;
    q.point_a = a.support(n);
    q.point_b = b.support(-n);
    q.separation = (q.point_b - q.point_a).dot(n);
  }
  q.hit = q.separation < max_separation;
  return q;
}

}  // namespace linx::collision
