// Preparing hulls and meshes (collision/geometry.hpp).
//
// Hull: Qhull (reentrant C API) computes the facets; Qhull merges facets that are coplanar within
// roundoff (its default "C-0" for 3-d) and, with "A-0.99999", facets within about 0.25 degrees of
// each other, so a box's 8 corners give 6 quadrilaterals, not 12 triangles: the contact manifold
// clips whole faces. Each facet's vertices are ordered counter-clockwise about its outward normal
// by their angle in the facet plane.
//
// Mass properties: each face polygon is fanned into triangles (v0, vi, vi+1) and each triangle
// with a reference point o inside the hull makes a tetrahedron of signed volume
// V = (a - o) . ((b - o) x (c - o)) / 6 and centroid (o + a + b + c) / 4. With the four vertices
// x0..x3 relative to o, the second moment of the tetrahedron is
// C = integral of x x^T dV = V / 20 (sum_i x_i x_i^T + (sum_i x_i)(sum_i x_i)^T)
// (Tonon 2004), and the inertia per unit density about the centroid c is
// I = tr(C_c) 1 - C_c with C_c = C - V (c - o)(c - o)^T.
//
// Mesh: the AABB tree is built top-down, splitting each node at the median triangle centroid
// along the longest axis of the centroids' bounds, ties broken by triangle index so the tree (and
// the order of contacts) is deterministic.
#include "collision/geometry.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <map>
#include <numeric>
#include <stdexcept>
#include <string>
#include <utility>

extern "C" {
#include <libqhull_r/libqhull_r.h>
}

namespace linx::collision {

namespace {

bool finite(const Vec3& v) {
  return v.allFinite();
}

/// A hull thinner than this fraction of its size is refused (the flatness test after Qhull
/// refuses them too, as a volume below 1e-9 of the extent cubed).
constexpr double kThin = 1e-9;

/// Captures Qhull's error text so it can go into the exception rather than onto stderr.
class ErrorStream {
 public:
  ErrorStream() : file_(open_memstream(&buffer_, &size_)) {}
  ~ErrorStream() {
    if (file_ != nullptr) std::fclose(file_);
    std::free(buffer_);
  }
  ErrorStream(const ErrorStream&) = delete;
  ErrorStream& operator=(const ErrorStream&) = delete;
  FILE* file() const { return file_; }
  /// The first line of what Qhull wrote (its error code and message).
  std::string firstLine() {
    if (file_ == nullptr) return {};
    std::fflush(file_);
    std::string text = buffer_ != nullptr ? std::string(buffer_, size_) : std::string();
    const auto end = text.find('\n');
    return end == std::string::npos ? text : text.substr(0, end);
  }

 private:
  char* buffer_ = nullptr;
  std::size_t size_ = 0;
  FILE* file_ = nullptr;
};

/// Owns a Qhull context and frees its memory however the computation ends.
struct QhullRun {
  qhT context;
  QhullRun(FILE* err) { qh_zero(&context, err); }
  ~QhullRun() {
    qh_freeqhull(&context, !qh_ALL);
    int curlong = 0, totlong = 0;
    qh_memfreeshort(&context, &curlong, &totlong);
  }
  QhullRun(const QhullRun&) = delete;
  QhullRun& operator=(const QhullRun&) = delete;
};

/// Orders a face's vertices counter-clockwise about its outward normal n: the angle of each
/// vertex about the face centre, in the basis (u, n x u) of the face plane.
void orderCounterClockwise(std::vector<int>& face, const std::vector<Vec3>& vertices,
                           const Vec3& n) {
  Vec3 centre = Vec3::Zero();
  for (int v : face) centre += vertices[v];
  centre /= static_cast<double>(face.size());
  const Vec3 u = (vertices[face[0]] - centre - n * n.dot(vertices[face[0]] - centre)).normalized();
  const Vec3 w = n.cross(u);
  std::vector<std::pair<double, int>> keyed;
  for (int v : face) {
    const Vec3 d = vertices[v] - centre;
    keyed.emplace_back(std::atan2(d.dot(w), d.dot(u)), v);
  }
  std::sort(keyed.begin(), keyed.end());
  for (std::size_t i = 0; i < face.size(); ++i) face[i] = keyed[i].second;
}

/// "a spread of 18 orders of magnitude (at most 9)": how much larger `big` is than `small`.
std::string spread(double big, double small) {
  return fmt::format("a spread of {:.0f} orders of magnitude (at most {:.0f})",
                     std::floor(std::log10(big / small)), -std::log10(kThin));
}

/// Refuses points (not all the same) that span no volume, in plain words, before Qhull sees
/// them (its messages are its own): all on one line or in one plane (exactly, as such; or too close
/// to it for the hull to be computed reliably: within kThin of the points' extent, as with
/// edges of 1e-9 and 1e9 m). The extent is the distance between a point a farthest from the
/// first and the point b farthest from a; the line is ab; the plane is through ab and the
/// point c farthest from that line.
void checkSpansAVolume(std::span<const Vec3> points) {
  const auto farthest = [&](auto&& distance) {
    std::size_t best = 0;
    double most = -1.0;
    for (std::size_t i = 0; i < points.size(); ++i)
      if (const double d = distance(points[i]); d > most) best = i, most = d;
    return std::pair(best, most);
  };
  const std::size_t n = points.size();
  const Vec3 a = points[farthest([&](const Vec3& p) { return (p - points[0]).norm(); }).first];
  const auto [ib, length] = farthest([&](const Vec3& p) { return (p - a).norm(); });
  const Vec3 u = (points[ib] - a) / length;
  const auto [ic, width] = farthest([&](const Vec3& p) { return (p - a).cross(u).norm(); });
  if (width == 0.0)
    throw std::invalid_argument(fmt::format("convex: all {} points lie on one line", n));
  if (width < kThin * length)
    throw std::invalid_argument(
        fmt::format("convex: the hull is {:.3g} m long but only {:.3g} m wide, {}", length, width,
                    spread(length, width)));
  const Vec3 normal = u.cross(points[ic] - a).normalized();
  const double thickness =
      farthest([&](const Vec3& p) { return std::abs(normal.dot(p - a)); }).second;
  if (thickness == 0.0)
    throw std::invalid_argument(fmt::format("convex: all {} points lie in one plane", n));
  if (thickness < kThin * length)
    throw std::invalid_argument(
        fmt::format("convex: the hull is {:.3g} m across but only {:.3g} m thick, {}", length,
                    thickness, spread(length, thickness)));
}

Aabb triangleBox(const Vec3& a, const Vec3& b, const Vec3& c) {
  return Aabb{a.cwiseMin(b).cwiseMin(c), a.cwiseMax(b).cwiseMax(c)};
}

}  // namespace

std::shared_ptr<const Geometry> Geometry::convexHull(std::span<const Vec3> points) {
  if (points.size() < 4)
    throw std::invalid_argument(
        fmt::format("convex: needs at least 4 non-coplanar points, got {}", points.size()));
  std::vector<double> coords;
  coords.reserve(3 * points.size());
  Vec3 lo = Vec3::Constant(kInfinity), hi = Vec3::Constant(-kInfinity);
  for (std::size_t i = 0; i < points.size(); ++i) {
    if (!finite(points[i]))
      throw std::invalid_argument(fmt::format("convex: point {} is not finite", i));
    if (points[i].cwiseAbs().maxCoeff() > kMaxCoordinate)
      throw std::invalid_argument(fmt::format(
          "convex: point {} has a coordinate of {:g} m, too large (at most {:g} m: the hull's "
          "volume and inertia would overflow)",
          i, points[i].cwiseAbs().maxCoeff(), kMaxCoordinate));
    coords.insert(coords.end(), {points[i].x(), points[i].y(), points[i].z()});
    lo = lo.cwiseMin(points[i]);
    hi = hi.cwiseMax(points[i]);
  }
  // The size, without squares (which underflow for points 1e-200 apart).
  const double size = (hi - lo).maxCoeff();
  if (size == 0.0)
    throw std::invalid_argument(fmt::format("convex: all {} points are the same", points.size()));
  if (size < kMinSize)
    throw std::invalid_argument(
        fmt::format("convex: the points span only {:g} m, too small (at least {:g} m: the hull's "
                    "volume and inertia would underflow)",
                    size, kMinSize));
  checkSpansAVolume(points);

  std::shared_ptr<Geometry> g(new Geometry());
  g->kind_ = Kind::Convex;
  {
    ErrorStream err;
    QhullRun run(err.file());
    qhT* qh = &run.context;
    char flags[] = "qhull C-0 A-0.99999";
    const int code = qh_new_qhull(qh, 3, static_cast<int>(points.size()), coords.data(), False,
                                  flags, nullptr, err.file());
    // Not Qhull's text (it speaks of its own internals): the cases it refuses are checked above,
    // so this is one they missed.
    if (code != 0)
      throw std::invalid_argument(fmt::format(
          "convex: cannot compute the hull of the {} points (too close to flat for its precision)",
          points.size()));

    // Vertices in increasing input order, so the result does not depend on Qhull's lists.
    std::vector<int> input_ids;
    vertexT* vertex = nullptr;
    FORALLvertices input_ids.push_back(qh_pointid(qh, vertex->point));
    std::sort(input_ids.begin(), input_ids.end());
    std::map<int, int> index_of;
    for (int id : input_ids) {
      index_of[id] = static_cast<int>(g->vertices_.size());
      g->vertices_.push_back(points[id]);
    }

    facetT* facet = nullptr;
    vertexT** vertexp = nullptr;
    FORALLfacets {
      HullFace face;
      face.normal = Vec3(facet->normal[0], facet->normal[1], facet->normal[2]).normalized();
      FOREACHvertex_(facet->vertices)
          face.vertices.push_back(index_of.at(qh_pointid(qh, vertex->point)));
      if (face.vertices.size() < 3) continue;
      // Qhull's plane is n . x + offset = 0 with n outward; the offset of a merged facet is a
      // best fit, so take the plane through its outermost vertex (the hull lies below it).
      face.offset = -kInfinity;
      for (int v : face.vertices)
        face.offset = std::max(face.offset, face.normal.dot(g->vertices_[v]));
      orderCounterClockwise(face.vertices, g->vertices_, face.normal);
      g->faces_.push_back(std::move(face));
    }
  }
  // Faces in a canonical order (by their lowest vertex, then normal), so ids do not depend on
  // the order of Qhull's facet list.
  std::sort(g->faces_.begin(), g->faces_.end(), [](const HullFace& x, const HullFace& y) {
    const int mx = *std::min_element(x.vertices.begin(), x.vertices.end());
    const int my = *std::min_element(y.vertices.begin(), y.vertices.end());
    if (mx != my) return mx < my;
    return std::lexicographical_compare(x.normal.data(), x.normal.data() + 3, y.normal.data(),
                                        y.normal.data() + 3);
  });

  // Edges: each polygon side, with the two faces that share it.
  std::map<std::pair<int, int>, int> edge_of;
  for (int f = 0; f < static_cast<int>(g->faces_.size()); ++f) {
    const std::vector<int>& fv = g->faces_[f].vertices;
    for (std::size_t k = 0; k < fv.size(); ++k) {
      const int i = fv[k], j = fv[(k + 1) % fv.size()];
      const std::pair<int, int> key(std::min(i, j), std::max(i, j));
      auto [it, inserted] = edge_of.emplace(key, static_cast<int>(g->edges_.size()));
      if (inserted)
        g->edges_.push_back(HullEdge{key.first, key.second, f, f});
      else
        g->edges_[it->second].face1 = f;
    }
  }

  // Volume, centroid and unit-density inertia from tetrahedra (o, v0, vi, vi+1).
  Vec3 o = Vec3::Zero();
  for (const Vec3& v : g->vertices_) o += v;
  o /= static_cast<double>(g->vertices_.size());
  double volume = 0.0;
  Vec3 first_moment = Vec3::Zero();   // integral of (x - o) dV
  Mat3 second_moment = Mat3::Zero();  // integral of (x - o)(x - o)^T dV
  for (const HullFace& face : g->faces_) {
    const Vec3 a = g->vertices_[face.vertices[0]] - o;
    for (std::size_t k = 1; k + 1 < face.vertices.size(); ++k) {
      const Vec3 b = g->vertices_[face.vertices[k]] - o;
      const Vec3 c = g->vertices_[face.vertices[k + 1]] - o;
      const double v = a.dot(b.cross(c)) / 6.0;
      const Vec3 sum = a + b + c;  // the fourth vertex is o itself: zero
      volume += v;
      first_moment += v * sum / 4.0;
      second_moment +=
          v / 20.0 *
          (a * a.transpose() + b * b.transpose() + c * c.transpose() + sum * sum.transpose());
    }
  }
  const double extent = (hi - lo).norm();
  if (!(volume > 1e-9 * extent * extent * extent))
    throw std::invalid_argument(fmt::format(
        "convex: the hull of the {} points is flat (volume {:g} m^3)", points.size(), volume));
  const Vec3 c = first_moment / volume;  // centroid relative to o
  const Mat3 central = second_moment - volume * c * c.transpose();
  g->volume_ = volume;
  g->centroid_ = o + c;
  g->unit_inertia_ = central.trace() * Mat3::Identity() - central;
  // The second moments go as the fifth power of the size (kMinSize keeps them representable).
  if (!(g->unit_inertia_.diagonal().minCoeff() >= std::numeric_limits<double>::min()) ||
      !g->unit_inertia_.allFinite())
    throw std::invalid_argument(fmt::format(
        "convex: the hull is too small ({:g} m across): its inertia underflows", extent));
  return g;
}

std::shared_ptr<const Geometry> Geometry::mesh(std::span<const Vec3> points,
                                               std::span<const std::array<int, 3>> triangles) {
  if (triangles.empty()) throw std::invalid_argument("mesh: has no triangles");
  for (std::size_t i = 0; i < points.size(); ++i) {
    if (!finite(points[i]))
      throw std::invalid_argument(fmt::format("mesh: vertex {} is not finite", i));
    if (points[i].cwiseAbs().maxCoeff() > kMaxCoordinate)
      throw std::invalid_argument(fmt::format(
          "mesh: vertex {} has a coordinate of {:g} m, too large (at most {:g} m: triangle areas "
          "would overflow)",
          i, points[i].cwiseAbs().maxCoeff(), kMaxCoordinate));
  }
  std::shared_ptr<Geometry> g(new Geometry());
  g->kind_ = Kind::Mesh;
  g->vertices_.assign(points.begin(), points.end());
  g->triangles_.assign(triangles.begin(), triangles.end());
  const int nv = static_cast<int>(points.size());
  for (std::size_t t = 0; t < triangles.size(); ++t) {
    for (int v : triangles[t])
      if (v < 0 || v >= nv)
        throw std::invalid_argument(
            fmt::format("mesh: triangle {} has vertex index {} out of range [0, {})", t, v, nv));
    for (int k = 0; k < 3; ++k)
      if (triangles[t][k] == triangles[t][(k + 1) % 3])
        throw std::invalid_argument(
            fmt::format("mesh: triangle {} repeats vertex {}", t, triangles[t][k]));
    const Vec3& a = points[triangles[t][0]];
    const Vec3 e1 = points[triangles[t][1]] - a, e2 = points[triangles[t][2]] - a;
    const Vec3 n = e1.cross(e2);
    // Zero area, up to roundoff relative to the edge lengths.
    if (!(n.norm() > 1e-12 * std::max(e1.squaredNorm(), e2.squaredNorm())))
      throw std::invalid_argument(fmt::format("mesh: triangle {} is degenerate (zero area)", t));
    g->normals_.push_back(n.normalized());
  }

  // Active edges. Two triangles t, u sharing an edge (p, q): the edge is convex when u's third
  // vertex o lies below t's plane, (o - p) . n_t < 0, and it is a real edge when, in addition,
  // the normals differ by more than 5 degrees. Boundary and non-manifold edges stay active.
  const double kFlatCos = std::cos(5.0 * 3.14159265358979323846 / 180.0);
  g->edge_active_.assign(triangles.size(), {true, true, true});
  std::map<std::pair<int, int>, std::vector<std::pair<int, int>>> sides;  // edge -> (t, k)
  for (int t = 0; t < static_cast<int>(triangles.size()); ++t)
    for (int k = 0; k < 3; ++k) {
      const int i = triangles[t][k], j = triangles[t][(k + 1) % 3];
      sides[{std::min(i, j), std::max(i, j)}].emplace_back(t, k);
    }
  for (const auto& [edge, users] : sides) {
    if (users.size() != 2) continue;
    const auto [t, k] = users[0];
    const auto [u, l] = users[1];
    const Vec3& p = points[edge.first];
    const int o = triangles[u][(l + 2) % 3];
    const double height = (points[o] - p).dot(g->normals_[t]);
    const double scale = (points[o] - p).norm();
    const bool convex = height < -1e-9 * scale;
    const bool bent = g->normals_[t].dot(g->normals_[u]) < kFlatCos;
    g->edge_active_[t][k] = g->edge_active_[u][l] = convex && bent;
  }
  g->vertex_active_.assign(points.size(), 0);
  for (int t = 0; t < static_cast<int>(triangles.size()); ++t)
    for (int k = 0; k < 3; ++k)
      if (g->edge_active_[t][k]) {
        g->vertex_active_[triangles[t][k]] = 1;
        g->vertex_active_[triangles[t][(k + 1) % 3]] = 1;
      }
  g->buildBvh();
  return g;
}

void Geometry::buildBvh() {
  const int n = static_cast<int>(triangles_.size());
  std::vector<Aabb> boxes(n);
  std::vector<Vec3> centres(n);
  for (int t = 0; t < n; ++t) {
    const auto& tri = triangles_[t];
    boxes[t] = triangleBox(vertices_[tri[0]], vertices_[tri[1]], vertices_[tri[2]]);
    centres[t] = boxes[t].centre();
  }
  tree_triangles_.resize(n);
  std::iota(tree_triangles_.begin(), tree_triangles_.end(), 0);
  nodes_.clear();
  nodes_.reserve(2 * n / kLeafSize + 2);

  struct Task {
    int node, first, count;
  };
  nodes_.push_back(BvhNode{});
  std::vector<Task> stack{{0, 0, n}};
  while (!stack.empty()) {
    const Task task = stack.back();
    stack.pop_back();
    Aabb box = boxes[tree_triangles_[task.first]];
    Aabb centre_box{centres[tree_triangles_[task.first]], centres[tree_triangles_[task.first]]};
    for (int i = task.first; i < task.first + task.count; ++i) {
      box.merge(boxes[tree_triangles_[i]]);
      centre_box.merge(Aabb{centres[tree_triangles_[i]], centres[tree_triangles_[i]]});
    }
    nodes_[task.node].box = box;
    if (task.count <= kLeafSize) {
      nodes_[task.node].first = task.first;
      nodes_[task.node].count = task.count;
      continue;
    }
    int axis = 0;
    centre_box.extent().maxCoeff(&axis);
    const int half = task.count / 2;
    auto begin = tree_triangles_.begin() + task.first;
    std::nth_element(begin, begin + half, begin + task.count, [&](int x, int y) {
      if (centres[x][axis] != centres[y][axis]) return centres[x][axis] < centres[y][axis];
      return x < y;
    });
    const int left = static_cast<int>(nodes_.size());
    nodes_.push_back(BvhNode{});
    nodes_.push_back(BvhNode{});
    nodes_[task.node].left = left;
    nodes_[task.node].right = left + 1;
    stack.push_back({left, task.first, half});
    stack.push_back({left + 1, task.first + half, task.count - half});
  }
}

void Geometry::queryTriangles(const Aabb& box, std::vector<int>& out) const {
  if (nodes_.empty()) return;
  const std::size_t first = out.size();
  int stack[64];
  int top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const BvhNode& node = nodes_[stack[--top]];
    if (!node.box.overlaps(box)) continue;
    if (node.left < 0) {
      for (int i = node.first; i < node.first + node.count; ++i) {
        const int t = tree_triangles_[i];
        const auto& tri = triangles_[t];
        if (triangleBox(vertices_[tri[0]], vertices_[tri[1]], vertices_[tri[2]]).overlaps(box))
          out.push_back(t);
      }
    } else if (top + 2 <= 64) {
      stack[top++] = node.right;
      stack[top++] = node.left;
    }
  }
  std::sort(out.begin() + static_cast<std::ptrdiff_t>(first), out.end());
}

int Geometry::supportVertex(const Vec3& dir) const {
  int best = 0;
  double best_dot = -kInfinity;
  for (int i = 0; i < static_cast<int>(vertices_.size()); ++i) {
    const double d = vertices_[i].dot(dir);
    if (d > best_dot) {
      best_dot = d;
      best = i;
    }
  }
  return best;
}

int Geometry::supportFace(const Vec3& dir) const {
  int best = 0;
  double best_dot = -kInfinity;
  for (int f = 0; f < static_cast<int>(faces_.size()); ++f) {
    const double d = faces_[f].normal.dot(dir);
    if (d > best_dot) {
      best_dot = d;
      best = f;
    }
  }
  return best;
}

std::shared_ptr<const Geometry> prepareGeometry(const ShapeDef& shape) {
  switch (shape.type) {
    case ShapeType::Convex:
      return Geometry::convexHull(shape.points);
    case ShapeType::Mesh:
      return Geometry::mesh(shape.points, shape.triangles);
    default:
      return nullptr;
  }
}

}  // namespace linx::collision
