// Exact narrowphase of the primitive pairs (collision/primitive_pairs.hpp) against closed forms:
// depths, normals and points of known placements, the sign convention (swapping a and b turns
// the normal around), speculative points within the margin and none beyond it, manifolds that
// let a box rest on a box, a capsule on a capsule or a box and a cylinder on a plane, feature ids
// that stay put under a tiny motion, degenerate placements (never NaN, never a zero normal), and
// box-box and capsule-box depths against a brute-force minimum over directions of the overlap of
// the support functions, h_a(n) + h_b(-n), for random rotations.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numbers>
#include <random>
#include <tuple>
#include <vector>

#include "collision/manifold_reduction.hpp"
#include "collision/primitive_pairs.hpp"

namespace linx::collision {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kTol = 1e-12;

// ShapeDef has members without default initialisers (-Wmissing-field-initializers rules out
// designated initialisers), so the helpers assign.
ShapeDef sphereDef(double r) {
  ShapeDef d;
  d.type = ShapeType::Sphere;
  d.radius = r;
  return d;
}
ShapeDef boxDef(const Vec3& size) {
  ShapeDef d;
  d.type = ShapeType::Box;
  d.size = size;
  return d;
}
ShapeDef capsuleDef(double r, double length) {
  ShapeDef d;
  d.type = ShapeType::Capsule;
  d.radius = r;
  d.length = length;
  return d;
}
ShapeDef cylinderDef(double r, double length) {
  ShapeDef d = capsuleDef(r, length);
  d.type = ShapeType::Cylinder;
  return d;
}
ShapeDef planeDef(const Vec3& normal, double offset) {
  ShapeDef d;
  d.type = ShapeType::Plane;
  d.normal = normal;
  d.offset = offset;
  return d;
}

ShapeInstance at(const ShapeDef& def, const Vec3& position, const Quat& q = Quat::Identity()) {
  return ShapeInstance{.def = &def, .geometry = nullptr, .pose = Pose{position, q}};
}

Quat rotation(const Vec3& axis, double angle) {
  return Quat(Eigen::AngleAxisd(angle, axis.normalized()));
}

using Routine = int (*)(const ShapeInstance&, const ShapeInstance&, double,
                        std::vector<ContactPoint>&);

std::vector<ContactPoint> run(Routine f, const ShapeInstance& a, const ShapeInstance& b,
                              double margin = 0.0) {
  std::vector<ContactPoint> out;
  const int n = f(a, b, margin, out);
  EXPECT_EQ(n, static_cast<int>(out.size()));
  EXPECT_LE(n, kMaxPointsPerPair);
  for (const ContactPoint& c : out) {
    EXPECT_TRUE(c.point.allFinite());
    EXPECT_TRUE(std::isfinite(c.depth));
    EXPECT_NEAR(c.normal.norm(), 1.0, 1e-12);
    EXPECT_GT(c.depth, -margin);
  }
  return out;
}

double maxDepth(const std::vector<ContactPoint>& points) {
  double d = -kInfinity;
  for (const ContactPoint& c : points) d = std::max(d, c.depth);
  return d;
}

std::vector<std::uint32_t> features(const std::vector<ContactPoint>& points) {
  std::vector<std::uint32_t> ids;
  for (const ContactPoint& c : points) ids.push_back(c.feature);
  std::sort(ids.begin(), ids.end());
  return ids;
}

void expectVec(const Vec3& actual, const Vec3& expected, double tol = 1e-12) {
  EXPECT_NEAR((actual - expected).norm(), 0.0, tol)
      << "actual " << actual.transpose() << ", expected " << expected.transpose();
}

// Swapping a and b gives the same points and depths with the normal turned around (in any
// order: the reference face may change sides). Points agree within point_tol: a box clipped
// against the other's face may sit up to the clipping allowance (1e-6 of the mean half extent)
// further out.
void expectSwapSymmetric(Routine f, const ShapeInstance& a, const ShapeInstance& b, double margin,
                         double point_tol = 1e-12) {
  const auto ab = run(f, a, b, margin);
  const auto ba = run(f, b, a, margin);
  ASSERT_EQ(ab.size(), ba.size());
  for (const ContactPoint& p : ab) {
    const auto match = std::find_if(ba.begin(), ba.end(), [&](const ContactPoint& q) {
      return (p.point - q.point).norm() < point_tol && (p.normal + q.normal).norm() < 1e-12 &&
             std::abs(p.depth - q.depth) < 1e-12;
    });
    EXPECT_NE(match, ba.end()) << "no swapped match for the point at " << p.point.transpose();
  }
}

// --- spheres and capsules ----------------------------------------------------------------------

TEST(SphereSphere, DepthNormalAndMidwayPoint) {
  const ShapeDef da = sphereDef(1.0), db = sphereDef(0.75);
  const Vec3 dir = Vec3(1.0, 2.0, -2.0) / 3.0;
  const auto pts =
      run(collideSphereSphere, at(da, Vec3(1, 1, 1)), at(db, Vec3(1, 1, 1) + 1.5 * dir));
  ASSERT_EQ(pts.size(), 1u);
  EXPECT_NEAR(pts[0].depth, 0.25, kTol);
  expectVec(pts[0].normal, dir);  // from a towards b
  // Surfaces along the normal at 1.0 (a) and 1.5 - 0.75 = 0.75 (b): midway 0.875.
  expectVec(pts[0].point, Vec3(1, 1, 1) + 0.875 * dir);
  // Swapped: same depth, opposite normal.
  const auto ba =
      run(collideSphereSphere, at(db, Vec3(1, 1, 1) + 1.5 * dir), at(da, Vec3(1, 1, 1)));
  ASSERT_EQ(ba.size(), 1u);
  expectVec(ba[0].normal, -dir);
  EXPECT_NEAR(ba[0].depth, 0.25, kTol);
}

TEST(SphereSphere, SpeculativeGapWithinMarginOnly) {
  const ShapeDef d = sphereDef(0.5);
  const auto near = run(collideSphereSphere, at(d, Vec3::Zero()), at(d, Vec3(1.05, 0, 0)), 0.1);
  ASSERT_EQ(near.size(), 1u);
  EXPECT_NEAR(near[0].depth, -0.05, kTol);
  EXPECT_NEAR(near[0].point.x(), 0.525, kTol);  // midway across the gap
  EXPECT_TRUE(run(collideSphereSphere, at(d, Vec3::Zero()), at(d, Vec3(1.15, 0, 0)), 0.1).empty());
  EXPECT_TRUE(run(collideSphereSphere, at(d, Vec3::Zero()), at(d, Vec3(1.05, 0, 0)), 0.0).empty());
}

TEST(SphereSphere, CoincidentCentresGiveAUnitNormal) {
  const ShapeDef d = sphereDef(0.5);
  const auto pts = run(collideSphereSphere, at(d, Vec3(2, 3, 4)), at(d, Vec3(2, 3, 4)));
  ASSERT_EQ(pts.size(), 1u);
  EXPECT_NEAR(pts[0].depth, 1.0, kTol);
}

TEST(SphereCapsule, SideAndCapClosedForms) {
  const ShapeDef ds = sphereDef(0.3), dc = capsuleDef(0.2, 2.0);
  // Capsule along world x (local z turned onto x), centred at the origin.
  const Quat q = rotation(Vec3::UnitY(), kPi / 2);
  // Beside the cylindrical part: distance to the axis 0.45, depth 0.5 - 0.45.
  auto side = run(collideSphereCapsule, at(ds, Vec3(0.3, 0.0, 0.45)), at(dc, Vec3::Zero(), q));
  ASSERT_EQ(side.size(), 1u);
  EXPECT_NEAR(side[0].depth, 0.05, kTol);
  expectVec(side[0].normal, -Vec3::UnitZ());  // sphere (a) above, capsule (b) below
  expectVec(side[0].point, Vec3(0.3, 0.0, 0.5 * (0.45 - 0.3 + 0.2)));
  // Beyond the end cap at x = 1: distance from (1, 0, 0) to (1.3, 0.4, 0) is 0.5: depth 0.
  auto cap = run(collideSphereCapsule, at(ds, Vec3(1.3, 0.4, 0.0)), at(dc, Vec3::Zero(), q), 0.01);
  ASSERT_EQ(cap.size(), 1u);
  EXPECT_NEAR(cap[0].depth, 0.0, kTol);
  expectVec(cap[0].normal, -Vec3(0.6, 0.8, 0.0));
  // Sphere centre on the axis: pushed across the axis, depth = sum of radii.
  auto axis = run(collideSphereCapsule, at(ds, Vec3(0.2, 0, 0)), at(dc, Vec3::Zero(), q));
  ASSERT_EQ(axis.size(), 1u);
  EXPECT_NEAR(axis[0].depth, 0.5, kTol);
  EXPECT_NEAR(axis[0].normal.x(), 0.0, kTol);
}

TEST(CapsuleCapsule, CrossedGivesOnePoint) {
  const ShapeDef da = capsuleDef(0.2, 2.0), db = capsuleDef(0.3, 1.0);
  // a along x, b along y, 0.45 above: depth 0.5 - 0.45, normal +z, one point over the crossing.
  const auto pts =
      run(collideCapsuleCapsule, at(da, Vec3::Zero(), rotation(Vec3::UnitY(), kPi / 2)),
          at(db, Vec3(0.1, -0.2, 0.45), rotation(Vec3::UnitX(), kPi / 2)));
  ASSERT_EQ(pts.size(), 1u);
  EXPECT_NEAR(pts[0].depth, 0.05, kTol);
  expectVec(pts[0].normal, Vec3::UnitZ());
  expectVec(pts[0].point, Vec3(0.1, 0.0, 0.5 * (0.2 + 0.45 - 0.3)));
}

TEST(CapsuleCapsule, ParallelRestingGivesTheOverlapEnds) {
  const ShapeDef da = capsuleDef(0.2, 2.0), db = capsuleDef(0.3, 1.6);
  const Quat q = rotation(Vec3::UnitY(), kPi / 2);  // both along world x
  // a's core [-1, 1] on x, b's core [0.2, 1.8] at height 0.49: overlap [0.2, 1], depth 0.01.
  const ShapeInstance a = at(da, Vec3::Zero(), q);
  const auto pts = run(collideCapsuleCapsule, a, at(db, Vec3(1.0, 0.0, 0.49), q));
  ASSERT_EQ(pts.size(), 2u);
  for (const ContactPoint& c : pts) {
    EXPECT_NEAR(c.depth, 0.01, kTol);
    expectVec(c.normal, Vec3::UnitZ());
    EXPECT_NEAR(c.point.z(), 0.5 * (0.2 + 0.49 - 0.3), kTol);
  }
  std::vector<double> xs{pts[0].point.x(), pts[1].point.x()};
  std::sort(xs.begin(), xs.end());
  EXPECT_NEAR(xs[0], 0.2, kTol);
  EXPECT_NEAR(xs[1], 1.0, kTol);
  // A tiny slide along and across keeps the features.
  const auto moved = run(collideCapsuleCapsule, a, at(db, Vec3(1.0 + 1e-4, 2e-5, 0.49), q));
  EXPECT_EQ(features(moved), features(pts));
  // Swapped: b under a gives the normal the other way.
  expectSwapSymmetric(collideCapsuleCapsule, a, at(db, Vec3(1.0, 0.0, 0.49), q), 0.0);
}

TEST(CapsuleCapsule, SlightlyCrossedKeepsTheDeepestPoint) {
  const ShapeDef d = capsuleDef(0.25, 2.0);
  const Quat qa = rotation(Vec3::UnitY(), kPi / 2);
  const Quat qb = rotation(Vec3::UnitZ(), 0.02) * qa;  // crossed by 0.02 rad about z
  const auto pts =
      run(collideCapsuleCapsule, at(d, Vec3::Zero(), qa), at(d, Vec3(0, 0, 0.49), qb), 0.05);
  // The axes cross above the origin at distance 0.49: the deepest point, depth 0.01.
  EXPECT_GE(pts.size(), 2u);
  EXPECT_NEAR(maxDepth(pts), 0.01, kTol);
}

TEST(CapsuleCapsule, DegeneratePlacementsStayFinite) {
  const ShapeDef d = capsuleDef(0.2, 1.0), point = capsuleDef(0.2, 0.0);
  // Same axis, same place: coincident cores.
  auto same = run(collideCapsuleCapsule, at(d, Vec3::Zero()), at(d, Vec3::Zero()));
  ASSERT_FALSE(same.empty());
  for (const ContactPoint& c : same) EXPECT_NEAR(c.depth, 0.4, kTol);
  // Collinear, overlapping end to end.
  auto collinear = run(collideCapsuleCapsule, at(d, Vec3::Zero()), at(d, Vec3(0, 0, 0.5)));
  ASSERT_FALSE(collinear.empty());
  // Zero-length capsules are spheres.
  auto spheres = run(collideCapsuleCapsule, at(point, Vec3::Zero()), at(point, Vec3(0.3, 0, 0)));
  ASSERT_EQ(spheres.size(), 1u);
  EXPECT_NEAR(spheres[0].depth, 0.1, kTol);
  expectVec(spheres[0].normal, Vec3::UnitX());
  auto mixed = run(collideCapsuleCapsule, at(point, Vec3::Zero()), at(d, Vec3::Zero()));
  ASSERT_EQ(mixed.size(), 1u);
  EXPECT_NEAR(mixed[0].depth, 0.4, kTol);
}

// --- round shapes against boxes ----------------------------------------------------------------

TEST(SphereBox, FaceEdgeVertexAndInside) {
  const ShapeDef ds = sphereDef(0.5), db = boxDef(Vec3(2.0, 1.0, 0.6));  // half (1, 0.5, 0.3)
  const Quat q = rotation(Vec3(1, 2, 3), 0.7);
  const Vec3 c(0.3, -0.2, 0.1);
  const ShapeInstance box = at(db, c, q);
  auto world = [&](const Vec3& local) { return Vec3(c + q * local); };
  // Over the +z face: distance 0.45, depth 0.05, normal from the sphere down into the box.
  auto face = run(collideSphereBox, at(ds, world(Vec3(0.2, 0.1, 0.75))), box);
  ASSERT_EQ(face.size(), 1u);
  EXPECT_NEAR(face[0].depth, 0.05, kTol);
  expectVec(face[0].normal, q * -Vec3::UnitZ());
  expectVec(face[0].point, world(Vec3(0.2, 0.1, 0.5 * (0.25 + 0.3))));
  // Beyond the edge x = 1, z = 0.3: offset (0.3, 0, 0.3), distance 0.3 sqrt 2.
  auto edge = run(collideSphereBox, at(ds, world(Vec3(1.3, 0.0, 0.6))), box);
  ASSERT_EQ(edge.size(), 1u);
  EXPECT_NEAR(edge[0].depth, 0.5 - 0.3 * std::sqrt(2.0), kTol);
  expectVec(edge[0].normal, q * Vec3(-1, 0, -1).normalized());
  // Beyond the vertex (1, 0.5, 0.3): offset (0.2, 0.2, 0.1), distance 0.3.
  auto vertex = run(collideSphereBox, at(ds, world(Vec3(1.2, 0.7, 0.4))), box);
  ASSERT_EQ(vertex.size(), 1u);
  EXPECT_NEAR(vertex[0].depth, 0.2, kTol);
  expectVec(vertex[0].normal, q * Vec3(-2, -2, -1) / 3.0);
  // Centre inside, nearest face -y at distance 0.1: depth r + 0.1, pushed out through -y.
  auto inside = run(collideSphereBox, at(ds, world(Vec3(0.5, -0.4, 0.0))), box);
  ASSERT_EQ(inside.size(), 1u);
  EXPECT_NEAR(inside[0].depth, 0.6, kTol);
  expectVec(inside[0].normal, q * Vec3::UnitY());  // sphere (a) leaves through -y: b along +y
  // Centre at the box centre: nearest face is z (half 0.3): depth 0.8, unit normal.
  auto centre = run(collideSphereBox, at(ds, c), box);
  ASSERT_EQ(centre.size(), 1u);
  EXPECT_NEAR(centre[0].depth, 0.8, kTol);
  EXPECT_NEAR(std::abs(centre[0].normal.dot(q * Vec3::UnitZ())), 1.0, kTol);
  // Speculative: gap 0.04 with margin 0.05 reported, none with margin 0.03.
  EXPECT_EQ(run(collideSphereBox, at(ds, world(Vec3(0, 0, 0.84))), box, 0.05).size(), 1u);
  EXPECT_TRUE(run(collideSphereBox, at(ds, world(Vec3(0, 0, 0.84))), box, 0.03).empty());
}

TEST(CapsuleBox, LyingFlatOnAFaceGivesTwoPoints) {
  const ShapeDef dc = capsuleDef(0.2, 1.0), db = boxDef(Vec3(2.0, 2.0, 1.0));
  const Quat along_x = rotation(Vec3::UnitY(), kPi / 2);
  const ShapeInstance box = at(db, Vec3::Zero());
  const auto pts = run(collideCapsuleBox, at(dc, Vec3(0.1, 0.2, 0.69), along_x), box);
  ASSERT_EQ(pts.size(), 2u);
  for (const ContactPoint& c : pts) {
    EXPECT_NEAR(c.depth, 0.01, kTol);
    expectVec(c.normal, -Vec3::UnitZ());  // capsule (a) above the box (b)
    EXPECT_NEAR(c.point.z(), 0.5 * (0.49 + 0.5), kTol);
  }
  EXPECT_NEAR(std::min(pts[0].point.x(), pts[1].point.x()), -0.4, kTol);
  EXPECT_NEAR(std::max(pts[0].point.x(), pts[1].point.x()), 0.6, kTol);
  const auto moved =
      run(collideCapsuleBox, at(dc, Vec3(0.1 + 2e-5, 0.2 - 1e-5, 0.69), along_x), box);
  EXPECT_EQ(features(moved), features(pts));
  // Hanging over the edge x = 1: clipped to the face, the point at x = 1.
  const auto over = run(collideCapsuleBox, at(dc, Vec3(0.8, 0.0, 0.69), along_x), box);
  ASSERT_EQ(over.size(), 2u);
  EXPECT_NEAR(std::max(over[0].point.x(), over[1].point.x()), 1.0, kTol);
  // Resting on the face slightly penetrating (core above the face): still two points.
  const auto deep = run(collideCapsuleBox, at(dc, Vec3(0.0, 0.0, 0.55), along_x), box);
  ASSERT_EQ(deep.size(), 2u);
  for (const ContactPoint& c : deep) EXPECT_NEAR(c.depth, 0.15, kTol);
}

TEST(CapsuleBox, TiltedEndAndEdgeClosedForms) {
  const ShapeDef dc = capsuleDef(0.2, 1.0), db = boxDef(Vec3(2.0, 2.0, 1.0));
  const ShapeInstance box = at(db, Vec3::Zero());
  // Tilted 30 degrees from vertical, lower end 0.15 above the face: one point, depth 0.05.
  const double tilt = kPi / 6;
  const Quat q = rotation(Vec3::UnitY(), tilt);
  const Vec3 centre(0.0, 0.0, 0.5 + 0.15 + 0.5 * std::cos(tilt));
  const auto end = run(collideCapsuleBox, at(dc, centre, q), box, 0.01);
  ASSERT_EQ(end.size(), 1u);
  EXPECT_NEAR(end[0].depth, 0.05, kTol);
  expectVec(end[0].normal, -Vec3::UnitZ());
  // Vertical capsule poking into the face by 0.1: core inside, depth r + 0.1.
  const auto poke = run(collideCapsuleBox, at(dc, Vec3(0.3, 0.3, 0.4 + 0.5)), box);
  ASSERT_EQ(poke.size(), 1u);
  EXPECT_NEAR(poke[0].depth, 0.3, kTol);
  expectVec(poke[0].normal, -Vec3::UnitZ());
  // Along y beside the box edge (x = 1, z = 0.5), core offset (0.1, 0.1): depth r - 0.1 sqrt 2.
  const auto edge =
      run(collideCapsuleBox, at(dc, Vec3(1.1, 0.0, 0.6), rotation(Vec3::UnitX(), kPi / 2)), box);
  ASSERT_EQ(edge.size(), 1u);
  EXPECT_NEAR(edge[0].depth, 0.2 - 0.1 * std::sqrt(2.0), kTol);
  expectVec(edge[0].normal, Vec3(-1, 0, -1).normalized());
  // Swapping is the dispatcher's job; here: speculative points only within the margin.
  EXPECT_TRUE(
      run(collideCapsuleBox, at(dc, Vec3(0, 0, 0.75), rotation(Vec3::UnitY(), kPi / 2)), box, 0.04)
          .empty());
  EXPECT_EQ(
      run(collideCapsuleBox, at(dc, Vec3(0, 0, 0.75), rotation(Vec3::UnitY(), kPi / 2)), box, 0.06)
          .size(),
      2u);
  // Zero-length capsule: a sphere.
  const ShapeDef point = capsuleDef(0.2, 0.0);
  const auto sphere = run(collideCapsuleBox, at(point, Vec3(0, 0, 0.65)), box);
  ASSERT_EQ(sphere.size(), 1u);
  EXPECT_NEAR(sphere[0].depth, 0.05, kTol);
}

// --- box against box ---------------------------------------------------------------------------

TEST(BoxBox, RestingBoxGivesFourStablePoints) {
  const ShapeDef ground = boxDef(Vec3(4.0, 4.0, 1.0)), cube = boxDef(Vec3(1.0, 1.0, 1.0));
  const ShapeInstance a = at(ground, Vec3(0, 0, -0.5));
  const Quat yaw = rotation(Vec3::UnitZ(), 0.3);
  const auto pts = run(collideBoxBox, a, at(cube, Vec3(0.2, -0.1, 0.49), yaw));
  ASSERT_EQ(pts.size(), 4u);
  for (const ContactPoint& c : pts) {
    EXPECT_NEAR(c.depth, 0.01, kTol);
    expectVec(c.normal, Vec3::UnitZ());
    EXPECT_NEAR(c.point.z(), -0.005, kTol);
  }
  // The points are the cube's bottom corners (midway in z).
  for (int sx : {-1, 1}) {
    for (int sy : {-1, 1}) {
      const Vec3 corner = Vec3(0.2, -0.1, -0.005) + yaw * Vec3(0.5 * sx, 0.5 * sy, 0.0);
      const bool found = std::any_of(pts.begin(), pts.end(), [&](const ContactPoint& c) {
        return (c.point - corner).norm() < 1e-12;
      });
      EXPECT_TRUE(found) << corner.transpose();
    }
  }
  // Same ids after a tiny translation.
  const auto moved = run(collideBoxBox, a, at(cube, Vec3(0.2 + 1e-4, -0.1 - 3e-5, 0.4899), yaw));
  ASSERT_EQ(moved.size(), 4u);
  EXPECT_EQ(features(moved), features(pts));
  // Distinct ids.
  auto ids = features(pts);
  EXPECT_EQ(std::unique(ids.begin(), ids.end()), ids.end());
  // Swapped: same points with the normal turned around.
  expectSwapSymmetric(collideBoxBox, a, at(cube, Vec3(0.2, -0.1, 0.49), yaw), 0.0, 1e-6);
}

TEST(BoxBox, EqualBoxesStackedGiveFourPoints) {
  const ShapeDef cube = boxDef(Vec3(1.0, 1.0, 1.0));
  const ShapeInstance a = at(cube, Vec3::Zero());
  const auto pts = run(collideBoxBox, a, at(cube, Vec3(0.0, 0.0, 1.0)), 0.01);
  ASSERT_EQ(pts.size(), 4u);
  for (const ContactPoint& c : pts) EXPECT_NEAR(c.depth, 0.0, kTol);
  // Shifted by half a width: the overlap is the rectangle [0, 0.5] x [-0.5, 0.5].
  const auto half = run(collideBoxBox, a, at(cube, Vec3(0.5, 0.0, 0.99)));
  ASSERT_EQ(half.size(), 4u);
  for (const ContactPoint& c : half) {
    EXPECT_NEAR(c.depth, 0.01, kTol);
    // Within the overlap, up to the clipping allowance (1e-6 of the half extent).
    EXPECT_GE(c.point.x(), -1e-6);
    EXPECT_LE(c.point.x(), 0.5 + 1e-6);
  }
  const auto half_moved = run(collideBoxBox, a, at(cube, Vec3(0.5 + 1e-5, 1e-7, 0.99 - 1e-7)));
  EXPECT_EQ(features(half_moved), features(half));
}

TEST(BoxBox, SpeculativeGapWithinMarginOnly) {
  const ShapeDef cube = boxDef(Vec3(1.0, 1.0, 1.0));
  const ShapeInstance a = at(cube, Vec3::Zero());
  const ShapeInstance b = at(cube, Vec3(0.1, 0.2, 1.03), rotation(Vec3::UnitZ(), 0.5));
  const auto near = run(collideBoxBox, a, b, 0.05);
  ASSERT_GE(near.size(), 3u);
  for (const ContactPoint& c : near) EXPECT_NEAR(c.depth, -0.03, kTol);
  EXPECT_TRUE(run(collideBoxBox, a, b, 0.03).empty());
  EXPECT_TRUE(run(collideBoxBox, a, b, 0.02).empty());
}

TEST(BoxBox, RotatedEdgeEdgeDepthIsAnalytic) {
  // Unit cubes: a turned 45 degrees about x (top edge along x at z = sqrt(2)/2), b turned 45
  // degrees about y (bottom edge along y at z = c - sqrt(2)/2). They cross over the z axis with
  // depth sqrt(2) - c and normal +z.
  const ShapeDef cube = boxDef(Vec3(1.0, 1.0, 1.0));
  const double c = std::sqrt(2.0) - 0.02;
  const ShapeInstance a = at(cube, Vec3::Zero(), rotation(Vec3::UnitX(), kPi / 4));
  const ShapeInstance b = at(cube, Vec3(0.0, 0.0, c), rotation(Vec3::UnitY(), kPi / 4));
  const auto pts = run(collideBoxBox, a, b);
  ASSERT_EQ(pts.size(), 1u);
  EXPECT_NEAR(pts[0].depth, 0.02, kTol);
  expectVec(pts[0].normal, Vec3::UnitZ());
  expectVec(pts[0].point, Vec3(0.0, 0.0, 0.5 * std::sqrt(2.0) - 0.01));
  expectSwapSymmetric(collideBoxBox, a, b, 0.0);
  // Shifted sideways along both edges: the same depth, the point follows the crossing.
  const auto shifted =
      run(collideBoxBox, at(cube, Vec3(0.1, 0.0, 0.0), rotation(Vec3::UnitX(), kPi / 4)),
          at(cube, Vec3(0.0, 0.2, c), rotation(Vec3::UnitY(), kPi / 4)));
  ASSERT_EQ(shifted.size(), 1u);
  EXPECT_NEAR(shifted[0].depth, 0.02, kTol);
  expectVec(shifted[0].point, Vec3(0.0, 0.0, 0.5 * std::sqrt(2.0) - 0.01));
  EXPECT_EQ(shifted[0].feature, pts[0].feature);
}

TEST(BoxBox, CoincidentBoxesStayFinite) {
  const ShapeDef box = boxDef(Vec3(1.0, 2.0, 3.0));
  const auto pts = run(collideBoxBox, at(box, Vec3::Zero()), at(box, Vec3::Zero()));
  ASSERT_FALSE(pts.empty());
  EXPECT_NEAR(maxDepth(pts), 1.0, kTol);  // out through the thinnest pair of faces (x)
}

// Brute-force penetration depth: the minimum over unit directions n of h_a(n) + h_b(-n) (the
// distance b must move along n to clear a), sampled on a Fibonacci sphere, then refined by a
// random local search with a shrinking step. An upper bound that converges to the exact depth.
constexpr double kBruteTol = 1e-5;  // how far above the minimum the brute force may stop (m)

template <class SupportA, class SupportB>
double bruteForceDepth(SupportA ha, SupportB hb, std::mt19937& rng) {
  auto overlap = [&](const Vec3& n) { return ha(n) + hb(Vec3(-n)); };
  // Fibonacci sphere: near-uniform directions ~0.025 rad apart.
  const int samples = 20000;
  const double golden = kPi * (3.0 - std::sqrt(5.0));
  std::vector<std::pair<double, Vec3>> grid;
  for (int k = 0; k < samples; ++k) {
    const double z = 1.0 - 2.0 * (k + 0.5) / samples;
    const double rho = std::sqrt(1.0 - z * z);
    const Vec3 n(rho * std::cos(golden * k), rho * std::sin(golden * k), z);
    grid.emplace_back(overlap(n), n);
  }
  std::sort(grid.begin(), grid.end(),
            [](const auto& x, const auto& y) { return x.first < y.first; });
  // Refine from the best samples of up to 12 distinct basins (starts over 0.1 rad apart).
  std::vector<Vec3> starts;
  for (const auto& [value, n] : grid) {
    if (starts.size() >= 12) break;
    if (std::none_of(starts.begin(), starts.end(),
                     [&](const Vec3& m) { return (m - n).norm() < 0.1; })) {
      starts.push_back(n);
    }
  }
  std::normal_distribution<double> gauss(0.0, 1.0);
  double result = kInfinity;
  for (Vec3 best : starts) {
    double best_value = overlap(best);
    double step = 0.03;
    int failures = 0;
    while (step > 1e-10) {
      const Vec3 trial = (best + step * Vec3(gauss(rng), gauss(rng), gauss(rng))).normalized();
      const double v = overlap(trial);
      if (v < best_value) {
        best_value = v;
        best = trial;
        failures = 0;
      } else if (++failures > 100) {
        step *= 0.5;
        failures = 0;
      }
    }
    result = std::min(result, best_value);
  }
  return result;
}

double boxSupport(const ShapeInstance& s, const Vec3& n) {
  const Vec3 local = s.pose.orientation.conjugate() * n;
  return n.dot(s.pose.position) + (0.5 * s.def->size).dot(local.cwiseAbs());
}

Quat randomRotation(std::mt19937& rng) {
  std::normal_distribution<double> gauss(0.0, 1.0);
  return Quat(gauss(rng), gauss(rng), gauss(rng), gauss(rng)).normalized();
}

TEST(BoxBox, RandomRotationsMatchBruteForceDepth) {
  std::mt19937 rng(20261122);
  std::uniform_real_distribution<double> size(0.3, 2.0), unit(-1.0, 1.0);
  int checked = 0, deepest_kept = 0;
  for (int trial = 0; trial < 300 && checked < 120; ++trial) {
    const ShapeDef da = boxDef(Vec3(size(rng), size(rng), size(rng)));
    const ShapeDef db = boxDef(Vec3(size(rng), size(rng), size(rng)));
    const ShapeInstance a = at(da, Vec3::Zero(), randomRotation(rng));
    const ShapeInstance b = at(db, Vec3(unit(rng), unit(rng), unit(rng)), randomRotation(rng));
    const double truth = bruteForceDepth([&](const Vec3& n) { return boxSupport(a, n); },
                                         [&](const Vec3& n) { return boxSupport(b, n); }, rng);
    std::vector<ContactPoint> out;
    collideBoxBox(a, b, 0.0, out);
    const double bias = 1e-3 * (da.size.sum() + db.size.sum()) / 12.0;  // mean half extent
    if (!(truth > 1e-3)) {
      // Apart (or barely touching): no point may claim more than the true overlap.
      for (const ContactPoint& c : out) EXPECT_LE(c.depth, std::max(truth, 0.0) + bias + 1e-9);
      continue;
    }
    ++checked;
    ASSERT_FALSE(out.empty()) << "trial " << trial;
    // The depth of the pair is the overlap along the chosen normal, h_a(n) + h_b(-n). The axis
    // bias may pick a face up to 1e-3 x the mean half extent more penetrating than the exact
    // minimum, never less (the brute force bounds the minimum from above, converged to within
    // kBruteTol).
    const Vec3 n = out[0].normal;
    const double along = boxSupport(a, n) + boxSupport(b, -n);
    EXPECT_GE(along, truth - kBruteTol) << "trial " << trial;
    EXPECT_LE(along, truth + bias + 1e-9) << "trial " << trial;
    // The points share the normal and none is deeper than that overlap; the deepest is that
    // overlap unless clipping to the reference face cut the deepest corner away.
    for (const ContactPoint& c : out) expectVec(c.normal, n);
    EXPECT_LE(maxDepth(out), along + 1e-9) << "trial " << trial;
    if (maxDepth(out) > along - 1e-9) ++deepest_kept;
  }
  std::printf("box-box: deepest corner kept in %d of %d overlapping placements\n", deepest_kept,
              checked);
  EXPECT_GE(checked, 100);
}

double capsuleSupport(const ShapeInstance& s, const Vec3& n) {
  const Vec3 half = s.pose.orientation * Vec3(0, 0, 0.5 * s.def->length);
  return n.dot(s.pose.position) + std::abs(n.dot(half)) + s.def->radius;
}

TEST(CapsuleBox, RandomRotationsMatchBruteForceDepth) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> size(0.3, 2.0), unit(-1.0, 1.0), radius(0.05, 0.5);
  int checked = 0;
  for (int trial = 0; trial < 300 && checked < 100; ++trial) {
    const ShapeDef dc = capsuleDef(radius(rng), size(rng));
    const ShapeDef db = boxDef(Vec3(size(rng), size(rng), size(rng)));
    const ShapeInstance a = at(dc, Vec3(unit(rng), unit(rng), unit(rng)), randomRotation(rng));
    const ShapeInstance b = at(db, Vec3::Zero(), randomRotation(rng));
    const double truth = bruteForceDepth([&](const Vec3& n) { return capsuleSupport(a, n); },
                                         [&](const Vec3& n) { return boxSupport(b, n); }, rng);
    const auto out = run(collideCapsuleBox, a, b, 0.5);
    if (truth <= -0.5 + 1e-6) {
      EXPECT_TRUE(out.empty()) << "trial " << trial;
      continue;
    }
    ++checked;
    ASSERT_FALSE(out.empty()) << "trial " << trial;
    // Exact: the separated case is the true distance, the overlapping one a separating axis
    // test (with a face bias of 1e-3 x (mean half extent + radius)).
    const double bias = 1e-3 * (db.size.sum() / 6.0 + dc.radius);
    EXPECT_LE(maxDepth(out), truth + bias + 1e-9) << "trial " << trial;
    EXPECT_GE(maxDepth(out), truth - kBruteTol) << "trial " << trial;
  }
  EXPECT_GE(checked, 80);
}

// --- planes ------------------------------------------------------------------------------------

// A tilted plane: local normal +x with offset 0.3, posed so that its world normal is n and it
// passes through origin + 0.3 n (+ the pose position along n).
struct TiltedPlane {
  ShapeDef def = planeDef(Vec3::UnitX(), 0.3);
  Quat q = rotation(Vec3(0.3, -1.0, 0.2), 1.1);
  Vec3 position = Vec3(0.1, 0.2, -0.4);
  Vec3 normal() const { return q * Vec3::UnitX(); }
  double offset() const { return 0.3 + normal().dot(position); }  // world: n.x = offset
  ShapeInstance instance() const { return at(def, position, q); }
};

TEST(Plane, SphereAndCapsule) {
  const TiltedPlane plane;
  const Vec3 n = plane.normal();
  const ShapeDef ds = sphereDef(0.4);
  const Vec3 c = Vec3(1, 2, 3) - n.dot(Vec3(1, 2, 3)) * n + (plane.offset() + 0.35) * n;
  const auto s = run(collidePlane, plane.instance(), at(ds, c));
  ASSERT_EQ(s.size(), 1u);
  EXPECT_NEAR(s[0].depth, 0.05, kTol);
  expectVec(s[0].normal, n);
  EXPECT_NEAR(n.dot(s[0].point) - plane.offset(), -0.025, kTol);  // midway
  // A capsule lying on the plane (axis across n), its core 0.15 above: both ends, depth 0.05.
  const ShapeDef dc = capsuleDef(0.2, 1.5);
  const Vec3 across = n.cross(Vec3::UnitZ()).normalized();
  const Quat lying = Quat::FromTwoVectors(Vec3::UnitZ(), across);
  const auto cap = run(collidePlane, plane.instance(), at(dc, c - 0.2 * n, lying));
  ASSERT_EQ(cap.size(), 2u);
  for (const ContactPoint& p : cap) {
    EXPECT_NEAR(p.depth, 0.05, kTol);
    expectVec(p.normal, n);
  }
  EXPECT_NEAR((cap[0].point - cap[1].point).norm(), 1.5, kTol);
  // Beyond the margin: nothing.
  EXPECT_TRUE(run(collidePlane, plane.instance(), at(ds, c + 0.1 * n), 0.04).empty());
  EXPECT_EQ(run(collidePlane, plane.instance(), at(ds, c + 0.1 * n), 0.06).size(), 1u);
}

TEST(Plane, BoxCornerDepths) {
  const TiltedPlane plane;
  const Vec3 n = plane.normal();
  const ShapeDef db = boxDef(Vec3(0.8, 0.5, 0.3));
  const Vec3 h = 0.5 * db.size;
  std::mt19937 rng(3);
  for (int trial = 0; trial < 50; ++trial) {
    const Quat q = randomRotation(rng);
    // Corner v (bits: + side on x, y, z) in the world, for the box centred at the origin.
    auto corner = [&](std::uint32_t v) {
      return Vec3(
          q * Vec3((v & 1) ? h.x() : -h.x(), (v & 2) ? h.y() : -h.y(), (v & 4) ? h.z() : -h.z()));
    };
    double lowest = kInfinity;
    for (std::uint32_t v = 0; v < 8; ++v) lowest = std::min(lowest, n.dot(corner(v)));
    // Place the box so that its lowest corner is 0.02 deep.
    const Vec3 centre = (plane.offset() - lowest - 0.02) * n;
    const double margin = 0.15;
    int within = 0;
    for (std::uint32_t v = 0; v < 8; ++v) {
      within += plane.offset() - n.dot(centre + corner(v)) > -margin ? 1 : 0;
    }
    const auto pts = run(collidePlane, plane.instance(), at(db, centre, q), margin);
    EXPECT_EQ(static_cast<int>(pts.size()), std::min(within, 4));
    EXPECT_NEAR(maxDepth(pts), 0.02, kTol);
    for (const ContactPoint& p : pts) {
      ASSERT_LT(p.feature, 8u);
      const double depth = plane.offset() - n.dot(centre + corner(p.feature));
      EXPECT_NEAR(p.depth, depth, kTol);
      expectVec(p.point, centre + corner(p.feature) + 0.5 * depth * n);
      expectVec(p.normal, n);
    }
  }
  // Resting flat: the four bottom corners at the same depth, with stable ids.
  const Quat flat = Quat::FromTwoVectors(Vec3::UnitZ(), n);
  const Vec3 centre = (plane.offset() + h.z() - 0.01) * n;
  const auto pts = run(collidePlane, plane.instance(), at(db, centre, flat));
  ASSERT_EQ(pts.size(), 4u);
  for (const ContactPoint& p : pts) EXPECT_NEAR(p.depth, 0.01, kTol);
  const auto moved =
      run(collidePlane, plane.instance(), at(db, centre + 1e-4 * Vec3(1, 1, 1).cross(n), flat));
  EXPECT_EQ(features(moved), features(pts));
}

TEST(Plane, CylinderStandingLyingAndTilted) {
  const ShapeDef plane_def = planeDef(Vec3::UnitZ(), 0.0);
  const ShapeInstance ground = at(plane_def, Vec3::Zero());
  const ShapeDef dc = cylinderDef(0.3, 1.0);
  // Standing on its face, 0.01 deep: four rim points of the bottom cap.
  const Quat yaw = rotation(Vec3::UnitZ(), 0.4);
  const auto standing = run(collidePlane, ground, at(dc, Vec3(1, 2, 0.49), yaw), 0.05);
  ASSERT_EQ(standing.size(), 4u);
  for (const ContactPoint& p : standing) {
    EXPECT_NEAR(p.depth, 0.01, kTol);
    expectVec(p.normal, Vec3::UnitZ());
    EXPECT_NEAR((p.point - Vec3(1, 2, p.point.z())).norm(), 0.3, kTol);
  }
  const auto moved = run(collidePlane, ground, at(dc, Vec3(1 + 1e-4, 2, 0.49), yaw), 0.05);
  EXPECT_EQ(features(moved), features(standing));
  // Lying on its side (axis along y after a turn about x), 0.01 deep: two points along the line
  // of contact, one at each cap.
  const Quat side = rotation(Vec3(1, 0, 0), kPi / 2) * rotation(Vec3::UnitZ(), 0.3);
  const auto lying = run(collidePlane, ground, at(dc, Vec3(0, 0, 0.29), side), 0.05);
  ASSERT_EQ(lying.size(), 2u);
  for (const ContactPoint& p : lying) {
    EXPECT_NEAR(p.depth, 0.01, kTol);
    EXPECT_NEAR(p.point.x(), 0.0, kTol);
    EXPECT_NEAR(std::abs(p.point.y()), 0.5, kTol);
  }
  // Tilted by 0.5 rad on its rim: depth = L/2 cos t + r sin t - centre height.
  for (const double t : {0.5, 1e-3, 1.2}) {
    const Quat tilt = rotation(Vec3(1, 1, 0), t) * yaw;
    const double reach = 0.5 * std::cos(t) + 0.3 * std::sin(t);
    const auto pts = run(collidePlane, ground, at(dc, Vec3(0, 0, reach - 0.02), tilt), 0.01);
    ASSERT_GE(pts.size(), 1u) << t;
    EXPECT_NEAR(maxDepth(pts), 0.02, 1e-9) << t;
  }
}

TEST(Plane, ZeroLengthShapesStayFinite) {
  const ShapeDef plane_def = planeDef(Vec3::UnitZ(), 0.0);
  const ShapeInstance ground = at(plane_def, Vec3::Zero());
  const ShapeDef flat_cylinder = cylinderDef(0.3, 0.0), point_capsule = capsuleDef(0.2, 0.0);
  EXPECT_EQ(run(collidePlane, ground, at(flat_cylinder, Vec3::Zero()), 0.01).size(), 4u);
  EXPECT_EQ(run(collidePlane, ground, at(point_capsule, Vec3(0, 0, 0.1))).size(), 1u);
}

// Placements on a coarse grid with right-angle turns hit the degenerate cases (coincident
// centres, cores on faces and edges, parallel axes and edges, zero sizes): every routine must
// still give finite points, unit normals, at most 4 points, and the same output when called
// again.
TEST(Degenerate, GridPlacementsStayFiniteAndDeterministic) {
  std::mt19937 rng(11);
  std::uniform_int_distribution<int> cell(-4, 4), pick(0, 3);
  const std::array<double, 4> lengths{0.0, 0.5, 1.0, 2.0};
  auto turn = [&]() {
    switch (pick(rng)) {
      case 0:
        return Quat::Identity();
      case 1:
        return rotation(Vec3::UnitX(), kPi / 2);
      case 2:
        return rotation(Vec3(1, 1, 0), kPi / 2);
      default:
        return randomRotation(rng);
    }
  };
  auto spot = [&]() { return Vec3(0.25 * cell(rng), 0.25 * cell(rng), 0.25 * cell(rng)); };
  const ShapeDef plane = planeDef(Vec3::UnitZ(), 0.0);
  for (int trial = 0; trial < 2000; ++trial) {
    const ShapeDef sphere = sphereDef(lengths[pick(rng)]);
    const ShapeDef capsule = capsuleDef(lengths[pick(rng)], lengths[pick(rng)]);
    const ShapeDef capsule2 = capsuleDef(lengths[pick(rng)], lengths[pick(rng)]);
    const ShapeDef box = boxDef(Vec3(lengths[pick(rng)], lengths[pick(rng)], lengths[pick(rng)]));
    const ShapeDef box2 = boxDef(Vec3(lengths[pick(rng)], lengths[pick(rng)], lengths[pick(rng)]));
    const ShapeDef cylinder = cylinderDef(lengths[pick(rng)], lengths[pick(rng)]);
    const ShapeInstance s = at(sphere, spot(), turn()), c = at(capsule, spot(), turn());
    const ShapeInstance c2 = at(capsule2, spot(), turn()), b = at(box, spot(), turn());
    const ShapeInstance b2 = at(box2, spot(), turn()), y = at(cylinder, spot(), turn());
    const ShapeInstance p = at(plane, spot(), turn());
    const std::vector<std::tuple<Routine, ShapeInstance, ShapeInstance>> pairs{
        {collideSphereSphere, s, s},   {collideSphereCapsule, s, c}, {collideCapsuleCapsule, c, c2},
        {collideCapsuleCapsule, c, c}, {collideSphereBox, s, b},     {collideCapsuleBox, c, b},
        {collideBoxBox, b, b2},        {collideBoxBox, b, b},        {collidePlane, p, s},
        {collidePlane, p, c},          {collidePlane, p, b},         {collidePlane, p, y}};
    for (const auto& [f, x, z] : pairs) {
      const auto first = run(f, x, z, 0.1);
      const auto again = run(f, x, z, 0.1);
      ASSERT_EQ(first.size(), again.size());
      for (std::size_t k = 0; k < first.size(); ++k) {
        EXPECT_EQ(first[k].feature, again[k].feature);
        EXPECT_EQ(first[k].depth, again[k].depth);
      }
    }
  }
}

}  // namespace
}  // namespace linx::collision

// Found by fuzz_state (UBSan: an index of -1 in reduceManifold): contact points of a state that
// overflowed, non-finite, compare with nothing. The reduction keeps one and reads nothing outside
// the points; the step's checks then name the state.
TEST(ManifoldReduction, NonFinitePointsKeepOneAndReadNothingOutside) {
  using linx::collision::ContactPoint;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  for (const double bad : {nan, inf}) {
    std::vector<ContactPoint> points(1);  // a point of an earlier pair, kept as it is
    points[0].depth = 0.5;
    for (int k = 0; k < 5; ++k) {
      ContactPoint p;
      p.point = linx::Vec3(bad, k, 0);
      p.depth = bad;
      points.push_back(p);
    }
    linx::collision::reduceManifold(points, 1, linx::Vec3::UnitZ());
    ASSERT_EQ(points.size(), 2u) << bad;
    EXPECT_EQ(points[0].depth, 0.5);
  }
}
