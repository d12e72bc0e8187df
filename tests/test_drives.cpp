// Drives and springs on joint coordinates: a spring-mass oscillator against its closed form
// (period 2 pi sqrt(m/k), amplitude kept), critical damping, a stiff spring that stays stable, a
// damped velocity motor's exponential approach, and a PD servo at k = 1e8 and h = 1 ms.
#include "joints/row_parts.hpp"
#include "support.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <numbers>

namespace linx {
namespace {

constexpr double kPi = std::numbers::pi;

struct Oscillator {
  World world;
  BodyId block;
  JointId slider;
  Vec3 axis;
  double mass;
};

// A block on a slider to the world along an axis aligned with no world axis, gravity off. The block
// is turned arbitrarily; the anchor is its centre of mass.
Oscillator makeOscillator(SolverType type, double h, double mass, const JointSpring& spring) {
  WorldSettings s;
  s.timestep = h;
  s.gravity.setZero();
  s.solver.type = type;
  if (type == SolverType::Soft) s.solver.substeps = 4;
  Oscillator o{World(s), {}, {}, Vec3(1.0, 2.0, -0.5).normalized(), mass};
  BodyDef d = test::boxBody("block", mass, Vec3(0.2, 0.1, 0.3), Vec3(0.3, -0.2, 1.0));
  d.orientation = Quat(Eigen::AngleAxisd(0.8, Vec3(1, 2, 3).normalized()));
  o.block = o.world.createBody(d);
  o.slider =
      o.world.createJoint("slider", JointDef{.name = "rail",
                                             .body1 = o.block,
                                             .anchor = d.position,
                                             .axis = o.axis,
                                             .coordinates = {CoordinateDef{.spring = spring}}});
  return o;
}

double rate(const Oscillator& o) {
  return o.world.body(o.block).linearVelocity().dot(o.axis);
}

// The solver's name, for messages (solverTypeName's views are of string literals).
class SpringOscillator : public testing::TestWithParam<SolverType> {};

TEST_P(SpringOscillator, KeepsItsPeriodAndAmplitudeOverTenPeriods) {
  // m = 2 kg, k = 50 N/m: omega = 5 rad/s; released 0.1 m from its rest position, 100 steps a
  // period. Symplectic Euler's period is shorter by (omega h)^2 / 24 = 1.6e-4; it keeps the
  // amplitude (no numerical damping), where implicit Euler loses 18 % a period.
  const double m = 2.0, k = 50.0, rest = 0.1;
  const double omega = std::sqrt(k / m), period = 2.0 * kPi / omega, h = period / 100.0;
  Oscillator o = makeOscillator(GetParam(), h, m, JointSpring{.stiffness = k, .rest = rest});
  std::vector<double> t, x;
  for (int i = 0; i < 1000; ++i) {
    o.world.step();
    t.push_back(o.world.time());
    x.push_back(o.world.jointCoordinates(o.slider)[0] - rest);
  }
  const auto crossings = test::upwardCrossings(t, x);
  ASSERT_GE(crossings.size(), 9u);
  const double measured =
      (crossings.back() - crossings.front()) / static_cast<double>(crossings.size() - 1);
  const auto peak = [&](std::size_t from, std::size_t to) {
    double p = 0.0;
    for (std::size_t i = from; i < to; ++i) p = std::max(p, std::abs(x[i]));
    return p;
  };
  const double first = peak(0, 100), last = peak(900, 1000);
  std::printf("%s: period %.6f s (closed form %.6f, %.2e), amplitude %.6f -> %.6f m (%.2e)\n",
              test::solverName(GetParam()), measured, period, measured / period - 1.0, first, last,
              last / first - 1.0);
  EXPECT_NEAR(measured / period, 1.0, 5e-4);
  EXPECT_NEAR(first, 0.1, 1e-3);
  EXPECT_NEAR(last / first, 1.0, 5e-3);  // the bound: 0.5 % over 10 periods
  EXPECT_LT(o.world.maxJointError(), 1e-9);
}

TEST_P(SpringOscillator, CriticallyDampedDoesNotOvershoot) {
  // c = 2 sqrt(k m): x(t) = -A (1 + omega t) exp(-omega t), approaching rest from one side.
  const double m = 2.0, k = 50.0, rest = 0.1, A = 0.1, h = 1e-3;
  const double omega = std::sqrt(k / m), c = 2.0 * std::sqrt(k * m);
  Oscillator o =
      makeOscillator(GetParam(), h, m, JointSpring{.stiffness = k, .damping = c, .rest = rest});
  double worst = 0.0, highest = -kInfinity;
  for (int i = 0; i < 3000; ++i) {
    o.world.step();
    const double tt = o.world.time();
    const double x = o.world.jointCoordinates(o.slider)[0] - rest;
    worst = std::max(worst, std::abs(x + A * (1.0 + omega * tt) * std::exp(-omega * tt)));
    highest = std::max(highest, x);
  }
  std::printf("%s: largest deviation from the closed form %.2e m, highest %.2e m\n",
              test::solverName(GetParam()), worst, highest);
  EXPECT_LT(worst, 0.01 * A);  // first order in h: omega h A = 5e-4 m
  EXPECT_LE(highest, 1e-9 * A);
}

TEST_P(SpringOscillator, StiffSpringStaysStableAtTenTimesTheStepRate) {
  // omega h = 10: symplectic Euler would blow up (it needs omega h < 2). The spring takes enough of
  // its force implicitly to stay stable; its energy never rises.
  const double m = 2.0, k = 2e6, rest = 0.1, h = 1e-2;
  Oscillator o = makeOscillator(GetParam(), h, m, JointSpring{.stiffness = k, .rest = rest});
  const auto energy = [&] {
    const double x = o.world.jointCoordinates(o.slider)[0] - rest, v = rate(o);
    return 0.5 * m * v * v + 0.5 * k * x * x;
  };
  const double e0 = energy();
  double highest = e0;
  for (int i = 0; i < 1000; ++i) {
    o.world.step();
    highest = std::max(highest, energy());
  }
  std::printf("%s: energy %.4g J at the start, highest %.4g, at the end %.4g\n",
              test::solverName(GetParam()), e0, highest, energy());
  EXPECT_LE(highest, e0 * (1.0 + 1e-9));
  EXPECT_LT(energy(), 1e-3 * e0);  // and it settles
}

TEST_P(SpringOscillator, DampedVelocityMotorApproachesItsSpeedExponentially) {
  // F = c (v_t - v) on a free block: v(t) = v_t (1 - exp(-c t / m)).
  const double m = 2.0, c = 4.0, vt = 0.7, h = 1e-3;
  Oscillator o = makeOscillator(GetParam(), h, m, JointSpring{});
  o.world.joint(o.slider).setMotor(JointMotor{.target_velocity = vt, .damping = c});
  double worst = 0.0;
  for (int i = 0; i < 2000; ++i) {
    o.world.step();
    worst = std::max(worst, std::abs(rate(o) - vt * (1.0 - std::exp(-c * o.world.time() / m))));
  }
  std::printf("%s: largest deviation from v_t (1 - exp(-c t / m)): %.2e m/s\n",
              test::solverName(GetParam()), worst);
  EXPECT_LT(worst, 2e-3 * vt);  // implicit Euler's first-order error, c h / (2 m) of v_t
}

INSTANTIATE_TEST_SUITE_P(Solvers, SpringOscillator,
                         testing::Values(SolverType::Auto, SolverType::Exact, SolverType::Pgs,
                                         SolverType::Soft),
                         [](const auto& info) {
                           return std::string(test::solverName(info.param));
                         });

struct Rod {
  World world;
  BodyId rod;
  JointId hinge;
  double pivot_inertia;  // about the hinge axis through the anchor
};

// A 1 kg, 1 m rod hinged at one end (the origin) about y, lying along x.
Rod makeRod(SolverType type, double h, bool gravity,
            IntegratorType integrator = IntegratorSettings{}.type) {
  WorldSettings s;
  s.timestep = h;
  s.integrator.type = integrator;
  if (!gravity) s.gravity.setZero();
  s.solver.type = type;
  if (type == SolverType::Soft) s.solver.substeps = 4;
  Rod r{World(s), {}, {}, 1.0 * (1.0 + 0.02 * 0.02) / 12.0 + 0.25};
  r.rod = r.world.createBody(test::boxBody("rod", 1.0, Vec3(1.0, 0.02, 0.02), Vec3(0.5, 0, 0)));
  r.hinge = r.world.createJoint(
      "hinge",
      JointDef{.name = "pivot", .body1 = r.rod, .anchor = Vec3::Zero(), .axis = Vec3::UnitY()});
  return r;
}

TEST(TorsionSpring, RodOscillatesWithThePeriodOfItsPivotInertia) {
  // T = 2 pi sqrt(I_p / k), I_p about the pivot (the hinge carries the rod's end).
  for (const SolverType type : {SolverType::Auto, SolverType::Soft}) {
    const double k = 20.0, rest = 0.3;
    const double period = 2.0 * kPi * std::sqrt((1.0 / 12.0 * 1.0004 + 0.25) / k);
    Rod r = makeRod(type, period / 100.0, false);
    r.world.joint(r.hinge).setSpring(JointSpring{.stiffness = k, .rest = rest});
    std::vector<double> t, x;
    for (int i = 0; i < 1000; ++i) {
      r.world.step();
      t.push_back(r.world.time());
      x.push_back(r.world.jointCoordinates(r.hinge)[0] - rest);
    }
    const auto crossings = test::upwardCrossings(t, x);
    ASSERT_GE(crossings.size(), 9u);
    const double measured =
        (crossings.back() - crossings.front()) / static_cast<double>(crossings.size() - 1);
    double first = 0.0, last = 0.0;
    for (int i = 0; i < 100; ++i) first = std::max(first, std::abs(x[std::size_t(i)]));
    for (int i = 900; i < 1000; ++i) last = std::max(last, std::abs(x[std::size_t(i)]));
    std::printf("%s: period %.6f s (closed form %.6f), amplitude %.6f -> %.6f rad\n",
                test::solverName(type), measured, period, first, last);
    EXPECT_NEAR(measured / period, 1.0, 5e-4);
    EXPECT_NEAR(last / first, 1.0, 5e-3);
    EXPECT_LT(r.world.maxJointError(), 1e-9);
  }
}

TEST(Servo, StiffestGainIsStableAtAMillisecondAndSettlesOnItsTarget) {
  // k = 1e8 N m/rad at h = 1 ms (omega h = 17 on the rod's pivot inertia): under gravity, with and
  // without damping, the rod goes to its target and stays there; the gravity torque (at most
  // m g L / 2 = 4.9 N m) leaves an error of at most 4.9e-8 rad. Implicit Euler's overshoot is
  // 1 / (h omega)^2 = 0.3 % of the jump; to 0.5 rad in one step the rotation's linearization
  // adds some (the pivot, 6 cm off after that step, is projected back).
  for (const SolverType type : {SolverType::Auto, SolverType::Pgs, SolverType::Soft}) {
    for (const double damping : {0.0, 2.0 * std::sqrt(1e8 * 0.3334)}) {
      for (const double target : {0.01, 0.5}) {
        Rod r = makeRod(type, 1e-3, true);
        r.world.joint(r.hinge).setMotor(
            JointMotor{.target_position = target, .stiffness = 1e8, .damping = damping});
        double widest = 0.0;
        for (int i = 0; i < 1000; ++i) {
          r.world.step();
          widest = std::max(widest, std::abs(r.world.jointCoordinates(r.hinge)[0]));
        }
        const double angle = r.world.jointCoordinates(r.hinge)[0];
        const double w = r.world.body(r.rod).angularVelocity().norm();
        std::printf(
            "%s, damping %.3g, target %.2f: after 1 s %.10f rad, |w| %.2e rad/s, widest "
            "%.5f\n",
            test::solverName(type), damping, target, angle, w, widest);
        EXPECT_NEAR(angle, target, 1e-7);
        EXPECT_LT(w, 1e-4);
        EXPECT_LT(widest, target * (target < 0.1 ? 1.01 : 1.1));
      }
    }
  }
}

TEST(Servo, SaturatedServoAcceleratesAtItsMaximumTorque) {
  // A far target and a bound of 2 N m: the torque is 2 N m every step, so theta_n follows
  // symplectic Euler's constant acceleration, alpha h^2 n (n + 1) / 2 with alpha = 2 / I_p, with
  // the step, and alpha t^2 / 2 with "auto" (the accurate integrator: the servo is a force).
  for (const IntegratorType integrator : {IntegratorType::Step, IntegratorType::Auto}) {
    for (const SolverType type : {SolverType::Auto, SolverType::Exact, SolverType::Soft}) {
      const double h = 1e-3, torque = 2.0;
      Rod r = makeRod(type, h, false, integrator);
      r.world.joint(r.hinge).setMotor(
          JointMotor{.max_force = torque, .target_position = 10.0, .stiffness = 1e6});
      const double alpha = torque / r.pivot_inertia;
      const int substeps = type == SolverType::Soft ? r.world.settings().solver.substeps : 1;
      double worst = 0.0;
      for (int n = 1; n <= 500; ++n) {
        r.world.step();
        // The soft step's substeps of h / s: the same sum over n s substeps of h / s.
        const double exact = test::distanceFromRest(integrator, alpha, h / substeps, n * substeps);
        worst = std::max(worst, std::abs(r.world.jointCoordinates(r.hinge)[0] / exact - 1.0));
      }
      std::printf("%s, %s: angle %.9f rad after 0.5 s, worst against the closed form %.2e\n",
                  std::string(integratorTypeName(integrator)).c_str(), test::solverName(type),
                  r.world.jointCoordinates(r.hinge)[0], worst);
      // The torque is exact; what is left with the step is the rod's turning about a pivot
      // integrated as a free body held by velocity rows and projected back (second order in h:
      // 6e-7 here).
      EXPECT_LT(worst, 2e-6);
    }
  }
}

TEST(Signal, InterpolatesLinearlyAndHoldsItsEnds) {
  const Signal s({0.0, 1.0, 3.0}, {0.0, 2.0, 2.0});
  EXPECT_EQ(s.at(-1.0), 0.0);
  EXPECT_EQ(s.at(0.5), 1.0);
  EXPECT_EQ(s.at(1.0), 2.0);
  EXPECT_EQ(s.at(2.0), 2.0);
  EXPECT_EQ(s.at(7.0), 2.0);
  EXPECT_EQ(s.rate(-1.0), 0.0);
  EXPECT_EQ(s.rate(0.5), 2.0);
  EXPECT_EQ(s.rate(2.0), 0.0);
  EXPECT_EQ(s.rate(7.0), 0.0);
  EXPECT_EQ(Signal(4.5).at(100.0), 4.5);
  EXPECT_EQ(Signal(4.5).rate(100.0), 0.0);
}

TEST(Servo, FollowsARampWithoutLag) {
  // The target moves at 0.5 rad/s from t = 0 to 2 s (a table), the servo critically damped with
  // k = 1e4 N m/rad. Its damping aims at the table's rate, so the error obeys
  // I e'' + c e' + k e = 0 from e'(0) = -0.5 rad/s: e = -0.5 t exp(-omega t), gone within a
  // second (without the table's rate the rod would trail by c v / k = 5.8e-3 rad).
  for (const SolverType type : {SolverType::Auto, SolverType::Soft}) {
    Rod r = makeRod(type, 1e-3, false);
    const double k = 1e4, c = 2.0 * std::sqrt(k * r.pivot_inertia);
    r.world.joint(r.hinge).setMotor(JointMotor{
        .target_position = Signal({0.0, 2.0}, {0.0, 1.0}), .stiffness = k, .damping = c});
    double ramp = 0.0, corner = 0.0;  // worst errors in [1, 2) s and after the corner at 2 s
    for (int i = 0; i < 3000; ++i) {
      r.world.step();
      const double t = r.world.time(), target = std::min(0.5 * t, 1.0);
      const double e = std::abs(r.world.jointCoordinates(r.hinge)[0] - target);
      if (t >= 1.0) (t < 2.0 ? ramp : corner) = std::max(t < 2.0 ? ramp : corner, e);
    }
    std::printf("%s: from 1 to 2 s at most %.2e rad from the moving target, after its stop %.2e\n",
                test::solverName(type), ramp, corner);
    EXPECT_LT(ramp, 1e-8);
    // The stop at 2 s starts the transient again: 0.5 t exp(-omega t) peaks at 0.5 / (e omega),
    // 1.05e-3 rad.
    EXPECT_LT(corner, 1.1e-3);
    EXPECT_NEAR(r.world.jointCoordinates(r.hinge)[0], 1.0, 1e-6);  // held at the table's end
  }
}

TEST(Motor, VelocityTableIsFollowedExactly) {
  // Target rate 2 t (a table from (0, 0) to (1, 2)): the rigid motor makes the rate 2 t_(n+1) at
  // the end of every step, so theta_n = sum of h 2 k h = h^2 n (n + 1), 1.001 rad at 1 s.
  for (const SolverType type : {SolverType::Auto, SolverType::Pgs}) {
    const double h = 1e-3;
    Rod r = makeRod(type, h, false);
    r.world.joint(r.hinge).setMotor(
        JointMotor{.target_velocity = Signal({0.0, 1.0}, {0.0, 2.0}), .max_force = 1e3});
    double worst = 0.0;
    for (int n = 1; n <= 1000; ++n) {
      r.world.step();
      worst =
          std::max(worst, std::abs(r.world.jointCoordinates(r.hinge)[0] - h * h * n * (n + 1.0)));
    }
    std::printf("%s: angle %.9f rad at 1 s, worst against h^2 n (n + 1) %.2e\n",
                test::solverName(type), r.world.jointCoordinates(r.hinge)[0], worst);
    EXPECT_LT(worst, 1e-9);
  }
}

TEST(ImplicitShare, NoneWhileTheStepResolvesTheSpringAndHalfWhenItCannot) {
  using joints::implicitShare;
  EXPECT_EQ(implicitShare(50.0, 0.5, 0.01), joints::kMinImplicitShare);  // (h omega)^2 = 2.5e-3
  EXPECT_EQ(implicitShare(1.0, 1.0, 1.0), joints::kMinImplicitShare);    // (h omega)^2 = 1
  EXPECT_DOUBLE_EQ(implicitShare(4.0, 1.0, 1.0), 0.75);
  EXPECT_DOUBLE_EQ(implicitShare(1e8, 1.0, 1e-3), 0.99);               // towards implicit Euler
  EXPECT_EQ(implicitShare(0.0, 1.0, 1.0), joints::kMinImplicitShare);  // a damper alone
  EXPECT_EQ(implicitShare(1.0, 0.0, 1.0), joints::kMinImplicitShare);  // nothing moves
}

TEST(DriveDefinitions, RefusedWithTheFieldNamed) {
  Rod r = makeRod(SolverType::Auto, 1e-3, true);
  Joint& j = r.world.joint(r.hinge);
  const auto message = [&](auto&& set) {
    try {
      set();
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string("(accepted)");
  };
  EXPECT_EQ(message([&] { j.setMotor(JointMotor{.target_position = 1.0}); }),
            "motor.stiffness: a servo (target_position) needs a stiffness > 0 to pull towards it");
  EXPECT_EQ(message([&] { j.setMotor(JointMotor{.stiffness = 5.0}); }),
            "motor.target_position: missing: a stiffness pulls towards a target_position");
  EXPECT_EQ(message([&] { j.setMotor(JointMotor{.damping = -1.0}); }),
            "motor.damping: must be >= 0, got -1");
  EXPECT_EQ(message([&] {
              j.setMotor(JointMotor{.target_position = Signal({0.0, 1.0, 1.0}, {0, 1, 2}),
                                    .stiffness = 1.0});
            }),
            "motor.target_position: times[2]: must be after times[1] (1 <= 1)");
  EXPECT_EQ(message([&] {
              j.setMotor(JointMotor{.target_velocity = Signal({0.0, 1.0}, {0.0}), .max_force = 1});
            }),
            "motor.target_velocity: 2 times but 1 values");
  EXPECT_EQ(message([&] { j.setSpring(JointSpring{.stiffness = kInfinity}); }),
            "spring.stiffness: must be finite");
  EXPECT_EQ(message([&] { j.setSpring(JointSpring{.stiffness = 1.0, .rest = std::nan("")}); }),
            "spring.rest: must be finite");
  const BodyId ball =
      r.world.createBody(test::boxBody("b", 1.0, Vec3(0.1, 0.1, 0.1), Vec3(2, 0, 0)));
  EXPECT_THROW(r.world.createJoint("ball", JointDef{.name = "s",
                                                    .body1 = ball,
                                                    .anchor = Vec3(2, 0, 0),
                                                    .coordinates = {CoordinateDef{
                                                        .spring = JointSpring{.stiffness = 1.0}}}}),
               std::invalid_argument);
}

}  // namespace
}  // namespace linx
