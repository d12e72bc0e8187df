// General convex collision against closed forms: GJK distances of separated shapes, EPA depths
// of overlapping ones (boxes also against an independent separating-axis computation), contact
// manifolds of resting shapes (counts, depths, the normal's sign), triangle meshes (one point for
// a resting sphere, four for a box, the face normal on an internal edge), mesh files (OBJ, binary
// and ASCII STL) and the mass properties of convex hulls.
#include <linx/mass_properties.hpp>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <numbers>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include "collision/convex_pairs.hpp"
#include "collision/geometry.hpp"
#include "collision/gjk_epa.hpp"
#include "io/mesh_file.hpp"

namespace linx::collision {
namespace {

constexpr double kPi = std::numbers::pi;

// Shapes by assignment (designated initializers warn about the members left out).
ShapeDef shapeOf(ShapeType type) {
  ShapeDef s;
  s.type = type;
  return s;
}
ShapeDef sphere(double r) {
  ShapeDef s = shapeOf(ShapeType::Sphere);
  s.radius = r;
  return s;
}
ShapeDef box(const Vec3& size) {
  ShapeDef s = shapeOf(ShapeType::Box);
  s.size = size;
  return s;
}
ShapeDef capsule(double r, double length) {
  ShapeDef s = shapeOf(ShapeType::Capsule);
  s.radius = r;
  s.length = length;
  return s;
}
ShapeDef cylinder(double r, double length) {
  ShapeDef s = shapeOf(ShapeType::Cylinder);
  s.radius = r;
  s.length = length;
  return s;
}
ShapeDef convex(std::vector<Vec3> points) {
  ShapeDef s = shapeOf(ShapeType::Convex);
  s.points = std::move(points);
  return s;
}
ShapeDef plane(const Vec3& normal, double offset) {
  ShapeDef s = shapeOf(ShapeType::Plane);
  s.normal = normal;
  s.offset = offset;
  return s;
}
std::vector<Vec3> boxCorners(const Vec3& half, const Vec3& offset = Vec3::Zero()) {
  std::vector<Vec3> p;
  for (int c = 0; c < 8; ++c)
    p.push_back(offset + Vec3((c & 1) ? half.x() : -half.x(), (c & 2) ? half.y() : -half.y(),
                              (c & 4) ? half.z() : -half.z()));
  return p;
}

/// A shape placed in the world, owning its definition and prepared geometry.
struct Placed {
  ShapeDef def;
  std::shared_ptr<const Geometry> geometry;
  Pose pose;
  Placed(ShapeDef d, const Vec3& position, const Quat& orientation = Quat::Identity())
      : def(std::move(d)), geometry(prepareGeometry(def)) {
    pose.position = position;
    pose.orientation = orientation;
  }
  ShapeInstance instance() const { return ShapeInstance{&def, geometry.get(), pose}; }
  ConvexSupport support() const { return makeSupport(instance()); }
};

std::vector<ContactPoint> collideConvexPair(const Placed& a, const Placed& b, double margin) {
  std::vector<ContactPoint> out;
  const int n = collideConvex(a.instance(), b.instance(), margin, out);
  EXPECT_EQ(n, static_cast<int>(out.size()));
  return out;
}

std::vector<ContactPoint> collideWithMesh(const Placed& a, const Placed& mesh, double margin) {
  std::vector<ContactPoint> out;
  const int n = collideMesh(a.instance(), mesh.instance(), margin, out);
  EXPECT_EQ(n, static_cast<int>(out.size()));
  return out;
}

Quat axisAngle(double angle, const Vec3& axis) {
  return Quat(Eigen::AngleAxisd(angle, axis.normalized()));
}

// --- GJK: distances of separated shapes ---

TEST(Gjk, SphereSphereDistanceIsCentreDistanceMinusRadii) {
  const Placed a(sphere(0.5), Vec3(0, 0, 0)), b(sphere(1.0), Vec3(1, 2, 2));  // 3 apart
  const ContactQuery q = queryContact(a.support(), b.support(), 10.0);
  EXPECT_NEAR(q.separation, 1.5, 1e-12);
  EXPECT_TRUE(q.normal.isApprox(Vec3(1, 2, 2) / 3.0, 1e-12));
  EXPECT_TRUE(q.point_a.isApprox(Vec3(1, 2, 2) / 6.0, 1e-12));
  // The cores: the centres.
  const GjkResult g = gjkDistance(a.support(), b.support(), true);
  EXPECT_FALSE(g.overlap);
  EXPECT_NEAR(g.distance, 3.0, 1e-12);
  // Full shapes.
  EXPECT_NEAR(gjkDistance(a.support(), b.support(), false).distance, 1.5, 1e-9);
}

TEST(Gjk, BoxBoxDistanceAlongAnAxis) {
  // Unit cubes 2.5 apart along x: gap 1.5, whatever their rotation about x.
  for (double angle : {0.0, 0.3, 1.0}) {
    const Placed a(box(Vec3::Ones()), Vec3::Zero(), axisAngle(angle, Vec3::UnitX()));
    const Placed b(box(Vec3::Ones()), Vec3(2.5, 0.1, -0.2), axisAngle(-angle, Vec3::UnitX()));
    const GjkResult g = gjkDistance(a.support(), b.support(), false);
    EXPECT_FALSE(g.overlap);
    EXPECT_NEAR(g.distance, 1.5, 1e-12) << angle;
    const ContactQuery q = queryContact(a.support(), b.support(), 10.0);
    EXPECT_NEAR(q.separation, 1.5, 1e-12);
    EXPECT_TRUE(q.normal.isApprox(Vec3::UnitX(), 1e-12));
  }
  // A cube turned 45 degrees about z presents an edge: its reach along x is sqrt(2) / 2.
  const Placed a(box(Vec3::Ones()), Vec3::Zero(), axisAngle(kPi / 4, Vec3::UnitZ()));
  const Placed b(box(Vec3::Ones()), Vec3(3, 0, 0));
  EXPECT_NEAR(gjkDistance(a.support(), b.support(), false).distance, 2.5 - std::sqrt(0.5), 1e-12);
}

TEST(Gjk, CapsuleCapsuleDistanceIsSegmentDistanceMinusRadii) {
  // Parallel capsules 2 apart.
  const Placed a(capsule(0.3, 2.0), Vec3::Zero()), b(capsule(0.3, 1.0), Vec3(2, 0, 0.5));
  EXPECT_NEAR(queryContact(a.support(), b.support(), 10.0).separation, 1.4, 1e-12);
  // Skew: a along z, c along x through (0, 1.5, 0.5): the segments are 1.5 apart along y.
  const Placed c(capsule(0.25, 4.0), Vec3(0, 1.5, 0.5), axisAngle(kPi / 2, Vec3::UnitY()));
  const ContactQuery q = queryContact(a.support(), c.support(), 10.0);
  EXPECT_NEAR(q.separation, 1.5 - 0.55, 1e-12);
  EXPECT_TRUE(q.normal.isApprox(Vec3::UnitY(), 1e-12));
  // Beyond the distance of interest: no hit.
  EXPECT_FALSE(queryContact(a.support(), c.support(), 0.5).hit);
}

TEST(Gjk, CylinderAndHullDistances) {
  // A cylinder's rim against a box face, and a hull (a cube's corners) against a sphere.
  const Placed cyl(cylinder(0.5, 1.0), Vec3::Zero()), b(box(Vec3::Ones()), Vec3(2, 0, 0));
  EXPECT_NEAR(queryContact(cyl.support(), b.support(), 10.0).separation, 1.0, 1e-9);
  const Placed hull(convex(boxCorners(Vec3(0.5, 0.5, 0.5))), Vec3(0, 0, 1));
  const Placed s(sphere(0.25), Vec3(0, 0, 3));
  EXPECT_NEAR(queryContact(hull.support(), s.support(), 10.0).separation, 1.25, 1e-12);
  // A hull's corner towards the sphere: distance from (0.5, 0.5, 1.5) to (2, 2, 3), minus r.
  const Placed s2(sphere(0.25), Vec3(2, 2, 3));
  EXPECT_NEAR(queryContact(hull.support(), s2.support(), 10.0).separation,
              std::sqrt(3 * 1.5 * 1.5) - 0.25, 1e-12);
}

// --- EPA: penetration ---

TEST(Epa, OverlappingSpheres) {
  const Placed a(sphere(1.0), Vec3::Zero()), b(sphere(1.0), Vec3(1.5, 0, 0));
  // EPA on the full (curved) shapes: a polytope approximation.
  const Penetration p = epaPenetration(a.support(), b.support());
  ASSERT_TRUE(p.valid);
  EXPECT_NEAR(p.depth, 0.5, 2e-3);
  EXPECT_GT(p.normal.dot(Vec3::UnitX()), 0.999);
  // The combined query uses the cores (the centres): exact.
  const ContactQuery q = queryContact(a.support(), b.support(), 0.0);
  EXPECT_NEAR(q.separation, -0.5, 1e-12);
  EXPECT_TRUE(q.normal.isApprox(Vec3::UnitX(), 1e-12));
  // Concentric spheres: no direction is better, but the answer is finite: depth r_a + r_b.
  const Placed c(sphere(0.5), Vec3::Zero());
  const ContactQuery qc = queryContact(a.support(), c.support(), 0.0);
  EXPECT_TRUE(qc.normal.allFinite());
  EXPECT_NEAR(qc.normal.norm(), 1.0, 1e-12);
  EXPECT_NEAR(qc.separation, -1.5, 1e-12);
}

TEST(Epa, OverlappingBoxesMatchTheAxisAlignedOverlap) {
  // a: [-1, 1]^3; b: half 0.5 at (1.3, 0.1, 0.2): overlaps x by 0.2, y by 1.5, z by 1.3.
  const Placed a(box(Vec3(2, 2, 2)), Vec3::Zero()), b(box(Vec3::Ones()), Vec3(1.3, 0.1, 0.2));
  const Penetration p = epaPenetration(a.support(), b.support());
  ASSERT_TRUE(p.valid);
  EXPECT_NEAR(p.depth, 0.2, 1e-9);
  EXPECT_TRUE(p.normal.isApprox(Vec3::UnitX(), 1e-9));
  // Along z, with other sizes.
  const Placed c(box(Vec3(3, 1, 0.5)), Vec3::Zero()), d(box(Vec3(1, 2, 1)), Vec3(0.3, -0.2, -0.6));
  const ContactQuery q = queryContact(c.support(), d.support(), 0.0);
  // z: c spans [-0.25, 0.25], d [-1.1, -0.1]: pushing d down by 0.15 separates them.
  EXPECT_NEAR(q.separation, -0.15, 1e-9);
  EXPECT_TRUE(q.normal.isApprox(-Vec3::UnitZ(), 1e-9));
}

/// Penetration of two boxes by the separating axis theorem (independent of GJK/EPA): the
/// smallest overlap over the 15 axes (3 + 3 face normals, 9 edge cross products).
double satDepth(const Placed& a, const Placed& b) {
  const Mat3 ra = a.pose.orientation.toRotationMatrix(), rb = b.pose.orientation.toRotationMatrix();
  const Vec3 ha = 0.5 * a.def.size, hb = 0.5 * b.def.size;
  const Vec3 d = b.pose.position - a.pose.position;
  std::vector<Vec3> axes;
  for (int i = 0; i < 3; ++i) {
    axes.push_back(ra.col(i));
    axes.push_back(rb.col(i));
    for (int j = 0; j < 3; ++j) {
      const Vec3 c = ra.col(i).cross(rb.col(j));
      if (c.norm() > 1e-9) axes.push_back(c.normalized());
    }
  }
  double depth = kInfinity;
  for (const Vec3& n : axes) {
    const double reach =
        (ra.transpose() * n).cwiseAbs().dot(ha) + (rb.transpose() * n).cwiseAbs().dot(hb);
    depth = std::min(depth, reach - std::abs(n.dot(d)));
  }
  return depth;
}

TEST(Epa, RandomBoxPairsMatchTheSeparatingAxisDepth) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  int overlapping = 0;
  for (int k = 0; k < 300; ++k) {
    const Placed a(box(Vec3(1.0 + 0.5 * u(rng), 1.0 + 0.5 * u(rng), 1.0 + 0.5 * u(rng))),
                   Vec3(0.3 * u(rng), 0.3 * u(rng), 0.3 * u(rng)),
                   Quat(u(rng), u(rng), u(rng), u(rng)).normalized());
    const Placed b(box(Vec3(1.0 + 0.5 * u(rng), 1.0 + 0.5 * u(rng), 1.0 + 0.5 * u(rng))),
                   Vec3(1.2 * u(rng), 1.2 * u(rng), 1.2 * u(rng)),
                   Quat(u(rng), u(rng), u(rng), u(rng)).normalized());
    const double sat = satDepth(a, b);
    const ContactQuery q = queryContact(a.support(), b.support(), 1.0);
    ASSERT_TRUE(q.normal.allFinite());
    ASSERT_TRUE(std::isfinite(q.separation));
    if (sat > 1e-6) {
      ++overlapping;
      EXPECT_NEAR(-q.separation, sat, 1e-7) << k;
      // The normal separates: a's support along it and b's along -n overlap by the depth.
      const double reach =
          (a.support().support(q.normal) - b.support().support(-q.normal)).dot(q.normal);
      EXPECT_NEAR(reach, sat, 1e-7) << k;
    } else if (sat < -1e-6) {
      EXPECT_GT(q.separation, 0.0) << k;
    }
  }
  EXPECT_GT(overlapping, 50);
}

TEST(Epa, SphereInsideAConvexHullOfACube) {
  const Placed hull(convex(boxCorners(Vec3::Ones())), Vec3::Zero());
  const Placed s(sphere(0.5), Vec3(0.8, 0.1, 0.0));
  // To leave the cube [-1, 1]^3 the sphere must move by 1 - (0.8 - 0.5) = 0.7 along +x.
  const ContactQuery q = queryContact(hull.support(), s.support(), 0.0);
  EXPECT_NEAR(q.separation, -0.7, 1e-9);
  EXPECT_TRUE(q.normal.isApprox(Vec3::UnitX(), 1e-9));
  const std::vector<ContactPoint> pts = collideConvexPair(hull, s, 0.01);
  ASSERT_EQ(pts.size(), 1u);
  EXPECT_NEAR(pts[0].depth, 0.7, 1e-9);
}

// --- Manifolds ---

TEST(Manifold, CubeHullRestingOnABoxHasFourPointsAtTheExactDepth) {
  const double depth = 0.01;
  const Placed ground(box(Vec3(4, 4, 1)), Vec3(0, 0, -0.5));  // top face at z = 0
  for (double yaw : {0.0, 0.3}) {
    const Placed hull(convex(boxCorners(Vec3(0.5, 0.5, 0.5))), Vec3(0.2, -0.1, 0.5 - depth),
                      axisAngle(yaw, Vec3::UnitZ()));
    const std::vector<ContactPoint> pts = collideConvexPair(hull, ground, 0.02);
    ASSERT_EQ(pts.size(), 4u) << yaw;
    for (const ContactPoint& p : pts) {
      EXPECT_NEAR(p.depth, depth, 1e-9);
      EXPECT_TRUE(p.normal.isApprox(-Vec3::UnitZ(), 1e-9));  // from the hull to the ground
      EXPECT_NEAR(p.point.z(), -0.5 * depth, 1e-9);          // midway between the surfaces
      // At the hull's bottom corners.
      const Vec3 local = hull.pose.toLocal(p.point);
      EXPECT_NEAR(std::abs(local.x()), 0.5, 1e-9);
      EXPECT_NEAR(std::abs(local.y()), 0.5, 1e-9);
    }
    // Distinct, stable feature ids.
    for (std::size_t i = 0; i < pts.size(); ++i)
      for (std::size_t j = i + 1; j < pts.size(); ++j) EXPECT_NE(pts[i].feature, pts[j].feature);
    const std::vector<ContactPoint> again = collideConvexPair(hull, ground, 0.02);
    for (std::size_t i = 0; i < pts.size(); ++i) EXPECT_EQ(pts[i].feature, again[i].feature);
  }
}

TEST(Manifold, FeatureIdsStayWhileTheSameFeaturesTouch) {
  const Placed ground(box(Vec3(4, 4, 1)), Vec3(0, 0, -0.5));
  const Placed h1(convex(boxCorners(Vec3(0.5, 0.5, 0.5))), Vec3(0, 0, 0.49));
  const Placed h2(convex(boxCorners(Vec3(0.5, 0.5, 0.5))), Vec3(0.01, 0.02, 0.495),
                  axisAngle(0.01, Vec3::UnitZ()));
  std::vector<ContactPoint> p1 = collideConvexPair(h1, ground, 0.02);
  std::vector<ContactPoint> p2 = collideConvexPair(h2, ground, 0.02);
  ASSERT_EQ(p1.size(), 4u);
  ASSERT_EQ(p2.size(), 4u);
  auto ids = [](const std::vector<ContactPoint>& p) {
    std::vector<std::uint32_t> v;
    for (const ContactPoint& c : p) v.push_back(c.feature);
    std::sort(v.begin(), v.end());
    return v;
  };
  EXPECT_EQ(ids(p1), ids(p2));
}

TEST(Manifold, HullOnItsEdgeAndHullStacks) {
  const Placed ground(box(Vec3(4, 4, 1)), Vec3(0, 0, -0.5));
  // A unit cube hull turned 45 degrees about x rests on an edge: its lowest edge at
  // z = 0.6 - sqrt(2)/2, two points at the edge's ends.
  const Placed edge(convex(boxCorners(Vec3(0.5, 0.5, 0.5))), Vec3(0, 0, 0.7),
                    axisAngle(kPi / 4, Vec3::UnitX()));
  const double depth = std::sqrt(0.5) - 0.7;
  const std::vector<ContactPoint> pts = collideConvexPair(edge, ground, 0.02);
  ASSERT_EQ(pts.size(), 2u);
  for (const ContactPoint& p : pts) {
    EXPECT_NEAR(p.depth, depth, 1e-9);
    EXPECT_NEAR(std::abs(p.point.x()), 0.5, 1e-9);
    EXPECT_NEAR(p.point.y(), 0.0, 1e-9);
  }
  // Hull on hull, the upper one smaller and turned: its 4 bottom corners.
  const Placed lower(convex(boxCorners(Vec3(1, 1, 0.5))), Vec3(0, 0, 0.5));
  const Placed upper(convex(boxCorners(Vec3(0.4, 0.3, 0.2))), Vec3(0.1, 0.2, 1.195),
                     axisAngle(0.4, Vec3::UnitZ()));
  const std::vector<ContactPoint> stack = collideConvexPair(upper, lower, 0.02);
  ASSERT_EQ(stack.size(), 4u);
  for (const ContactPoint& p : stack) {
    EXPECT_NEAR(p.depth, 0.005, 1e-9);
    EXPECT_TRUE(p.normal.isApprox(-Vec3::UnitZ(), 1e-9));
  }
}

TEST(Manifold, TiltedCylinderTouchesAtItsLowestRimPoint) {
  // Tilted by 10 degrees about x: the lowest rim point is L/2 sin + r... below the centre by
  // (L/2) cos(t) + r sin(t).
  const Placed ground(box(Vec3(4, 4, 1)), Vec3(0, 0, -0.5));
  const double t = 10.0 * kPi / 180.0, r = 0.5, half = 0.5;
  const double reach = half * std::cos(t) + r * std::sin(t);
  const Placed cyl(cylinder(r, 2 * half), Vec3(0, 0, reach - 0.003), axisAngle(t, Vec3::UnitX()));
  const std::vector<ContactPoint> pts = collideConvexPair(cyl, ground, 0.01);
  ASSERT_GE(pts.size(), 1u);
  double deepest = -kInfinity;
  for (const ContactPoint& p : pts) deepest = std::max(deepest, p.depth);
  EXPECT_NEAR(deepest, 0.003, 1e-6);
}

TEST(Manifold, CylinderRestingFlatOnABoxHasAtLeastThreePoints) {
  const double depth = 0.002;
  const Placed ground(box(Vec3(4, 4, 1)), Vec3(0, 0, -0.5));
  const Placed cyl(cylinder(0.5, 1.0), Vec3(0.1, 0.3, 0.5 - depth));
  const std::vector<ContactPoint> pts = collideConvexPair(cyl, ground, 0.01);
  ASSERT_GE(pts.size(), 3u);
  ASSERT_LE(pts.size(), 4u);
  Vec3 centre = Vec3::Zero();
  for (const ContactPoint& p : pts) {
    EXPECT_NEAR(p.depth, depth, 1e-9);
    EXPECT_TRUE(p.normal.isApprox(-Vec3::UnitZ(), 1e-9));
    EXPECT_NEAR((p.point - cyl.pose.position).head<2>().norm(), 0.5, 1e-9);  // on the rim
    centre += p.point;
  }
  // The points surround the axis, so the cylinder cannot rock.
  centre /= static_cast<double>(pts.size());
  EXPECT_LT((centre - cyl.pose.position).head<2>().norm(), 0.2);
  // On its side: a line contact of two points.
  const Placed lying(cylinder(0.5, 1.0), Vec3(0, 0, 0.5 - depth),
                     axisAngle(kPi / 2, Vec3::UnitX()));
  const std::vector<ContactPoint> side = collideConvexPair(lying, ground, 0.01);
  ASSERT_EQ(side.size(), 2u);
  for (const ContactPoint& p : side) EXPECT_NEAR(p.depth, depth, 1e-9);
}

TEST(Manifold, CapsuleLyingOnABoxHasTwoPoints) {
  const Placed ground(box(Vec3(4, 4, 1)), Vec3(0, 0, -0.5));
  const Placed cap(capsule(0.2, 1.0), Vec3(0, 0, 0.19), axisAngle(kPi / 2, Vec3::UnitY()));
  const std::vector<ContactPoint> pts = collideConvexPair(cap, ground, 0.02);
  ASSERT_EQ(pts.size(), 2u);
  for (const ContactPoint& p : pts) {
    EXPECT_NEAR(p.depth, 0.01, 1e-9);
    EXPECT_NEAR(std::abs(p.point.x()), 0.5, 1e-9);
  }
}

TEST(Manifold, SwappingTheShapesTurnsTheNormalAround) {
  const Placed ground(box(Vec3(4, 4, 1)), Vec3(0, 0, -0.5));
  const Placed hull(convex(boxCorners(Vec3(0.5, 0.5, 0.5))), Vec3(0, 0, 0.49),
                    axisAngle(0.05, Vec3(1, 1, 0)));
  const std::vector<ContactPoint> ab = collideConvexPair(hull, ground, 0.02);
  const std::vector<ContactPoint> ba = collideConvexPair(ground, hull, 0.02);
  ASSERT_FALSE(ab.empty());
  ASSERT_EQ(ab.size(), ba.size());
  double max_ab = -kInfinity, max_ba = -kInfinity;
  for (const ContactPoint& p : ab) {
    EXPECT_LT(p.normal.z(), -0.99);  // hull -> ground: down
    max_ab = std::max(max_ab, p.depth);
  }
  for (const ContactPoint& p : ba) {
    EXPECT_GT(p.normal.z(), 0.99);  // ground -> hull: up
    max_ba = std::max(max_ba, p.depth);
  }
  EXPECT_NEAR(max_ab, max_ba, 1e-9);
  // Separated beyond the margin: nothing.
  const Placed far(convex(boxCorners(Vec3(0.5, 0.5, 0.5))), Vec3(0, 0, 0.6));
  EXPECT_TRUE(collideConvexPair(far, ground, 0.05).empty());
  // Within the margin: speculative points with a negative depth.
  const Placed near(convex(boxCorners(Vec3(0.5, 0.5, 0.5))), Vec3(0, 0, 0.53));
  const std::vector<ContactPoint> spec = collideConvexPair(near, ground, 0.05);
  ASSERT_EQ(spec.size(), 4u);
  for (const ContactPoint& p : spec) EXPECT_NEAR(p.depth, -0.03, 1e-9);
}

TEST(Manifold, PlaneAgainstAConvexHullEitherOrder) {
  const Placed ground(plane(Vec3::UnitZ(), 0.0), Vec3::Zero());
  const Placed hull(convex(boxCorners(Vec3(0.5, 0.5, 0.5), Vec3(1, 2, 3))), Vec3(-1, -2, -2.52));
  const std::vector<ContactPoint> pts = collideConvexPair(ground, hull, 0.05);
  ASSERT_EQ(pts.size(), 4u);
  for (const ContactPoint& p : pts) {
    EXPECT_NEAR(p.depth, 0.02, 1e-12);
    EXPECT_TRUE(p.normal.isApprox(Vec3::UnitZ(), 1e-12));
    EXPECT_NEAR(p.point.z(), -0.01, 1e-12);
  }
  const std::vector<ContactPoint> swapped = collideConvexPair(hull, ground, 0.05);
  ASSERT_EQ(swapped.size(), 4u);
  for (const ContactPoint& p : swapped) EXPECT_TRUE(p.normal.isApprox(-Vec3::UnitZ(), 1e-12));
}

TEST(Manifold, UnpreparedHullIsPreparedOnTheFly) {
  const Placed ground(box(Vec3(4, 4, 1)), Vec3(0, 0, -0.5));
  const ShapeDef hull = convex(boxCorners(Vec3(0.5, 0.5, 0.5)));
  Pose pose;
  pose.position = Vec3(0, 0, 0.49);
  std::vector<ContactPoint> out;
  EXPECT_EQ(collideConvex(ShapeInstance{&hull, nullptr, pose}, ground.instance(), 0.02, out), 4);
}

TEST(Manifold, RandomPairsNeverGiveNaN) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<ShapeDef> defs = {sphere(0.4), box(Vec3(0.8, 0.5, 0.3)), capsule(0.2, 0.6),
                                cylinder(0.3, 0.7), convex(boxCorners(Vec3(0.3, 0.4, 0.2)))};
  for (int k = 0; k < 500; ++k) {
    const Placed a(defs[k % 5], Vec3(0.4 * u(rng), 0.4 * u(rng), 0.4 * u(rng)),
                   Quat(u(rng), u(rng), u(rng), u(rng)).normalized());
    const Placed b(defs[(k / 5) % 5], Vec3(0.8 * u(rng), 0.8 * u(rng), 0.8 * u(rng)),
                   Quat(u(rng), u(rng), u(rng), u(rng)).normalized());
    const std::vector<ContactPoint> pts = collideConvexPair(a, b, 0.05);
    ASSERT_LE(pts.size(), 4u);
    for (const ContactPoint& p : pts) {
      ASSERT_TRUE(p.point.allFinite()) << k;
      ASSERT_TRUE(p.normal.allFinite()) << k;
      ASSERT_TRUE(std::isfinite(p.depth)) << k;
      EXPECT_NEAR(p.normal.norm(), 1.0, 1e-9);
      EXPECT_GT(p.depth, -0.05);
    }
  }
}

// --- Triangle meshes ---

/// The square [-2, 2]^2 at z = 0 as two triangles sharing the diagonal y = x.
Placed square() {
  ShapeDef m = shapeOf(ShapeType::Mesh);
  m.points = {Vec3(-2, -2, 0), Vec3(2, -2, 0), Vec3(2, 2, 0), Vec3(-2, 2, 0)};
  m.triangles = {{0, 1, 2}, {0, 2, 3}};
  return Placed(m, Vec3::Zero());
}

TEST(Mesh, SphereRestingOnASquareHasOnePointAtTheRightDepth) {
  const Placed mesh = square();
  const Placed s(sphere(0.5), Vec3(0.9, -0.7, 0.49));
  const std::vector<ContactPoint> pts = collideWithMesh(s, mesh, 0.005);
  ASSERT_EQ(pts.size(), 1u);
  EXPECT_NEAR(pts[0].depth, 0.01, 1e-12);
  EXPECT_TRUE(pts[0].normal.isApprox(-Vec3::UnitZ(), 1e-12));  // sphere -> mesh
  EXPECT_TRUE(pts[0].point.isApprox(Vec3(0.9, -0.7, -0.005), 1e-12));
  // The dispatcher's way in (collideConvex with a mesh as b) agrees.
  std::vector<ContactPoint> out;
  EXPECT_EQ(collideConvex(s.instance(), mesh.instance(), 0.005, out), 1);
}

TEST(Mesh, BoxRestingOnASquareHasFourPoints) {
  const Placed mesh = square();
  for (const Vec3& at : {Vec3(0.3, 0.2, 0.49), Vec3(0, 0, 0.49), Vec3(-1.1, 0.6, 0.49)}) {
    const Placed b(box(Vec3(1, 1, 1)), at, axisAngle(0.2, Vec3::UnitZ()));
    const std::vector<ContactPoint> pts = collideWithMesh(b, mesh, 0.02);
    ASSERT_EQ(pts.size(), 4u) << at.transpose();
    for (const ContactPoint& p : pts) {
      EXPECT_NEAR(p.depth, 0.01, 1e-9);
      EXPECT_TRUE(p.normal.isApprox(-Vec3::UnitZ(), 1e-9));
      const Vec3 local = b.pose.toLocal(p.point);
      EXPECT_NEAR(std::abs(local.x()), 0.5, 1e-9);
      EXPECT_NEAR(std::abs(local.y()), 0.5, 1e-9);
    }
  }
}

TEST(Mesh, CylinderAndCapsuleRestOnTheSquare) {
  const Placed mesh = square();
  // A cylinder standing across the diagonal: its cap touches both triangles.
  const Placed cyl(cylinder(0.5, 1.0), Vec3(0.1, 0.0, 0.495));
  const std::vector<ContactPoint> pts = collideWithMesh(cyl, mesh, 0.01);
  ASSERT_GE(pts.size(), 3u);
  ASSERT_LE(pts.size(), 4u);
  for (const ContactPoint& p : pts) {
    EXPECT_NEAR(p.depth, 0.005, 1e-9);
    EXPECT_TRUE(p.normal.isApprox(-Vec3::UnitZ(), 1e-9));
  }
  // A capsule lying across the diagonal: its two ends.
  const Placed cap(capsule(0.2, 1.0), Vec3(0.2, -0.1, 0.19), axisAngle(kPi / 2, Vec3::UnitY()));
  const std::vector<ContactPoint> two = collideWithMesh(cap, mesh, 0.02);
  ASSERT_EQ(two.size(), 2u);
  for (const ContactPoint& p : two) {
    EXPECT_NEAR(p.depth, 0.01, 1e-9);
    EXPECT_NEAR(std::abs(p.point.x() - 0.2), 0.5, 1e-9);
  }
}

TEST(Mesh, SphereOnTheInternalEdgeGetsTheFaceNormal) {
  const Placed mesh = square();
  // On the shared diagonal, and just to either side of it, slightly penetrating.
  for (double off : {0.0, 1e-4, -1e-4, 0.02}) {
    const Placed s(sphere(0.5), Vec3(0.5 + off, 0.5 - off, 0.48));
    const std::vector<ContactPoint> pts = collideWithMesh(s, mesh, 0.005);
    ASSERT_EQ(pts.size(), 1u) << off;
    EXPECT_TRUE(pts[0].normal.isApprox(-Vec3::UnitZ(), 1e-12)) << off;
    EXPECT_NEAR(pts[0].depth, 0.02, 1e-12);
  }
  // A sphere sunk deep at the edge still gets the face normal, never a sideways push.
  const Placed deep(sphere(0.5), Vec3(0.5, 0.5, 0.2));
  const std::vector<ContactPoint> pts = collideWithMesh(deep, mesh, 0.005);
  ASSERT_EQ(pts.size(), 1u);
  EXPECT_TRUE(pts[0].normal.isApprox(-Vec3::UnitZ(), 1e-12));
  EXPECT_NEAR(pts[0].depth, 0.3, 1e-12);
}

TEST(Mesh, RealEdgesKeepTheirNormal) {
  // A ridge: two triangles meeting at 90 degrees along the x axis (a convex edge).
  ShapeDef m = shapeOf(ShapeType::Mesh);
  m.points = {Vec3(-2, 0, 0),   Vec3(2, 0, 0),  Vec3(2, -1, -1),
              Vec3(-2, -1, -1), Vec3(2, 1, -1), Vec3(-2, 1, -1)};
  m.triangles = {{0, 3, 2}, {0, 2, 1}, {0, 1, 4}, {0, 4, 5}};
  const Placed ridge(m, Vec3::Zero());
  EXPECT_FALSE(ridge.geometry->edgeActive(1)[0]);  // (0, 2): between coplanar triangles
  EXPECT_TRUE(ridge.geometry->edgeActive(1)[2]);   // (1, 0): the ridge
  // A sphere right above the ridge touches the edge: the normal is straight down.
  const Placed s(sphere(0.5), Vec3(0.3, 0, 0.49));
  const std::vector<ContactPoint> pts = collideWithMesh(s, ridge, 0.005);
  ASSERT_GE(pts.size(), 1u);
  for (const ContactPoint& p : pts) {
    EXPECT_TRUE(p.normal.isApprox(-Vec3::UnitZ(), 1e-9));
    EXPECT_NEAR(p.depth, 0.01, 1e-9);
  }
}

TEST(Mesh, TreeQueryFindsExactlyTheOverlappingTriangles) {
  // A 20 x 20 grid of squares (800 triangles): the tree answers as a brute-force scan does.
  ShapeDef m = shapeOf(ShapeType::Mesh);
  const int n = 20;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) m.points.push_back(Vec3(i, j, 0.1 * std::sin(i + j)));
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const int v = j * (n + 1) + i;
      m.triangles.push_back({v, v + 1, v + n + 2});
      m.triangles.push_back({v, v + n + 2, v + n + 1});
    }
  const auto g = prepareGeometry(m);
  const Aabb query{Vec3(3.5, 7.2, -1), Vec3(6.1, 9.9, 1)};
  std::vector<int> found;
  g->queryTriangles(query, found);
  std::vector<int> brute;
  for (int t = 0; t < static_cast<int>(m.triangles.size()); ++t) {
    Aabb b{Vec3::Constant(kInfinity), Vec3::Constant(-kInfinity)};
    for (int v : m.triangles[t]) b.merge(Aabb{m.points[v], m.points[v]});
    if (b.overlaps(query)) brute.push_back(t);
  }
  EXPECT_EQ(found, brute);
  EXPECT_FALSE(found.empty());
}

// --- Mesh files ---

const std::filesystem::path kData = std::filesystem::path(__FILE__).parent_path() / "data";

std::filesystem::path tempFile(const std::string& name) {
  const auto dir = std::filesystem::temp_directory_path() / "linx_test_convex";
  std::filesystem::create_directories(dir);
  return dir / name;
}

void writeBinaryStl(const std::filesystem::path& path, const std::vector<std::array<Vec3, 3>>& tris,
                    std::size_t truncate_to = 0) {
  std::string bytes(80, ' ');
  const std::uint32_t count = static_cast<std::uint32_t>(tris.size());
  bytes.append(reinterpret_cast<const char*>(&count), 4);
  for (const auto& t : tris) {
    const Vec3 n = (t[1] - t[0]).cross(t[2] - t[0]).normalized();
    float f[12];
    for (int i = 0; i < 3; ++i) f[i] = static_cast<float>(n[i]);
    for (int k = 0; k < 3; ++k)
      for (int i = 0; i < 3; ++i) f[3 + 3 * k + i] = static_cast<float>(t[k][i]);
    bytes.append(reinterpret_cast<const char*>(f), sizeof f);
    bytes.append(2, '\0');
  }
  if (truncate_to > 0) bytes.resize(truncate_to);
  std::ofstream(path, std::ios::binary) << bytes;
}

const std::vector<std::array<Vec3, 3>> kTetra = {{Vec3(0, 0, 0), Vec3(0, 1, 0), Vec3(1, 0, 0)},
                                                 {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 0, 1)},
                                                 {Vec3(0, 0, 0), Vec3(0, 0, 1), Vec3(0, 1, 0)},
                                                 {Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1)}};

/// Sum over triangles of the signed volume (0, a, b, c): the enclosed volume when closed and
/// outward-wound.
double enclosedVolume(const ShapeDef& m) {
  double v = 0.0;
  for (const auto& t : m.triangles)
    v += m.points[t[0]].dot(m.points[t[1]].cross(m.points[t[2]])) / 6.0;
  return v;
}

TEST(MeshFile, ObjCubeIsTriangulated) {
  const ShapeDef m = io::loadMeshFile((kData / "cube.obj").string());
  EXPECT_EQ(m.type, ShapeType::Mesh);
  EXPECT_EQ(m.points.size(), 8u);
  EXPECT_EQ(m.triangles.size(), 12u);
  EXPECT_NEAR(enclosedVolume(m), 1.0, 1e-12);
  const auto g = prepareGeometry(m);
  // Every edge of a cube's triangulation: the diagonals are inactive, the cube's edges active.
  int active = 0;
  for (int t = 0; t < 12; ++t)
    for (bool a : g->edgeActive(t)) active += a;
  EXPECT_EQ(active, 24);  // 12 cube edges, each seen from 2 triangles
}

TEST(MeshFile, BinaryStlTetrahedron) {
  const auto path = tempFile("tetra.stl");
  writeBinaryStl(path, kTetra);
  const ShapeDef m = io::loadMeshFile(path.string());
  EXPECT_EQ(m.points.size(), 4u);  // shared corners welded
  EXPECT_EQ(m.triangles.size(), 4u);
  EXPECT_NEAR(enclosedVolume(m), 1.0 / 6.0, 1e-7);
  EXPECT_NO_THROW(prepareGeometry(m));
}

TEST(MeshFile, AsciiStlTetrahedron) {
  const ShapeDef m = io::loadMeshFile((kData / "tetra_ascii.stl").string());
  EXPECT_EQ(m.points.size(), 4u);
  EXPECT_EQ(m.triangles.size(), 4u);
  EXPECT_NEAR(enclosedVolume(m), 1.0 / 6.0, 1e-12);
}

void expectLoadError(const std::filesystem::path& path, const std::string& words) {
  try {
    io::loadMeshFile(path.string());
    ADD_FAILURE() << "no error for " << path;
  } catch (const std::runtime_error& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find(path.string()), std::string::npos) << what;
    EXPECT_NE(what.find(words), std::string::npos) << what;
  }
}

TEST(MeshFile, BadFilesAreReportedWithTheirName) {
  expectLoadError(tempFile("missing.stl"), "cannot open");
  const auto empty = tempFile("empty.obj");
  std::ofstream(empty).flush();
  expectLoadError(empty, "empty");
  const auto truncated = tempFile("truncated.stl");
  writeBinaryStl(truncated, kTetra, 84 + 50 * 3 + 10);
  expectLoadError(truncated, "truncated binary STL");
  const auto bad_index = tempFile("bad_index.obj");
  std::ofstream(bad_index) << "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 7\n";
  expectLoadError(bad_index, "out of range");
  // tinyobjloader reads a coordinate it cannot parse as 0: refused, with the line.
  const auto nan_vertex = tempFile("nan_vertex.obj");
  std::ofstream(nan_vertex) << "v 0 0 0\nv nan 0 0\nv 0 1 0\nf 1 2 3\n";
  expectLoadError(nan_vertex, "OBJ line 2: vertex coordinate 'nan' is not a finite number");
  const auto word_vertex = tempFile("word_vertex.obj");
  std::ofstream(word_vertex) << "# a comment\nv 0 0 0\nv 1 0 0\nv a b c\nf 1 2 3\n";
  expectLoadError(word_vertex, "OBJ line 4: vertex coordinate 'a' is not a finite number");
  const auto signed_vertex = tempFile("signed_vertex.obj");  // as tinyobjloader reads them
  std::ofstream(signed_vertex) << "v +0 -0 0\r\nv 1e0 0 0\r\nv 0 +1.0 0\r\nf 1 2 3\r\n";
  EXPECT_EQ(io::loadMeshFile(signed_vertex.string()).points[2], Vec3(0, 1, 0));
  const auto unknown = tempFile("mesh.ply");
  std::ofstream(unknown) << "ply\n";
  expectLoadError(unknown, "unknown extension");
}

// A binary STL is as long as its count says (84 + 50 n bytes): one with more data than its count,
// which used to be read as its first n triangles, is refused as one with less.
TEST(MeshFile, BinaryStlSizeMustMatchItsCount) {
  const auto longer = tempFile("longer.stl");
  writeBinaryStl(longer, kTetra);
  std::ofstream(longer, std::ios::binary | std::ios::app) << std::string(50, '\0');
  expectLoadError(longer,
                  "binary STL: 4 triangles need 284 bytes (84 + 50 per triangle), the file "
                  "has 334: the triangle count does not match the data");
}

// An OBJ face of kMaxObjFaceVertices is triangulated (a regular polygon: n - 2 triangles covering
// its area, n/2 sin(2 pi / n)); one more vertex is refused with the face's line, so that reading
// takes time linear in the file's size (one face of 400,000 took minutes).
TEST(MeshFile, ObjFacesAreBoundedInVertices) {
  const auto polygon = [](std::size_t n) {
    std::string text = "# a regular polygon\n";
    for (std::size_t i = 0; i < n; ++i) {
      const double a = 2 * std::numbers::pi * static_cast<double>(i) / static_cast<double>(n);
      text += fmt::format("v {:.17g} {:.17g} 0\n", std::cos(a), std::sin(a));
    }
    text += "f";
    for (std::size_t i = 1; i <= n; ++i) text += fmt::format(" {}", i);
    return text + "\n";
  };
  const std::size_t n = io::kMaxObjFaceVertices;
  const auto largest = tempFile("largest_face.obj");
  std::ofstream(largest) << polygon(n);
  const ShapeDef m = io::loadMeshFile(largest.string());
  ASSERT_EQ(m.triangles.size(), n - 2);
  double area = 0;
  for (const auto& t : m.triangles) {
    const Vec3 e1 =
        m.points[static_cast<std::size_t>(t[1])] - m.points[static_cast<std::size_t>(t[0])];
    const Vec3 e2 =
        m.points[static_cast<std::size_t>(t[2])] - m.points[static_cast<std::size_t>(t[0])];
    area += 0.5 * e1.cross(e2).norm();
  }
  EXPECT_NEAR(
      area, 0.5 * static_cast<double>(n) * std::sin(2 * std::numbers::pi / static_cast<double>(n)),
      1e-12);
  const auto above = tempFile("face_above.obj");
  std::ofstream(above) << polygon(n + 1);
  expectLoadError(above, fmt::format("OBJ line {}: a face of {} vertices, above the limit of {}",
                                     n + 3, n + 1, n));
}

/// The whole message of a file refused: "mesh file PATH: PROBLEM".
void expectLoadMessage(const std::filesystem::path& path, const std::string& text,
                       const std::string& problem) {
  std::ofstream(path, std::ios::binary) << text;
  try {
    io::loadMeshFile(path.string());
    ADD_FAILURE() << "no error for " << text;
  } catch (const std::runtime_error& e) {
    EXPECT_EQ(e.what(), "mesh file " + path.string() + ": " + problem) << text;
  }
}

// tinyobjloader's own text stays out (it stops at `f 0 1 2` and `f a b c` with "Failed parse `f'
// line(e.g. zero value for face index..."); what it would read silently (a missing coordinate as
// 0, an index beyond an int wrapped to a valid one) is refused; indices are quoted as written.
TEST(MeshFile, ObjLinesAreCheckedWithTheirLineAndWords) {
  const auto obj = tempFile("lines.obj");
  const std::string tri = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";
  expectLoadMessage(obj, tri + "f 0 1 2\n", "OBJ line 4: face index 0 (indices start at 1)");
  expectLoadMessage(obj, tri + "f a b c\n", "OBJ line 4: 'a' is not a vertex index");
  expectLoadMessage(obj, tri + "f 1 2 7\n", "OBJ line 4: vertex index 7 out of range [1, 3]");
  expectLoadMessage(obj, tri + "f -1 -2 -9\n",
                    "OBJ line 4: vertex index -9 out of range [-3, -1] (counting back from the 3 "
                    "vertices before it)");
  expectLoadMessage(
      obj, "f -1 -2 -3\n" + tri,
      "OBJ line 1: vertex index -1 counts back from no vertex (none comes before it)");
  expectLoadMessage(obj, tri + "v 5 5 5\nf 1 2 2147483651\n",
                    "OBJ line 5: vertex index 2147483651 out of range [1, 4]");
  expectLoadMessage(obj, tri + "f 1 2 4294967299\n",
                    "OBJ line 4: vertex index 4294967299 out of range [1, 3]");
  expectLoadMessage(obj, tri + "f 1 2 99999999999999999999\n",
                    "OBJ line 4: vertex index 99999999999999999999 out of range [1, 3]");
  expectLoadMessage(obj, "f 1 2 3\n", "OBJ line 1: vertex index 1, but the file has no vertices");
  expectLoadMessage(obj, "v 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n",
                    "OBJ line 1: a vertex needs 3 coordinates, got 2");
  expectLoadMessage(obj, tri + "f 1 2\n", "OBJ line 4: a face needs at least 3 vertices, got 2");
  expectLoadMessage(obj, tri + "f 1 2 -2\n", "OBJ line 4: the face repeats vertex 2");
  expectLoadMessage(obj, tri + "f 1/1 2/0 3/1\n",
                    "OBJ line 4: texture coordinate index 0 (indices start at 1)");
  expectLoadMessage(obj, tri + "f 1//1 2//x 3//1\n", "OBJ line 4: '2//x' is not a vertex index");
  expectLoadMessage(obj, tri + "f 1/ 2 3\n", "OBJ line 4: '1/' is not a vertex index");
  // Line numbers as tinyobjloader counts them: "\r\n" and a lone "\r" end a line too.
  expectLoadMessage(obj, "v 0 0 0\r\nv 1 0 0\rv 0 1 0\n\nf 1 2 0\n",
                    "OBJ line 5: face index 0 (indices start at 1)");
  // Another line tinyobjloader refuses: its line, not its text.
  expectLoadMessage(obj, tri + "f 1 2 3\nl 0 1\n", "OBJ line 5: cannot read it");
  // Still read: relative indices, v/vt/vn, vertices after the faces that use them.
  std::ofstream(obj) << "v 0 0 0\nv 1 0 0\nv 0 1 0\nf -3/1/1 -2//1 +3/2\nf 1 2 4\nv 0 0 1\n";
  const ShapeDef m = io::loadMeshFile(obj.string());
  ASSERT_EQ(m.triangles.size(), 2u);
  EXPECT_EQ(m.triangles[0], (std::array<int, 3>{0, 1, 2}));
  EXPECT_EQ(m.triangles[1], (std::array<int, 3>{0, 1, 3}));
}

TEST(MeshFile, StlProblemsAreReportedPlainly) {
  const auto stl = tempFile("bad.stl");
  const std::string head = "solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\n";
  const std::string tail = "endloop\nendfacet\nendsolid x\n";
  expectLoadMessage(stl, head + "vertex 1 0\nvertex 0 1 0\n" + tail,
                    "ASCII STL line 5: a vertex needs 3 coordinates, got 2");
  expectLoadMessage(stl, head + "vertex 1 0 nan\nvertex 0 1 0\n" + tail,
                    "ASCII STL line 5: vertex coordinate 'nan' is not a finite number");
  expectLoadMessage(stl, head + "vertex 1 0 1e999\nvertex 0 1 0\n" + tail,
                    "ASCII STL line 5: vertex coordinate '1e999' is not a finite number");
  expectLoadMessage(stl, head + "vertex 1 0 0\nvertex 0 1 0\nvertex 1 1 0\n" + tail,
                    "ASCII STL line 8: a facet needs 3 vertices, got 4");
  expectLoadMessage(stl, head + "vertex 1 0 0\nvertex 0 1 0\n",
                    "ASCII STL: truncated (no endsolid)");
  // A solid with no facets is ASCII (not a binary file shorter than its header).
  expectLoadMessage(stl, "solid empty\nendsolid empty\n", "no triangles");
  // Binary: a count of 2^32 - 1 in a small file, a non-finite corner.
  std::string bytes(80, ' ');
  bytes += std::string("\xff\xff\xff\xff", 4) + std::string(100, '\0');
  expectLoadMessage(stl, bytes,
                    "truncated binary STL: 4294967295 triangles need 214748364834 bytes, the file "
                    "has 184");
  writeBinaryStl(stl, {{Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, std::nan(""))}});
  std::ifstream in(stl, std::ios::binary);
  const std::string nan_corner((std::istreambuf_iterator<char>(in)),
                               std::istreambuf_iterator<char>());
  expectLoadMessage(stl, nan_corner, "triangle 0 has a non-finite coordinate");
}

// --- Prepared geometry and bad input ---

TEST(Geometry, HullOfACubeHasSixQuadrilateralFaces) {
  std::vector<Vec3> pts = boxCorners(Vec3(0.5, 1.0, 1.5));
  pts.push_back(Vec3(0.1, 0.2, 0.3));  // inside: not a vertex
  const auto g = prepareGeometry(convex(pts));
  ASSERT_NE(g, nullptr);
  EXPECT_EQ(g->vertices().size(), 8u);
  EXPECT_EQ(g->faces().size(), 6u);
  EXPECT_EQ(g->edges().size(), 12u);
  for (const HullFace& f : g->faces()) {
    EXPECT_EQ(f.vertices.size(), 4u);
    EXPECT_NEAR(f.normal.cwiseAbs().maxCoeff(), 1.0, 1e-12);
    // Counter-clockwise seen from outside: the polygon's area vector is along the normal.
    Vec3 area = Vec3::Zero();
    for (std::size_t k = 0; k < f.vertices.size(); ++k)
      area += g->vertices()[f.vertices[k]].cross(
          g->vertices()[f.vertices[(k + 1) % f.vertices.size()]]);
    EXPECT_GT(area.dot(f.normal), 0.0);
    for (int v : f.vertices) EXPECT_NEAR(f.normal.dot(g->vertices()[v]), f.offset, 1e-12);
  }
  EXPECT_EQ(prepareGeometry(sphere(1.0)), nullptr);
  EXPECT_EQ(prepareGeometry(box(Vec3::Ones())), nullptr);
}

TEST(Geometry, BadInputThrows) {
  EXPECT_THROW(prepareGeometry(convex({Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)})),
               std::invalid_argument);
  EXPECT_THROW(prepareGeometry(convex({Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(1, 1, 0),
                                       Vec3(0.5, 0.5, 0)})),
               std::invalid_argument);  // coplanar
  EXPECT_THROW(prepareGeometry(
                   convex({Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, std::nan(""))})),
               std::invalid_argument);
  ShapeDef m = shapeOf(ShapeType::Mesh);
  m.points = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)};
  m.triangles = {{0, 1, 3}};
  EXPECT_THROW(prepareGeometry(m), std::invalid_argument);  // index out of range
  m.triangles = {{0, 1, 1}};
  EXPECT_THROW(prepareGeometry(m), std::invalid_argument);  // repeats a vertex
  m.points.push_back(Vec3(2, 0, 0));
  m.triangles = {{0, 1, 3}};
  EXPECT_THROW(prepareGeometry(m), std::invalid_argument);  // degenerate
  m.points.pop_back();
  m.triangles.clear();
  EXPECT_THROW(prepareGeometry(m), std::invalid_argument);  // no triangles
  m.triangles = {{0, 1, 2}};
  m.points[1] = Vec3(kInfinity, 0, 0);
  EXPECT_THROW(prepareGeometry(m), std::invalid_argument);  // not finite
  try {
    prepareGeometry(convex({Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)}));
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("at least 4"), std::string::npos) << e.what();
  }
}

std::string hullError(std::vector<Vec3> points) {
  try {
    prepareGeometry(convex(std::move(points)));
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "accepted";
}

// Point sets with no volume are named in plain words before Qhull sees them (it said "QH6154
// Qhull precision error: Initial simplex is flat..." or "QH6421 qhull internal error..."), and
// coordinates whose volume overflows are called too large, not a flat hull of volume -nan.
TEST(Geometry, HullsWithoutAVolumeAreRefusedInPlainWords) {
  EXPECT_EQ(hullError(std::vector<Vec3>(5, Vec3(1, 2, 3))), "convex: all 5 points are the same");
  EXPECT_EQ(hullError({Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(2, 0, 0), Vec3(3, 0, 0)}),
            "convex: all 4 points lie on one line");
  EXPECT_EQ(hullError({Vec3(0, 0, 0), Vec3(1, 1, 1), Vec3(2, 2, 2), Vec3(0.1, 0.1, 0.1)}),
            "convex: all 4 points lie on one line");
  EXPECT_EQ(
      hullError({Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(1, 1, 0), Vec3(0.5, 0.5, 0)}),
      "convex: all 5 points lie in one plane");
  EXPECT_EQ(hullError({Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1),
                       Vec3(0.3333333333333333, 0.3333333333333333, 0.3333333333333334)}),
            "convex: all 4 points lie in one plane");
  // A real tetrahedron, but 1e-9 m thick and 1e9 m across: beyond what the hull can resolve.
  EXPECT_EQ(hullError({Vec3(0, 0, 0), Vec3(1e-9, 0, 0), Vec3(0, 1e9, 0), Vec3(0, 0, 1e9)}),
            "convex: the hull is 1.41e+09 m across but only 1e-09 m thick, a spread of 18 orders "
            "of magnitude (at most 9)");
  EXPECT_EQ(hullError({Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1e-13)}),
            "convex: the hull is 1.41 m across but only 1e-13 m thick, a spread of 13 orders of "
            "magnitude (at most 9)");
  EXPECT_EQ(hullError({Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1e-12, 0), Vec3(0, 0, 1e-12)}),
            "convex: the hull is 1 m long but only 1e-12 m wide, a spread of 12 orders of "
            "magnitude (at most 9)");
  EXPECT_EQ(
      hullError({Vec3(1e300, 0, 0), Vec3(-1e300, 0, 0), Vec3(0, 1e300, 0), Vec3(0, 0, 1e300)}),
      "convex: point 0 has a coordinate of 1e+300 m, too large (at most 1e+50 m: the hull's "
      "volume and inertia would overflow)");
  EXPECT_EQ(hullError({Vec3(0, 0, 0), Vec3(0, 1e150, 0), Vec3(0, 0, 1e150), Vec3(1, 0, 0)}),
            "convex: point 1 has a coordinate of 1e+150 m, too large (at most 1e+50 m: the hull's "
            "volume and inertia would overflow)");
  EXPECT_EQ(hullError({Vec3(0, 0, 0), Vec3(1e-200, 0, 0), Vec3(0, 1e-200, 0), Vec3(0, 0, 1e-200)}),
            "convex: the points span only 1e-200 m, too small (at least 1e-50 m: the hull's volume "
            "and inertia would underflow)");
  // Within the bounds, both ends.
  for (double scale : {1e-50, 1e49}) {
    const auto g = prepareGeometry(
        convex({Vec3(0, 0, 0), Vec3(scale, 0, 0), Vec3(0, scale, 0), Vec3(0, 0, scale)}));
    EXPECT_GT(g->volume(), 0.0);
    EXPECT_TRUE(g->unitInertia().allFinite());
    EXPECT_GT(g->unitInertia().diagonal().minCoeff(), 0.0);
  }

  ShapeDef m = shapeOf(ShapeType::Mesh);
  m.points = {Vec3(1e300, 0, 0), Vec3(-1e300, 0, 0), Vec3(0, 1e300, 0)};
  m.triangles = {{0, 1, 2}};
  try {
    prepareGeometry(m);
    ADD_FAILURE() << "a mesh of 1e300 m accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_STREQ(e.what(),
                 "mesh: vertex 0 has a coordinate of 1e+300 m, too large (at most 1e+50 m: "
                 "triangle areas would overflow)");
  }
  m.points = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)};
  m.triangles = {{0, 1, 1}};
  try {
    prepareGeometry(m);
    ADD_FAILURE() << "a triangle repeating a vertex accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_STREQ(e.what(), "mesh: triangle 0 repeats vertex 1");
  }
}

// --- Convex mass properties ---

TEST(ConvexMass, BoxCornersEqualTheBox) {
  const Vec3 size(1.0, 2.0, 3.0);
  ShapeDef b = box(size);
  b.position = Vec3(0.5, -1, 2);
  b.orientation = axisAngle(0.7, Vec3(1, 2, 3));
  ShapeDef c = convex(boxCorners(0.5 * size));
  c.position = b.position;
  c.orientation = b.orientation;
  const MassProperties mb = shapeMassProperties(b, 3.0), mc = shapeMassProperties(c, 3.0);
  EXPECT_NEAR(shapeVolume(c), 6.0, 1e-12);
  EXPECT_NEAR(mc.mass, mb.mass, 1e-12);
  EXPECT_TRUE(mc.center.isApprox(mb.center, 1e-12));
  EXPECT_LT((mc.inertia - mb.inertia).norm(), 1e-12 * mb.inertia.norm());
}

TEST(ConvexMass, HullOfPointsOnASphereApproachesTheSphere) {
  // Fibonacci points on the unit sphere: the inscribed hull's volume and inertia converge to
  // the sphere's as O(1/n).
  std::vector<Vec3> pts;
  const int n = 4000;
  const double golden = kPi * (3.0 - std::sqrt(5.0));
  for (int i = 0; i < n; ++i) {
    const double z = 1.0 - 2.0 * (i + 0.5) / n, r = std::sqrt(1.0 - z * z);
    pts.push_back(Vec3(r * std::cos(golden * i), r * std::sin(golden * i), z) + Vec3(2, 0, 0));
  }
  const MassProperties h = shapeMassProperties(convex(pts), 1.0);
  const MassProperties s = shapeMassProperties(sphere(1.0), 1.0);
  EXPECT_NEAR(h.mass / s.mass, 1.0, 2e-3);
  EXPECT_LT((h.center - Vec3(2, 0, 0)).norm(), 1e-3);
  EXPECT_LT((h.inertia - s.inertia).norm() / s.inertia.norm(), 4e-3);
}

TEST(ConvexMass, OffCentreTetrahedronMatchesTheClosedForm) {
  // The corner tetrahedron (0, a e_x, b e_y, c e_z) moved by d. Direct integration gives
  // V = abc/6, centroid d + (a, b, c)/4, and about the centroid (density rho, m = rho V):
  // I_xx = 3m (b^2 + c^2)/80 (and cyclic), I_xy = m ab/80 (and cyclic).
  const double a = 1.0, b = 2.0, c = 3.0, rho = 2.0;
  const Vec3 d(5.0, -2.0, 1.0);
  const ShapeDef t = convex({d, d + Vec3(a, 0, 0), d + Vec3(0, b, 0), d + Vec3(0, 0, c)});
  const MassProperties p = shapeMassProperties(t, rho);
  const double m = rho * a * b * c / 6.0;
  EXPECT_NEAR(p.mass, m, 1e-12);
  EXPECT_TRUE(p.center.isApprox(d + Vec3(a, b, c) / 4.0, 1e-12));
  Mat3 expected;
  expected << 3 * m * (b * b + c * c) / 80, m * a * b / 80, m * a * c / 80,  //
      m * a * b / 80, 3 * m * (a * a + c * c) / 80, m * b * c / 80,          //
      m * a * c / 80, m * b * c / 80, 3 * m * (a * a + b * b) / 80;
  EXPECT_LT((p.inertia - expected).norm(), 1e-12 * expected.norm());
  // Placed by a pose: the centroid moves with it and the inertia turns with it.
  ShapeDef placed = t;
  placed.position = Vec3(0.1, 0.2, 0.3);
  placed.orientation = axisAngle(1.1, Vec3(0.3, -1, 0.4));
  const MassProperties q = shapeMassProperties(placed, rho);
  const Mat3 r = placed.orientation.toRotationMatrix();
  EXPECT_TRUE(q.center.isApprox(placed.position + r * (d + Vec3(a, b, c) / 4.0), 1e-12));
  EXPECT_LT((q.inertia - r * expected * r.transpose()).norm(), 1e-12 * expected.norm());
}

}  // namespace
}  // namespace linx::collision
