#include "viz/tessellate.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <map>
#include <numbers>
#include <utility>

namespace linx::viz {

namespace {

int addPoint(Surface& s, const Vec3& p, const Vec3& n) {
  s.points.push_back(p);
  s.normals.push_back(n);
  return static_cast<int>(s.points.size()) - 1;
}

// A flat quad of corners a, b, c, d counter-clockwise around `n`.
void addQuad(Surface& s, const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d,
             const Vec3& n) {
  const int i = addPoint(s, a, n);
  addPoint(s, b, n);
  addPoint(s, c, n);
  addPoint(s, d, n);
  s.triangles.push_back({i, i + 1, i + 2});
  s.triangles.push_back({i, i + 2, i + 3});
}

Surface sphere(double r, int subdivisions) {
  // Icosahedron: the 12 points (0, +-1, +-t) and their cyclic permutations, t the golden ratio.
  const double t = (1 + std::sqrt(5.0)) / 2;
  std::vector<Vec3> unit = {{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0},
                            {0, -1, t}, {0, 1, t}, {0, -1, -t}, {0, 1, -t},
                            {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
  for (Vec3& p : unit) p.normalize();
  std::vector<std::array<int, 3>> faces = {
      {0, 11, 5},  {0, 5, 1},  {0, 1, 7},  {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
      {11, 10, 2}, {10, 7, 6}, {7, 1, 8},  {3, 9, 4},  {3, 4, 2},   {3, 2, 6}, {3, 6, 8},
      {3, 8, 9},   {4, 9, 5},  {2, 4, 11}, {6, 2, 10}, {8, 6, 7},   {9, 8, 1}};
  for (int level = 0; level < subdivisions; ++level) {
    std::map<std::pair<int, int>, int> midpoints;
    const auto midpoint = [&](int a, int b) {
      const std::pair<int, int> key = std::minmax(a, b);
      const auto it = midpoints.find(key);
      if (it != midpoints.end()) return it->second;
      unit.push_back(
          (unit[static_cast<std::size_t>(a)] + unit[static_cast<std::size_t>(b)]).normalized());
      const int m = static_cast<int>(unit.size()) - 1;
      midpoints.emplace(key, m);
      return m;
    };
    std::vector<std::array<int, 3>> finer;
    finer.reserve(faces.size() * 4);
    for (const auto& f : faces) {
      const int ab = midpoint(f[0], f[1]), bc = midpoint(f[1], f[2]), ca = midpoint(f[2], f[0]);
      finer.push_back({f[0], ab, ca});
      finer.push_back({f[1], bc, ab});
      finer.push_back({f[2], ca, bc});
      finer.push_back({ab, bc, ca});
    }
    faces = std::move(finer);
  }
  Surface s;
  s.points.reserve(unit.size());
  for (const Vec3& u : unit) addPoint(s, r * u, u);
  s.triangles = std::move(faces);
  return s;
}

Surface box(const Vec3& size) {
  Surface s;
  const Vec3 h = size / 2;
  for (int a = 0; a < 3; ++a) {
    for (const double sign : {1.0, -1.0}) {
      // e_b x e_c = e_a: (u, v) = (e_b, e_c) on the + face, (e_c, e_b) on the - face.
      const int b = (a + 1) % 3, c = (a + 2) % 3;
      Vec3 n = Vec3::Zero(), u = Vec3::Zero(), v = Vec3::Zero();
      n[a] = sign;
      u[sign > 0 ? b : c] = h[sign > 0 ? b : c];
      v[sign > 0 ? c : b] = h[sign > 0 ? c : b];
      const Vec3 centre = n * h[a];
      addQuad(s, centre - u - v, centre + u - v, centre + u + v, centre - u + v, n);
    }
  }
  return s;
}

// Rings of points around the z axis joined into bands, top to bottom; `rings` are (z, radius,
// normal z, normal radial) of each ring. Optional poles close the ends.
struct Ring {
  double z, radius, nz, nr;
};

void addRevolved(Surface& s, const std::vector<Ring>& rings, int n, const Ring* top,
                 const Ring* bottom) {
  std::vector<int> first;
  for (const Ring& ring : rings) {
    first.push_back(static_cast<int>(s.points.size()));
    for (int j = 0; j < n; ++j) {
      const double phi = 2 * std::numbers::pi * j / n;
      const double c = std::cos(phi), si = std::sin(phi);
      addPoint(s, Vec3(ring.radius * c, ring.radius * si, ring.z),
               Vec3(ring.nr * c, ring.nr * si, ring.nz));
    }
  }
  for (std::size_t i = 0; i + 1 < rings.size(); ++i) {
    for (int j = 0; j < n; ++j) {
      const int k = (j + 1) % n;
      const int a = first[i] + j, b = first[i] + k, c = first[i + 1] + j, d = first[i + 1] + k;
      s.triangles.push_back({a, c, d});
      s.triangles.push_back({a, d, b});
    }
  }
  if (top) {
    const int p = addPoint(s, Vec3(0, 0, top->z), Vec3(0, 0, top->nz));
    for (int j = 0; j < n; ++j)
      s.triangles.push_back({p, first.front() + j, first.front() + (j + 1) % n});
  }
  if (bottom) {
    const int p = addPoint(s, Vec3(0, 0, bottom->z), Vec3(0, 0, bottom->nz));
    for (int j = 0; j < n; ++j)
      s.triangles.push_back({first.back() + j, p, first.back() + (j + 1) % n});
  }
}

Surface capsule(double r, double length, int segments) {
  const int n = std::max(3, segments), q = std::max(2, segments / 4);
  std::vector<Ring> rings;
  for (int k = 1; k <= q; ++k) {  // top cap, from the pole down to the equator
    const double theta = std::numbers::pi / 2 * k / q;
    rings.push_back(
        {length / 2 + r * std::cos(theta), r * std::sin(theta), std::cos(theta), std::sin(theta)});
  }
  for (int k = q; k >= 1; --k) {  // bottom cap, from the equator down to the pole
    const double theta = std::numbers::pi / 2 * k / q;
    rings.push_back({-length / 2 - r * std::cos(theta), r * std::sin(theta), -std::cos(theta),
                     std::sin(theta)});
  }
  const Ring top{length / 2 + r, 0, 1, 0}, bottom{-length / 2 - r, 0, -1, 0};
  Surface s;
  addRevolved(s, rings, n, &top, &bottom);
  return s;
}

Surface cylinder(double r, double length, int segments) {
  const int n = std::max(3, segments);
  Surface s;
  const double h = length / 2;
  addRevolved(s, {{h, r, 0, 1}, {-h, r, 0, 1}}, n, nullptr, nullptr);  // side
  const Ring top{h, 0, 1, 0}, bottom{-h, 0, -1, 0};
  addRevolved(s, {{h, r, 1, 0}}, n, &top, nullptr);       // top cap
  addRevolved(s, {{-h, r, -1, 0}}, n, nullptr, &bottom);  // bottom cap
  return s;
}

// A point per triangle corner with the triangle's normal. Convex hulls are turned outward.
Surface faceted(const ShapeDef& shape, bool orient_outward) {
  Surface s;
  Vec3 centre = Vec3::Zero();
  for (const Vec3& p : shape.points) centre += p;
  if (!shape.points.empty()) centre /= static_cast<double>(shape.points.size());
  const auto count = static_cast<int>(shape.points.size());
  for (const auto& t : shape.triangles) {
    if (std::any_of(t.begin(), t.end(), [&](int i) { return i < 0 || i >= count; })) continue;
    Vec3 a = shape.points[static_cast<std::size_t>(t[0])],
         b = shape.points[static_cast<std::size_t>(t[1])],
         c = shape.points[static_cast<std::size_t>(t[2])];
    Vec3 n = (b - a).cross(c - a);
    if (orient_outward && n.dot((a + b + c) / 3 - centre) < 0) {
      std::swap(b, c);
      n = -n;
    }
    n = n.norm() > 0 ? Vec3(n.normalized()) : Vec3(Vec3::UnitZ());
    const int i = addPoint(s, a, n);
    addPoint(s, b, n);
    addPoint(s, c, n);
    s.triangles.push_back({i, i + 1, i + 2});
  }
  return s;
}

Surface plane(const ShapeDef& shape, const TessellationOptions& options) {
  const Vec3 n = shape.normal.norm() > 0 ? Vec3(shape.normal.normalized()) : Vec3(Vec3::UnitZ());
  const Vec3 origin = options.plane_center - (n.dot(options.plane_center) - shape.offset) * n;
  // u x v = n.
  Eigen::Index least = 0;
  n.cwiseAbs().minCoeff(&least);
  const Vec3 u = n.cross(Vec3::Unit(least)).normalized() * options.plane_half_size;
  const Vec3 v = n.cross(u);
  Surface s;
  addQuad(s, origin - u - v, origin + u - v, origin + u + v, origin - u + v, n);
  return s;
}

}  // namespace

Surface tessellate(const ShapeDef& shape, const TessellationOptions& options) {
  switch (shape.type) {
    case ShapeType::Sphere:
      return sphere(shape.radius, std::clamp(options.sphere_subdivisions, 0, 8));
    case ShapeType::Box:
      return box(shape.size);
    case ShapeType::Capsule:
      return capsule(shape.radius, shape.length, options.segments);
    case ShapeType::Cylinder:
      return cylinder(shape.radius, shape.length, options.segments);
    case ShapeType::Plane:
      return plane(shape, options);
    case ShapeType::Convex:
      return faceted(shape, true);
    case ShapeType::Mesh:
      return faceted(shape, false);
    case ShapeType::Ellipsoid: {
      // A unit icosphere stretched by the semi-axes; the normals by their inverses.
      Surface s = sphere(1.0, std::clamp(options.sphere_subdivisions, 0, 8));
      const Vec3 r = shape.radii.cwiseAbs();
      for (std::size_t i = 0; i < s.points.size(); ++i) {
        s.normals[i] = s.points[i].cwiseQuotient(r).normalized();
        s.points[i] = s.points[i].cwiseProduct(r);
      }
      return s;
    }
  }
  return {};
}

}  // namespace linx::viz
