// Slider joint: uniform acceleration along an inclined axis, limits, the motor, the position
// readout, and exactness of the rows when both bodies rotate together.
#include "support.hpp"

#include <gtest/gtest.h>

namespace linx {
namespace {

struct Incline {
  World world;
  BodyId block;
  JointId slider;
  Vec3 axis;
};

// A 1 kg block on a slider to the world whose axis points down a slope (tilted 30 degrees and
// turned about z, so no axis is aligned with the world's); the block itself is turned arbitrarily.
Incline makeIncline(const SolverSettings& solver,
                    IntegratorType integrator = IntegratorSettings{}.type) {
  WorldSettings s;
  s.timestep = 1e-3;
  s.solver = solver;
  s.integrator.type = integrator;
  Incline in{World(s), {}, {}, Vec3(std::cos(0.4), std::sin(0.4), 0) * std::cos(0.5236)};
  in.axis.z() = -std::sin(0.5236);
  BodyDef d = test::boxBody("block", 1.0, Vec3(0.2, 0.1, 0.3), Vec3(0.3, -0.2, 1.0));
  d.orientation = Quat(Eigen::AngleAxisd(0.8, Vec3(1, 2, 3).normalized()));
  in.block = in.world.createBody(d);
  in.slider = in.world.createJoint(
      "slider", JointDef{.name = "rail", .body1 = in.block, .anchor = d.position, .axis = in.axis});
  return in;
}

class SliderIncline : public testing::TestWithParam<SolverType> {};

TEST_P(SliderIncline, FollowsUniformAccelerationAlongTheAxis) {
  // The step's solvers give symplectic Euler's discrete solution; "auto" (the accurate
  // integrator) the continuous s = 1/2 (g . d) t^2, whatever the solver.
  for (const IntegratorType integrator : {IntegratorType::Step, IntegratorType::Auto}) {
    SolverSettings solver;
    solver.type = GetParam();
    Incline in = makeIncline(solver, integrator);
    const double a = in.world.settings().gravity.dot(in.axis);  // g . d = 9.81 sin(30 deg)
    const Vec3 x0 = in.world.body(in.block).position();
    const Quat q0 = in.world.body(in.block).orientation();
    const double h = in.world.settings().timestep;
    const int n = 1000;
    double worst = 0.0;
    for (int i = 1; i <= n; ++i) {
      in.world.step();
      worst = std::max(worst, std::abs(in.world.jointCoordinates(in.slider)[0] -
                                       test::distanceFromRest(integrator, a, h, i)));
    }
    const double t = n * h, s = in.world.jointCoordinates(in.slider)[0];
    std::printf("%s: s(1 s) = %.9f m, 1/2 a t^2 = %.9f m, worst against its closed form %.2e m\n",
                std::string(integratorTypeName(integrator)).c_str(), s, 0.5 * a * t * t, worst);
    EXPECT_LT(worst, 1e-9);
    // The continuous s = 1/2 (g . d) t^2 differs from the discrete one by a h t / 2 only.
    EXPECT_NEAR(s, 0.5 * a * t * t, 0.5 * a * h * t + 1e-9);
    // The block neither leaves the axis nor turns.
    const Vec3 off = in.world.body(in.block).position() - x0;
    EXPECT_LT((off - in.axis * off.dot(in.axis)).norm(), 1e-9);
    EXPECT_LT(q0.angularDistance(in.world.body(in.block).orientation()), 1e-9);
    EXPECT_LT(in.world.jointError(in.slider), 1e-9);
  }
}
INSTANTIATE_TEST_SUITE_P(Solvers, SliderIncline,
                         testing::Values(SolverType::Exact, SolverType::Pgs),
                         [](const auto& info) { return std::string(solverTypeName(info.param)); });

TEST(Slider, LimitStopsTheBlockAtTheBound) {
  for (const SolverType type : {SolverType::Exact, SolverType::Pgs}) {
    SolverSettings solver;
    solver.type = type;
    Incline in = makeIncline(solver);
    in.world.joint(in.slider).setLimits(JointLimits{.lower = -0.1, .upper = 0.3});
    double highest = 0.0;
    for (int i = 0; i < 2000; ++i) {
      in.world.step();
      highest = std::max(highest, in.world.jointCoordinates(in.slider)[0]);
    }
    std::printf("%s: highest position %.12f m against the bound 0.3 m\n",
                std::string(solverTypeName(type)).c_str(), highest);
    // A speculative limit row lets the block arrive exactly at the bound: only round-off passes it.
    EXPECT_LT(highest, 0.3 + 1e-9);
    EXPECT_NEAR(in.world.jointCoordinates(in.slider)[0], 0.3, 1e-9);  // resting on it
    EXPECT_LT(in.world.body(in.block).linearVelocity().norm(), 1e-9);
  }
}

TEST(Slider, MotorDrivesAtTheTargetSpeedAndReadsPositivelyAlongTheAxis) {
  SolverSettings solver;
  Incline in = makeIncline(solver);
  // Up the slope at 0.5 m/s: the position along the axis (downhill) decreases at 0.5 m/s.
  in.world.joint(in.slider).setMotor(JointMotor{.target_velocity = -0.5, .max_force = 50.0});
  for (int i = 0; i < 1000; ++i) in.world.step();
  EXPECT_NEAR(in.world.body(in.block).linearVelocity().dot(in.axis), -0.5, 1e-9);
  // Spinning up at the 50 N bound against the weight's 4.905 N along the axis takes
  // t_up = 0.5 / 45.095 s; the lag is about 0.5 t_up / 2 = 2.77 mm (discretely a little less).
  const double t_up = 0.5 / (50.0 - 9.81 * std::sin(0.5236));
  EXPECT_NEAR(in.world.jointCoordinates(in.slider)[0], -0.5 * 1.0 + 0.5 * t_up / 2.0, 5e-4);
  // The motor's force equals the weight's component along the axis: after the first step (spin
  // up) the position follows -0.5 t exactly.
  const double s0 = in.world.jointCoordinates(in.slider)[0];
  for (int i = 0; i < 100; ++i) in.world.step();
  EXPECT_NEAR(in.world.jointCoordinates(in.slider)[0] - s0, -0.05, 1e-9);
  // The rate of the position is the motor's target velocity.
  EXPECT_NEAR(in.world.jointRates(in.slider)[0], -0.5, 1e-8);
}

TEST(Slider, RowsStayExactWhenBothBodiesRotateTogether) {
  // Two free bodies on a slider, no gravity, thrown spinning about an axis oblique to the slider
  // while sliding apart: the joint must hold with no drift from the rotation.
  WorldSettings s;
  s.gravity.setZero();
  s.timestep = 1e-3;
  World w(s);
  const BodyId a = w.createBody(test::boxBody("a", 2.0, Vec3(0.4, 0.2, 0.2), Vec3(0, 0, 0)));
  const BodyId b = w.createBody(test::boxBody("b", 1.0, Vec3(0.2, 0.2, 0.2), Vec3(0.5, 0, 0)));
  const JointId j = w.createJoint(
      "slider",
      JointDef{
          .name = "s", .body1 = b, .body2 = a, .anchor = Vec3(0.5, 0, 0), .axis = Vec3::UnitX()});
  const Vec3 omega(0.3, 1.0, 2.0);
  const Vec3 c = (2.0 * Vec3(0, 0, 0) + 1.0 * Vec3(0.5, 0, 0)) / 3.0;
  w.body(a).setAngularVelocity(omega);
  w.body(b).setAngularVelocity(omega);
  w.body(a).setLinearVelocity(omega.cross(Vec3(0, 0, 0) - c) - Vec3(0.1, 0, 0));
  w.body(b).setLinearVelocity(omega.cross(Vec3(0.5, 0, 0) - c) + Vec3(0.2, 0, 0));
  double worst = 0.0;
  for (int i = 0; i < 3000; ++i) {
    w.step();
    worst = std::max(worst, w.jointError(j));
  }
  std::printf("largest slider error while tumbling: %.2e\n", worst);
  // Linear rows are exact derivatives; the rotation lock is exact at zero error. What remains is
  // the first-order position update under a 2.3 rad/s spin, corrected by erp each step.
  EXPECT_LT(worst, 1e-5);
  // Momentum is conserved: the joint forces are internal.
  const Vec3 p = 2.0 * w.body(a).linearVelocity() + 1.0 * w.body(b).linearVelocity();
  EXPECT_LT(p.norm(), 1e-9);
}

}  // namespace
}  // namespace linx
