// Mass properties of shapes against closed forms and an independent numerical integration, and of
// compound bodies against the parallel-axis theorem.
#include <linx/mass_properties.hpp>

#include <gtest/gtest.h>

#include <numbers>

namespace linx {
namespace {

constexpr double kPi = std::numbers::pi;

ShapeDef capsule(double r, double length) {
  return ShapeDef{.type = ShapeType::Capsule, .radius = r, .length = length};
}

TEST(MassProperties, SphereAndBoxMatchTheirClosedForms) {
  const MassProperties s =
      shapeMassProperties(ShapeDef{.type = ShapeType::Sphere, .radius = 0.5}, 1000.0);
  EXPECT_NEAR(s.mass, 1000.0 * 4.0 / 3.0 * kPi * 0.125, 1e-9);
  EXPECT_TRUE(s.inertia.isApprox(Mat3::Identity() * 0.4 * s.mass * 0.25, 1e-14));
  const MassProperties b =
      shapeMassProperties(ShapeDef{.type = ShapeType::Box, .size = Vec3(1, 2, 3)}, 2.0);
  EXPECT_NEAR(b.mass, 12.0, 1e-12);
  EXPECT_TRUE(b.inertia.isApprox(Vec3(13.0, 10.0, 5.0).asDiagonal().toDenseMatrix(), 1e-14));
}

// Volume and inertia about the centre by midpoint sampling on a regular grid: a check that shares
// no formula with the library.
MassProperties integrate(const ShapeDef& s, double density, int n) {
  const double half_z = 0.5 * s.length + (s.type == ShapeType::Capsule ? s.radius : 0.0);
  const Vec3 lo(-s.radius, -s.radius, -half_z), hi(s.radius, s.radius, half_z);
  const Vec3 step = (hi - lo) / n;
  const double dv = step.prod();
  MassProperties p;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      for (int k = 0; k < n; ++k) {
        const Vec3 x = lo + Vec3(i + 0.5, j + 0.5, k + 0.5).cwiseProduct(step);
        const double rho2 = x.x() * x.x() + x.y() * x.y();
        const double zc = std::max(0.0, std::abs(x.z()) - 0.5 * s.length);  // beyond the side
        const bool inside = s.type == ShapeType::Cylinder ? rho2 <= s.radius * s.radius
                                                          : rho2 + zc * zc <= s.radius * s.radius;
        if (!inside) continue;
        const double dm = density * dv;
        p.mass += dm;
        p.inertia += dm * (x.squaredNorm() * Mat3::Identity() - x * x.transpose());
      }
  return p;
}

TEST(MassProperties, CapsuleAndCylinderMatchNumericalIntegration) {
  for (const ShapeDef& s : {capsule(0.3, 1.0), capsule(0.5, 0.2),
                            ShapeDef{.type = ShapeType::Cylinder, .radius = 0.4, .length = 1.5}}) {
    const MassProperties exact = shapeMassProperties(s, 1.0);
    const MassProperties grid = integrate(s, 1.0, 120);
    // Midpoint sampling of a curved boundary: about 1e-3 relative at 120 cells a side.
    EXPECT_NEAR(grid.mass / exact.mass, 1.0, 5e-3) << shapeTypeName(s.type);
    EXPECT_LT((grid.inertia - exact.inertia).norm() / exact.inertia.norm(), 5e-3)
        << shapeTypeName(s.type);
  }
}

TEST(MassProperties, ACapsuleOfLengthZeroIsASphere) {
  const MassProperties c = shapeMassProperties(capsule(0.3, 0.0), 7.0);
  const MassProperties s =
      shapeMassProperties(ShapeDef{.type = ShapeType::Sphere, .radius = 0.3}, 7.0);
  EXPECT_NEAR(c.mass, s.mass, 1e-12);
  EXPECT_TRUE(c.inertia.isApprox(s.inertia, 1e-12));
}

TEST(MassProperties, TwoHalvesOfABoxCombineIntoTheWholeBox) {
  // A 2 x 1 x 1 box is two unit cubes side by side: their combination must be the box exactly.
  const ShapeDef left{.type = ShapeType::Box, .size = Vec3(1, 1, 1), .position = Vec3(-0.5, 0, 0)};
  const ShapeDef right{.type = ShapeType::Box, .size = Vec3(1, 1, 1), .position = Vec3(0.5, 0, 0)};
  const MassProperties parts[] = {shapeMassProperties(left, 3.0), shapeMassProperties(right, 3.0)};
  const MassProperties both = combine(parts);
  const MassProperties whole =
      shapeMassProperties(ShapeDef{.type = ShapeType::Box, .size = Vec3(2, 1, 1)}, 3.0);
  EXPECT_NEAR(both.mass, whole.mass, 1e-12);
  EXPECT_LT(both.center.norm(), 1e-15);
  EXPECT_TRUE(both.inertia.isApprox(whole.inertia, 1e-14));
}

TEST(MassProperties, RotationAndOffsetFollowTheShapesPose) {
  // A box turned 90 degrees about z swaps its x and y moments; offset, its centre moves and the
  // inertia about the origin gains m d^2 about the perpendicular axes.
  ShapeDef box{.type = ShapeType::Box, .size = Vec3(1, 2, 3)};
  box.orientation = Quat(Eigen::AngleAxisd(kPi / 2, Vec3::UnitZ()));
  box.position = Vec3(0, 0, 2);
  const MassProperties p = shapeMassProperties(box, 1.0);  // m = 6
  // m = 6: moments m/12 (4 + 9), m/12 (1 + 9), m/12 (1 + 4) = 6.5, 5, 2.5; x and y swapped.
  EXPECT_TRUE(p.inertia.isApprox(Vec3(5.0, 6.5, 2.5).asDiagonal().toDenseMatrix(), 1e-12));
  EXPECT_EQ(p.center, Vec3(0, 0, 2));
  const Mat3 origin = p.inertiaAboutOrigin();
  EXPECT_NEAR(origin(0, 0), p.inertia(0, 0) + 6.0 * 4.0, 1e-12);
  EXPECT_NEAR(origin(2, 2), p.inertia(2, 2), 1e-12);
}

TEST(MassProperties, DumbbellFollowsTheParallelAxisTheorem) {
  const ShapeDef a{.type = ShapeType::Sphere, .radius = 0.1, .position = Vec3(-1, 0, 0)};
  const ShapeDef b{.type = ShapeType::Sphere, .radius = 0.1, .position = Vec3(1, 0, 0)};
  const MassProperties parts[] = {shapeMassProperties(a, 500.0), shapeMassProperties(b, 1500.0)};
  const MassProperties d = combine(parts);
  const double ma = parts[0].mass, mb = parts[1].mass, m = ma + mb;
  EXPECT_NEAR(d.center.x(), (mb - ma) / m, 1e-15);
  // About the common centre, perpendicular to the bar: each sphere's own 2/5 m r^2 plus m d^2.
  const double da = 1 + d.center.x(), db = 1 - d.center.x();
  EXPECT_NEAR(d.inertia(1, 1), 0.4 * m * 0.01 + ma * da * da + mb * db * db, 1e-12);
  EXPECT_NEAR(d.inertia(0, 0), 0.4 * m * 0.01, 1e-12);
}

// A shape of density 0 (MJCF's mass="0" geoms) weighs nothing: the body's mass, centre and
// inertia are those of its other shapes, by the box's closed form; with every density 0 there is
// no mass to make, and a negative density is refused.
TEST(MassProperties, MasslessShapesAddNothing) {
  BodyDef body;
  body.name = "b";
  body.shapes = {
      ShapeDef{.type = ShapeType::Box, .size = Vec3(1, 2, 3), .density = 2.0},
      ShapeDef{
          .type = ShapeType::Sphere, .radius = 0.7, .position = Vec3(3, 0, 0), .density = 0.0}};
  completeMassProperties(body);
  EXPECT_NEAR(*body.mass, 12.0, 1e-12);
  EXPECT_TRUE(body.inertia->isApprox(Vec3(13.0, 10.0, 5.0).asDiagonal().toDenseMatrix(), 1e-14));
  EXPECT_EQ(body.position, Vec3::Zero());  // the box's centre, not moved towards the sphere
  BodyDef none = body;
  none.mass.reset();
  none.inertia.reset();
  none.shapes[0].density = 0.0;
  EXPECT_THROW(completeMassProperties(none), std::invalid_argument);
  none.shapes[0].density = -1.0;
  EXPECT_THROW(completeMassProperties(none), std::invalid_argument);
}

}  // namespace
}  // namespace linx
