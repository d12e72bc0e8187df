// Fixed joint: two glued bodies thrown spinning under gravity move as one rigid body with the
// combined mass and inertia, compared with a simulation of that single body.
#include "support.hpp"

#include "math/rotation.hpp"

#include <gtest/gtest.h>

namespace linx {
namespace {

struct Gap {
  double position = 0.0, rotation = 0.0, joint_error = 0.0;
};

// Two boxes of different mass glued at an offset (the second one turned), thrown up spinning
// fast, against one body of the combined mass and inertia, over 2 s at step h, both by one
// integrator.
Gap gluedAgainstCombined(double h, IntegratorType integrator) {
  WorldSettings s;
  s.timestep = h;
  s.integrator.type = integrator;
  BodyDef d1 = test::boxBody("a", 2.0, Vec3(0.4, 0.2, 0.1), Vec3(0, 0, 1));
  BodyDef d2 = test::boxBody("b", 1.0, Vec3(0.1, 0.3, 0.2), Vec3(0.3, 0.1, 1.05));
  d2.orientation = Quat(Eigen::AngleAxisd(0.6, Vec3(1, 1, 0).normalized()));
  const double m = *d1.mass + *d2.mass;
  const Vec3 c = (*d1.mass * d1.position + *d2.mass * d2.position) / m;
  // Combined inertia about c, in the world frame at creation (parallel axis theorem).
  Mat3 inertia = Mat3::Zero();
  for (const BodyDef* d : {&d1, &d2}) {
    const Mat3 r = d->orientation.toRotationMatrix();
    const Vec3 o = d->position - c;
    inertia += r * *d->inertia * r.transpose() +
               *d->mass * (o.squaredNorm() * Mat3::Identity() - o * o.transpose());
  }
  const Vec3 v(1.0, -0.5, 3.0), omega(2.0, -1.0, 4.0);
  d1.linear_velocity = v + omega.cross(d1.position - c);
  d2.linear_velocity = v + omega.cross(d2.position - c);
  d1.angular_velocity = d2.angular_velocity = omega;

  World glued(s);
  const BodyId a = glued.createBody(d1);
  const BodyId b = glued.createBody(d2);
  const JointId j = glued.createJoint(
      "fixed", JointDef{.name = "glue", .body1 = b, .body2 = a, .anchor = Vec3(0.15, 0.05, 1.02)});
  BodyDef one;
  one.name = "combined";
  one.mass = m;
  one.inertia = inertia;
  one.position = c;
  one.linear_velocity = v;
  one.angular_velocity = omega;
  World single(s);
  const BodyId o = single.createBody(one);

  Gap gap;
  const int n = static_cast<int>(std::lround(2.0 / h));
  for (int i = 0; i < n; ++i) {
    glued.step();
    single.step();
    const Body& ba = glued.body(a);
    const Body& bb = glued.body(b);
    const Body& bo = single.body(o);
    const Vec3 centre = (*d1.mass * ba.position() + *d2.mass * bb.position()) / m;
    gap.position = std::max(gap.position, (centre - bo.position()).norm());
    // Body a's orientation is the combined body's rotation applied to its initial one.
    gap.rotation =
        std::max(gap.rotation, ba.orientation().angularDistance(bo.orientation() * d1.orientation));
    gap.joint_error = std::max(gap.joint_error, glued.jointError(j));
  }
  return gap;
}

TEST(Fixed, GluedBodiesMoveAsOneRigidBodyOfTheCombinedInertia) {
  const Gap g = gluedAgainstCombined(1e-3, IntegratorType::Step),
            half = gluedAgainstCombined(5e-4, IntegratorType::Step);
  std::printf(
      "step, 2 s: centre of mass %.2e m, orientation %.2e rad (%.2e at h/2), joint error "
      "%.2e\n",
      g.position, g.rotation, half.rotation, g.joint_error);
  // The centre of mass feels only gravity: joint forces are internal, so it matches to round-off.
  EXPECT_LT(g.position, 1e-9);
  // The pair's rotation and the combined body's are two first-order discretizations of the same
  // motion: they differ by O(h) (2.7e-3 rad at 1 ms, |w| = 4.6 rad/s) and converge together:
  // halving h halves the gap.
  EXPECT_LT(g.rotation, 5e-3);
  EXPECT_NEAR(g.rotation / half.rotation, 2.0, 0.3);
  // Relative pose drift, held by error reduction.
  EXPECT_LT(g.joint_error, 1e-4);

  // The accurate integrator moves both to its tolerance (1e-10 per step): the two motions agree
  // to far below the step's gap, the joint exactly closed.
  const Gap a = gluedAgainstCombined(1e-3, IntegratorType::Accurate);
  std::printf("accurate, 2 s: centre of mass %.2e m, orientation %.2e rad, joint error %.2e\n",
              a.position, a.rotation, a.joint_error);
  EXPECT_LT(a.position, 1e-9);
  EXPECT_LT(a.rotation, 1e-9);
  EXPECT_LT(a.joint_error, 1e-12);
}

TEST(Fixed, WeldedToTheWorldABodyStaysPut) {
  World w;
  const BodyId a = w.createBody(test::boxBody("a", 1.0, Vec3(1, 1, 1), Vec3(0.5, 0, 2)));
  const JointId j =
      w.createJoint("fixed", JointDef{.name = "weld", .body1 = a, .anchor = Vec3(0, 0, 2)});
  for (int i = 0; i < 1000; ++i) w.step();
  EXPECT_LT((w.body(a).position() - Vec3(0.5, 0, 2)).norm(), 1e-9);
  EXPECT_LT(w.jointError(j), 1e-9);
  EXPECT_EQ(w.jointCoordinates(j).size(), 0);
}

}  // namespace
}  // namespace linx
