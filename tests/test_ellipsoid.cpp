// Ellipsoids against independent truths: the mass and inertia of the closed form agree with a
// numerical integration over the solid; the support point lies on the surface with its normal
// along the direction; the bounding box is the surface's extent; at rest on a plane or a box the
// centre sits one semi-axis above the surface (to the slop); contacts and a scene file, an MJCF
// geom and the pictures take it.
#include "support.hpp"

#include <linx/import.hpp>
#include <linx/mass_properties.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <numbers>
#include <random>

#include "collision/aabb.hpp"
#include "collision/gjk_epa.hpp"
#include "collision/narrowphase.hpp"
#include "viz/tessellate.hpp"

namespace linx {
namespace {

constexpr double kPi = std::numbers::pi;

ShapeDef ellipsoid(const Vec3& radii) {
  ShapeDef s;
  s.type = ShapeType::Ellipsoid;
  s.radii = radii;
  return s;
}

// Midpoint sampling of the solid on a regular grid: a check that shares no formula with the
// library's closed form.
TEST(Ellipsoid, MassAndInertiaAreTheSolidsIntegral) {
  const Vec3 r(0.3, 0.2, 0.1);
  const double density = 500.0;
  const MassProperties p = shapeMassProperties(ellipsoid(r), density);
  const int n = 160;
  const Vec3 step = 2.0 * r / n;
  const double dv = step.prod();
  double mass = 0.0;
  Mat3 inertia = Mat3::Zero();
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      for (int k = 0; k < n; ++k) {
        const Vec3 x = -r + step.cwiseProduct(Vec3(i + 0.5, j + 0.5, k + 0.5));
        if (x.cwiseQuotient(r).squaredNorm() > 1.0) continue;
        mass += density * dv;
        inertia += density * dv * (x.squaredNorm() * Mat3::Identity() - x * x.transpose());
      }
  EXPECT_NEAR(p.mass, density * 4.0 / 3.0 * kPi * r.prod(), 1e-12);
  EXPECT_NEAR(mass / p.mass, 1.0, 2e-3);
  for (int a = 0; a < 3; ++a) EXPECT_NEAR(inertia(a, a) / p.inertia(a, a), 1.0, 3e-3) << a;
  EXPECT_LT(p.inertia.norm() - p.inertia.diagonal().norm(), 1e-15);  // principal in its frame
}

// The support point in any direction is on the surface, and the surface's normal there points
// along the direction (the definition of the support mapping of a smooth convex body).
TEST(Ellipsoid, SupportPointIsOnTheSurfaceWithItsNormalAlongTheDirection) {
  const ShapeDef s = ellipsoid(Vec3(0.5, 0.2, 0.05));
  collision::ShapeInstance placed{&s, nullptr, Pose{Vec3(1, -2, 3), Quat(0.9, 0.1, -0.3, 0.2)}};
  placed.pose.orientation.normalize();
  const collision::ConvexSupport support = collision::makeSupport(placed);
  const Mat3 R = placed.pose.orientation.toRotationMatrix();
  std::mt19937 rng(7);
  std::normal_distribution<double> gauss;
  for (int trial = 0; trial < 200; ++trial) {
    const Vec3 d(gauss(rng), gauss(rng), gauss(rng));
    const Vec3 local = R.transpose() * (support.support(d) - placed.pose.position);
    EXPECT_NEAR(local.cwiseQuotient(s.radii).squaredNorm(), 1.0, 1e-12);
    const Vec3 normal = R * local.cwiseQuotient(s.radii.cwiseProduct(s.radii)).normalized();
    EXPECT_LT((normal - d.normalized()).norm(), 1e-12);
  }
}

// The bounding box is the surface's extent: every tessellated surface point inside it, and each
// face touched by the support point along its axis.
TEST(Ellipsoid, BoundingBoxIsTheSurfacesExtent) {
  const ShapeDef s = ellipsoid(Vec3(0.5, 0.2, 0.05));
  Pose pose{Vec3(1, 2, 3), Quat(0.8, 0.3, 0.1, -0.4).normalized()};
  const collision::Aabb box = collision::shapeAabb(s, pose);
  const viz::Surface surface = viz::tessellate(s);
  for (const Vec3& p : surface.points) {
    const Vec3 world = pose.toWorld(p);
    EXPECT_TRUE((world.array() >= box.min.array() - 1e-12).all());
    EXPECT_TRUE((world.array() <= box.max.array() + 1e-12).all());
  }
  collision::ShapeInstance placed{&s, nullptr, pose};
  const collision::ConvexSupport support = collision::makeSupport(placed);
  for (int a = 0; a < 3; ++a) {
    EXPECT_NEAR(support.support(Vec3::Unit(a))[a], box.max[a], 1e-12);
    EXPECT_NEAR(support.support(-Vec3::Unit(a))[a], box.min[a], 1e-12);
  }
}

// Dropped flat onto the ground (a plane) and onto a static box, an ellipsoid comes to rest with
// its centre its vertical semi-axis above the surface, less at most the slop, and its turn kept.
TEST(Ellipsoid, RestsOneSemiAxisAboveAPlaneAndABox) {
  for (const bool on_box : {false, true}) {
    SCOPED_TRACE(on_box ? "box" : "plane");
    World world;
    if (on_box) {
      BodyDef table = test::boxBody("table", 1.0, Vec3(2, 2, 0.5), Vec3(0, 0, -0.25));
      table.is_static = true;
      world.createBody(table);  // top face at z = 0
    } else {
      world.createBody(test::groundPlane());
    }
    BodyDef egg;
    egg.name = "egg";
    egg.position = Vec3(0.1, -0.05, 0.12);
    egg.orientation = Quat(Eigen::AngleAxisd(0.7, Vec3::UnitZ()));
    ShapeDef shape = ellipsoid(Vec3(0.3, 0.2, 0.1));
    shape.density = 800.0;
    egg.shapes.push_back(shape);
    const BodyId id = world.createBody(egg);
    for (int i = 0; i < 2000; ++i) world.step();
    const Body& b = world.body(id);
    const double slop = world.settings().contact.slop;
    EXPECT_NEAR(b.position().z(), 0.1 - 0.5 * slop, 0.5 * slop + 1e-4);
    EXPECT_LT(b.linearVelocity().norm(), 1e-3);
    const Vec3 up = b.orientation() * Vec3::UnitZ();
    EXPECT_GT(up.z(), 1.0 - 1e-6);  // still flat
  }
}

// Two ellipsoids touching end to end (GJK and EPA on two smooth bodies): one contact at the
// depth of their overlap along the line of their long axes, its normal along it to EPA's
// tolerance on a curved surface (6e-5 rad at 2 cm overlap).
TEST(Ellipsoid, OverlapAlongTheLongAxesIsTheExactDepth) {
  const ShapeDef s = ellipsoid(Vec3(0.5, 0.2, 0.1));
  for (const double gap : {0.01, -0.02}) {
    const collision::ShapeInstance a{&s, nullptr, Pose{}};
    const collision::ShapeInstance b{&s, nullptr, Pose{Vec3(1.0 + gap, 0, 0), Quat::Identity()}};
    std::vector<collision::ContactPoint> out;
    ASSERT_EQ(collision::collide(a, b, 0.05, out), 1);
    EXPECT_NEAR(out[0].depth, -gap, 1e-6);
    EXPECT_LT((out[0].normal - Vec3::UnitX()).norm(), 1e-4);
    EXPECT_NEAR(out[0].point.x(), 0.5 + 0.5 * gap, 1e-6);
  }
}

// A scene file and an MJCF geom both make one, with MuJoCo's size (three semi-axes).
TEST(Ellipsoid, SceneFilesAndMjcfGeomsTakeIt) {
  const Scene scene = parseScene(R"({"bodies": [{"name": "e", "shapes": [
      {"type": "ellipsoid", "radii": [0.3, 0.2, 0.1], "density": 1000}]}]})",
                                 "e.json");
  ASSERT_EQ(scene.bodies[0].shapes[0].type, ShapeType::Ellipsoid);
  EXPECT_NEAR(*scene.bodies[0].mass, 1000.0 * 4.0 / 3.0 * kPi * 0.006, 1e-12);
  EXPECT_EQ(writeSceneJson(parseScene(writeSceneJson(scene), "w.json")), writeSceneJson(scene));
  try {
    parseScene(R"({"bodies": [{"name": "e", "mass": 1, "shapes": [
        {"type": "ellipsoid", "radii": [0.3, 0, 0.1]}]}]})",
               "e.json");
    ADD_FAILURE() << "a zero semi-axis accepted";
  } catch (const SceneError& e) {
    EXPECT_EQ(e.field(), "bodies[0].shapes[0].radii[1]");
  }
  const test::TempFolder folder("linx_ellipsoid_mjcf");
  const auto path = folder.write("egg.xml", R"(<mujoco><worldbody><body name="egg">
      <freejoint/><geom type="ellipsoid" size="0.3 0.2 0.1" density="1000"/>
    </body></worldbody></mujoco>)");
  const Scene model = importMjcf(path);
  const BodyDef& egg = model.bodies.back();
  ASSERT_EQ(egg.shapes[0].type, ShapeType::Ellipsoid);
  EXPECT_EQ(egg.shapes[0].radii, Vec3(0.3, 0.2, 0.1));
  EXPECT_NEAR(*egg.mass, 1000.0 * 4.0 / 3.0 * kPi * 0.006, 1e-12);
}

}  // namespace
}  // namespace linx
