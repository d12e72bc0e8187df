// The joints' stiffness K = d(J^T lambda)/dq (Joint::stiffness), which the geometric stiffness of
// the velocity solve is made of (step/geometric_stiffness.hpp): the closed forms of the hinge, ball
// and fixed joints against the finite differences of their own rows (the default every other type
// uses), and against the closed form of a pendulum, whose joint force m g holds its bob with the
// stiffness m g L of gravity's restoring torque.
#include "random_state.hpp"
#include "support.hpp"

#include "math/rotation.hpp"

#include <gtest/gtest.h>

#include <random>

namespace linx {
namespace {

using test::randomState;
using test::randomVec;

TEST(GeometricStiffness, ClosedFormsMatchTheRowsFiniteDifferences) {
  std::mt19937 rng(11);
  int compared = 0;
  for (const char* type : {"hinge", "ball", "fixed", "universal"}) {
    for (int trial = 0; trial < 20; ++trial) {
      const BodyState c1 = randomState(rng), c2 = randomState(rng);
      JointDef def{.name = "j", .anchor = randomVec(rng, 1.0), .axis = randomVec(rng, 1.0)};
      // Limits on both sides of each coordinate, a motor, a spring and friction: every row the
      // joint can write.
      const CoordinateDef everything{
          .limits = JointLimits{-0.05, 0.05},
          .motor = JointMotor{1.0, 10.0},
          .spring = JointSpring{.stiffness = 30.0, .damping = 0.5, .rest = 0.2},
          .friction = 2.0};
      const JointTypeInfo& info = *findJointType(type);
      for (int i = 0; i < info.freeCoordinates(); ++i)  // a ball joint's angle: its bound only
        def.coordinates[static_cast<std::size_t>(i)] =
            info.coordinates[static_cast<std::size_t>(i)].limits_only
                ? CoordinateDef{.limits = JointLimits{0.0, 0.05}}
                : everything;
      if (std::string(type) == "universal") def.axis2 = def.axis.cross(randomVec(rng, 1.0));
      std::unique_ptr<Joint> j = makeJoint(type, def, c1, c2);
      // Off the pose of creation: the joint open, and its hinge past its limits.
      const BodyState b1 = randomState(rng), b2 = randomState(rng);
      const JointContext ctx{b1, b2, 0.01, 0.2, 0.0};
      std::vector<Row> rows(static_cast<std::size_t>(j->maxRows()));
      rows.resize(static_cast<std::size_t>(j->fill(ctx, rows)));
      std::vector<double> lambda(rows.size());
      for (double& l : lambda) l = std::uniform_real_distribution<double>(-3.0, 3.0)(rng);
      const Mat12 closed = j->stiffness(ctx, rows, lambda);
      const Mat12 numeric = j->Joint::stiffness(ctx, rows, lambda);
      EXPECT_LT((closed - numeric).norm(), 1e-7 * (1.0 + numeric.norm()))
          << type << " trial " << trial << "\nclosed\n"
          << closed << "\nnumeric\n"
          << numeric;
      if (std::string(type) == "hinge") {
        EXPECT_GE(rows.size(), 7u);  // a limit and the motor
      }
      ++compared;
    }
  }
  EXPECT_EQ(compared, 80);
}

TEST(GeometricStiffness, HangingBobIsHeldWithThePendulumsStiffness) {
  // A bob of mass m hangs at rest L below a hinge to the world: the joint pulls it up with m g,
  // and turning the bob by a small angle about the hinge turns that force's torque into the
  // restoring torque -m g L angle: K(rot, rot) about the axis is -m g L (times h for an impulse).
  constexpr double m = 2.0, g = 9.81, L = 0.7, h = 1.0 / 240.0;
  const BodyState bob{Pose{Vec3(0.0, 0.0, -L), Quat::Identity()}, Vec3::Zero(), Vec3::Zero()};
  const BodyState world{};
  const std::unique_ptr<Joint> j =
      makeJoint("hinge", JointDef{.name = "pivot", .anchor = Vec3::Zero(), .axis = Vec3::UnitY()},
                bob, world);
  const JointContext ctx{bob, world, h, 0.2, 0.0};
  std::vector<Row> rows(static_cast<std::size_t>(j->maxRows()));
  rows.resize(static_cast<std::size_t>(j->fill(ctx, rows)));
  // The impulses that hold the bob over a step: m g h upwards on the point rows (world axes).
  std::vector<double> lambda(rows.size(), 0.0);
  for (std::size_t k = 0; k < 3; ++k) lambda[k] = m * g * h * rows[k].Ja.z();
  const Mat12 k = j->stiffness(ctx, rows, lambda);
  EXPECT_NEAR(k(4, 4), -m * g * L * h, 1e-12);  // about y, the hinge's axis
  EXPECT_NEAR(k(3, 3), -m * g * L * h, 1e-12);  // about x: the same pull, the same lever
  EXPECT_NEAR(k(5, 5), 0.0, 1e-12);             // about z, along the force: nothing turns
}

}  // namespace
}  // namespace linx
