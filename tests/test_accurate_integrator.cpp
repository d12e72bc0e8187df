// The accurate integrator (docs/integrators.md): energy and joint errors of mechanisms over long
// runs, against conservation of energy and the joints' own geometry.
#include "support.hpp"

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <numbers>

namespace linx {
namespace {

WorldSettings accurateSettings(double h) {
  WorldSettings s;
  s.timestep = h;
  s.integrator.type = IntegratorType::Accurate;
  return s;
}

double largestJointError(const World& w) {
  double e = 0.0;
  for (const JointId id : w.jointIds()) e = std::max(e, w.jointError(id));
  return e;
}

// A chain of `links` uniform rods (1 kg, 0.2 m, no shapes: nothing touches) hinged end to end
// about y, the first to the world at the origin, released horizontal along +x.
World horizontalChain(int links, const WorldSettings& s) {
  World w(s);
  BodyId previous;
  const double length = 0.2;
  for (int i = 0; i < links; ++i) {
    BodyDef d = test::boxBody("link" + std::to_string(i), 1.0, Vec3(length, 0.02, 0.02),
                              Vec3((i + 0.5) * length, 0, 0));
    d.shapes.clear();
    const BodyId id = w.createBody(d);
    JointDef j{.name = "hinge" + std::to_string(i),
               .body1 = i == 0 ? id : previous,
               .anchor = Vec3(i * length, 0, 0),
               .axis = Vec3::UnitY()};
    if (i > 0) j.body2 = id;
    w.createJoint("hinge", j);
    previous = id;
  }
  return w;
}

TEST(AccurateIntegrator, FiveLinkChainKeepsItsEnergy) {
  World w = horizontalChain(5, accurateSettings(1e-3));
  const double e0 = w.energy().total();
  double exchanged = 0.0, drift = 0.0, joint = 0.0;
  const auto start = std::chrono::steady_clock::now();
  const double duration = test::runLength(60.0, 10.0);
  while (w.time() < duration - 1e-9) {
    w.step();
    exchanged = std::max(exchanged, w.energy().kinetic);
    drift = std::max(drift, std::abs(w.energy().total() - e0));
    joint = std::max(joint, largestJointError(w));
  }
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::printf("over %g s: exchanged %.6g J, drift %.3g J (%.3g), joints %.3g m, %.3f s\n", duration,
              exchanged, drift, drift / exchanged, joint, seconds);
  EXPECT_LT(drift, 1e-6 * exchanged);
  EXPECT_LT(joint, 1e-8);
}

// Dzhanibekov's flips: a free body with I1 < I2 < I3 spun about its intermediate axis with a
// small disturbance turns over and back. Euler's equations have the closed form (Landau and
// Lifshitz, Mechanics, section 37; L^2 > 2 E I2): w2 = A2 sn(lambda t + tau0, k), so w2 changes
// sign at t_n = (2 n K(k) - tau0) / lambda.
TEST(AccurateIntegrator, FreeBodyFlipsAtTheClosedFormTimes) {
  WorldSettings s = accurateSettings(1e-3);
  s.gravity = Vec3::Zero();
  World w(s);
  const Vec3 inertia(1.0, 2.0, 3.0);
  const Vec3 w0(0.01, 10.0, 0.01);
  BodyDef d;
  d.name = "tumbler";
  d.mass = 1.0;
  d.inertia = inertia.asDiagonal();
  d.angular_velocity = w0;
  const BodyId id = w.createBody(d);

  const double i1 = inertia[0], i2 = inertia[1], i3 = inertia[2];
  const double two_e = inertia.dot(w0.cwiseProduct(w0));
  const double l2 = inertia.cwiseProduct(w0).squaredNorm();
  ASSERT_GT(l2, two_e * i2);
  const double k2 = (i2 - i1) * (two_e * i3 - l2) / ((i3 - i2) * (l2 - two_e * i1));
  const double k = std::sqrt(k2);
  const double lambda = std::sqrt((i3 - i2) * (l2 - two_e * i1) / (i1 * i2 * i3));
  const double a2 = std::sqrt((two_e * i3 - l2) / (i2 * (i3 - i2)));
  const double big_k = std::comp_ellint_1(k);
  const double tau0 = std::ellint_1(k, std::asin(w0[1] / a2));

  const double e0 = w.energy().kinetic;
  double drift = 0.0, previous = w0[1], worst = 0.0;
  int flips = 0;
  while (w.time() < 30.0 - 1e-9) {
    w.step();
    const Body& b = w.body(id);
    drift = std::max(drift, std::abs(w.energy().kinetic - e0));
    const double w2 = (b.orientation().conjugate() * b.angularVelocity())[1];
    if ((w2 < 0) != (previous < 0)) {
      ++flips;
      const double t = w.time() - s.timestep * w2 / (w2 - previous);  // linear interpolation
      const double expected = (2.0 * flips * big_k - tau0) / lambda;
      worst = std::max(worst, std::abs(t - expected));
    }
    previous = w2;
  }
  std::printf("%d flips, worst time %.3g s, energy drift %.3g of %.6g J\n", flips, worst, drift,
              e0);
  EXPECT_GE(flips, 4);
  EXPECT_LT(worst, 1e-3);
  EXPECT_LT(drift, 1e-6 * e0);
}

// The heavy symmetric top in steady precession: a top of mass m, its centre at l from the fixed
// tip (a ball joint), tilted theta from the vertical, keeps theta and precesses at the constant
// rate W when its spin about its axis is w3 = (m g l + I1 W^2 cos(theta)) / (I3 W), I1 about the
// tip (Goldstein, Classical Mechanics, section 5.7).
// The top on a ball joint (its rows' curvature in closed form) and on a cone-twist joint without
// a cone (the same point rows, but a type whose curvature is measured by differences of its rows).
TEST(AccurateIntegrator, HeavyTopPrecessesSteadily) {
  for (const char* type : {"ball", "cone_twist"}) {
    WorldSettings s = accurateSettings(1e-3);
    World w(s);
    const double m = 1.0, l = 0.1, theta = 0.5, precession = 1.5;
    const double ia = 2e-3, i3 = 3e-3;  // about the centre: across and along the axis
    const double i1 = ia + m * l * l;   // across, about the tip
    const double g = 9.81;
    const double w3 =
        (m * g * l + i1 * precession * precession * std::cos(theta)) / (i3 * precession);
    const Vec3 axis(std::sin(theta), 0.0, std::cos(theta));  // at t = 0, in the x-z plane
    BodyDef d;
    d.name = "top";
    d.mass = m;
    d.inertia = Vec3(ia, ia, i3).asDiagonal();
    d.orientation = Quat::FromTwoVectors(Vec3::UnitZ(), axis);
    d.position = l * axis;
    // w = W z + (w3 - W cos(theta)) axis, so that w . axis = w3.
    const Vec3 omega = precession * Vec3::UnitZ() + (w3 - precession * std::cos(theta)) * axis;
    d.angular_velocity = omega;
    d.linear_velocity = omega.cross(d.position);
    const BodyId id = w.createBody(d);
    w.createJoint(type, JointDef{.name = "tip",
                                 .body1 = id,
                                 .anchor = Vec3::Zero(),
                                 .axis = axis,
                                 .axis2 = axis.cross(Vec3::UnitY()).normalized()});

    double tilt = 0.0, azimuth = 0.0;
    while (w.time() < 5.0 - 1e-9) {
      w.step();
      const Vec3 a = w.body(id).position().normalized();
      tilt = std::max(tilt, std::abs(std::acos(a.z()) - theta));
      // The axis's azimuth against W t, wrapped to (-pi, pi].
      const double expected = precession * w.time();
      const double phase =
          std::remainder(std::atan2(a.y(), a.x()) - expected, 2.0 * std::numbers::pi);
      azimuth = std::max(azimuth, std::abs(phase));
    }
    std::printf("%s: tilt off by %.3g rad, azimuth off by %.3g rad over 5 s\n", type, tilt,
                azimuth);
    EXPECT_EQ(w.lastIntegratorReport().bodies, 1) << type;  // the accurate integrator moved it
    EXPECT_LT(tilt, 1e-6) << type;
    EXPECT_LT(azimuth, 1e-6) << type;
  }
}

// An island switches cleanly: a ball falling free is an island of its own, moved by the accurate
// integrator (exactly on the parabola: the plain step's semi-implicit Euler is h g t / 2 off it);
// near the ground its contact rows make it take the step, which bounces it; once it has left the
// ground far enough to have no contact rows it is the accurate integrator's again, and rises to
// e^2 of its drop height.
TEST(AccurateIntegrator, AFallingBallSwitchesToTheStepAtTheGroundAndBack) {
  World w(accurateSettings(1e-3));
  w.createBody(test::groundPlane());
  BodyDef d;
  d.name = "ball";
  d.mass = 1.0;
  d.inertia = Vec3(4e-4, 4e-4, 4e-4).asDiagonal();
  const double radius = 0.05, drop = 1.0, e = 0.8, g = 9.81;
  d.position = Vec3(0, 0, radius + drop);
  d.shapes.push_back(ShapeDef{.type = ShapeType::Sphere, .radius = radius, .restitution = e});
  const BodyId ball = w.createBody(d);
  double fall = 0.0, apex = 0.0;
  bool touched = false, accurate_again = false;
  while (w.time() < 1.2 - 1e-9) {
    w.step();
    const double z = w.body(ball).position().z() - radius;
    const int accurate = w.lastIntegratorReport().bodies;
    if (!touched && accurate == 1) {
      fall = std::max(fall, std::abs(z - (drop - 0.5 * g * w.time() * w.time())));
    } else if (accurate == 0) {
      touched = true;
    } else if (touched) {
      accurate_again = true;
      apex = std::max(apex, z);
    }
  }
  std::printf("free fall off the parabola by %.3g m, apex %.4f m (e^2 H = %.4f m)\n", fall, apex,
              e * e * drop);
  EXPECT_LT(fall, 1e-12);
  EXPECT_TRUE(touched);
  EXPECT_TRUE(accurate_again);
  EXPECT_NEAR(apex, e * e * drop, 0.02 * e * e * drop);
}

// Springs, dampers, servos and coordinate forces act as forces in the accurate integrator: a block
// on a slider with a spring and a damper follows the damped oscillator's closed form
// x = A exp(-z w t) (cos(wd t) + z w / wd sin(wd t)), and with a constant coordinate force
// x = F t^2 / (2 m); a pendulum held out by a position servo settles where the servo's torque
// k (target - theta) balances gravity's m g l sin(theta).
TEST(AccurateIntegrator, SpringsServosAndForcesActAsForces) {
  WorldSettings s = accurateSettings(1e-3);
  s.gravity = Vec3::Zero();
  const double m = 2.0, k = 50.0, amplitude = 0.1;
  for (const double damping : {0.0, 2.0}) {
    World w(s);
    BodyDef d = test::boxBody("block", m, Vec3(0.1, 0.1, 0.1), Vec3(amplitude, 0, 0));
    d.shapes.clear();
    const BodyId block = w.createBody(d);
    JointDef j{
        .name = "rail", .body1 = block, .anchor = Vec3(amplitude, 0, 0), .axis = Vec3::UnitX()};
    j.coordinates[0].reference = amplitude;
    j.coordinates[0].spring = JointSpring{.stiffness = k, .damping = damping, .rest = 0.0};
    w.createJoint("slider", j);
    const double omega = std::sqrt(k / m), zeta = damping / (2.0 * std::sqrt(k * m));
    const double wd = omega * std::sqrt(1.0 - zeta * zeta);
    double worst = 0.0;
    while (w.time() < 5.0 - 1e-9) {
      w.step();
      ASSERT_EQ(w.lastIntegratorReport().bodies, 1);
      const double t = w.time();
      const double x = amplitude * std::exp(-zeta * omega * t) *
                       (std::cos(wd * t) + zeta * omega / wd * std::sin(wd * t));
      worst = std::max(worst, std::abs(w.body(block).position().x() - x));
    }
    std::printf("spring and damper (c = %g): %.3g m off the closed form over 5 s\n", damping,
                worst);
    EXPECT_LT(worst, 1e-8 * amplitude);
  }
  {
    World w(s);
    BodyDef d = test::boxBody("block", m, Vec3(0.1, 0.1, 0.1), Vec3::Zero());
    d.shapes.clear();
    const BodyId block = w.createBody(d);
    JointDef j{.name = "rail", .body1 = block, .anchor = Vec3::Zero(), .axis = Vec3::UnitX()};
    j.coordinates[0].force = Signal(3.0);
    w.createJoint("slider", j);
    while (w.time() < 2.0 - 1e-9) w.step();
    EXPECT_EQ(w.lastIntegratorReport().bodies, 1);
    EXPECT_NEAR(w.body(block).position().x(), 3.0 * 4.0 / (2.0 * m), 1e-12);
  }
  {
    WorldSettings g = accurateSettings(1e-3);
    World w(g);
    const double l = 0.5, stiffness = 40.0, target = 0.6;
    BodyDef d = test::boxBody("bob", 1.0, Vec3(0.05, 0.05, 0.05), Vec3(l, 0, 0));
    d.shapes.clear();
    const BodyId bob = w.createBody(d);
    JointDef j{.name = "shoulder", .body1 = bob, .anchor = Vec3::Zero(), .axis = -Vec3::UnitY()};
    j.coordinates[0].motor = JointMotor{.max_force = 100.0,
                                        .target_position = Signal(target),
                                        .stiffness = stiffness,
                                        .damping = 4.0};
    const JointId shoulder = w.createJoint("hinge", j);
    while (w.time() < 20.0 - 1e-9) w.step();
    EXPECT_EQ(w.lastIntegratorReport().bodies, 1);
    // The angle up from horizontal (axis -y: positive lifts +x up), and its balance.
    const double theta = w.jointCoordinates(shoulder)[0];
    const Body& b = w.body(bob);
    const double inertia = b.inertiaBody()(1, 1) + l * l;  // not needed for the balance
    (void)inertia;
    const double balance = stiffness * (target - theta) - 9.81 * l * std::cos(theta);
    std::printf("servo: theta %.9f rad, torque balance %.3g N m\n", theta, balance);
    EXPECT_LT(std::abs(balance), 1e-9);
  }
}

// The joints' forces over a frame are the momentum they gave: a 1 kg mass on a 1 m rod (a distance
// joint) swinging from horizontal, at 10 ms frames, each split into several Runge-Kutta steps: the
// reaction times h is m (v+ - v) - m g h, and along the rod at the frame's middle.
TEST(AccurateIntegrator, JointForcesAreTheMomentumTheyGave) {
  WorldSettings s = accurateSettings(0.01);
  World w(s);
  BodyDef d;
  d.name = "mass";
  d.mass = 1.0;
  d.inertia = Vec3(1e-4, 1e-4, 1e-4).asDiagonal();
  d.position = Vec3(1, 0, 0);
  const BodyId mass = w.createBody(d);
  const JointId rod = w.createJoint(
      "distance",
      JointDef{.name = "rod", .body1 = mass, .anchor = Vec3(1, 0, 0), .anchor2 = Vec3::Zero()});
  double worst = 0.0, largest = 0.0;
  while (w.time() < 3.0 - 1e-9) {
    const Vec3 v0 = w.body(mass).linearVelocity();
    w.step();
    const Vec3 given = w.body(mass).linearVelocity() - v0 - s.gravity * s.timestep;  // m = 1
    const Vec3 impulse = w.jointReaction(rod).force * s.timestep;
    worst = std::max(worst, (impulse - given).norm());
    largest = std::max(largest, given.norm());
  }
  std::printf("joint impulses off the momentum they gave by %.3g N s (largest %.3g N s)\n", worst,
              largest);
  EXPECT_LT(worst, 1e-9 * largest);
}

// Integrator "auto" on a pendulum: a 1 kg point mass on a 1 m massless rod (a hinge about z at the
// origin, gravity along -y), released `angle` from hanging.
World autoPendulum(IntegratorType type, double tolerance, double angle, double h) {
  WorldSettings s;
  s.timestep = h;
  s.gravity = Vec3(0, -9.81, 0);
  s.integrator = IntegratorSettings{.type = type, .tolerance = tolerance};
  World w(s);
  BodyDef d;
  d.name = "bob";
  d.mass = 1.0;
  d.inertia = Vec3(1e-4, 1e-4, 1e-4).asDiagonal();
  d.position = Vec3(std::sin(angle), -std::cos(angle), 0);
  const BodyId bob = w.createBody(d);
  w.createJoint(
      "hinge",
      JointDef{.name = "pivot", .body1 = bob, .anchor = Vec3::Zero(), .axis = Vec3::UnitZ()});
  return w;
}

double pendulumEnergy(const World& w) {
  const Body& b = w.body(w.bodyIds()[0]);
  return 0.5 * b.linearVelocity().squaredNorm() +
         0.5 * b.angularVelocity().dot(b.inertiaWorld() * b.angularVelocity()) +
         9.81 * b.position().y();
}

TEST(AutoIntegrator, KeepsTheAccurateIntegratorWhereOneStepAFrameHoldsTheTolerance) {
  // At tolerance 1e-6 one Runge-Kutta step of 10 ms holds a 1 m pendulum swinging 60 degrees:
  // "auto" moves it by the accurate integrator on every frame, as "accurate" does, and so keeps
  // its energy, where the step loses it.
  const double angle = std::numbers::pi / 3.0, h = 0.01;
  World a = autoPendulum(IntegratorType::Auto, 1e-6, angle, h);
  World accurate = autoPendulum(IntegratorType::Accurate, 1e-6, angle, h);
  World step = autoPendulum(IntegratorType::Step, 1e-6, angle, h);
  const double e0 = pendulumEnergy(a), exchanged = 9.81 * (1.0 - std::cos(angle));
  int frames_accurate = 0, frames = 0;
  double apart = 0.0;
  for (; a.time() < 20.0 - 1e-9; ++frames) {
    a.step();
    accurate.step();
    step.step();
    const IntegratorReport& r = a.lastIntegratorReport();
    if (r.bodies == 1 && r.steps == 1 && r.rejected == 0) ++frames_accurate;
    apart = std::max(
        apart, (a.body(a.bodyIds()[0]).position() - accurate.body(accurate.bodyIds()[0]).position())
                   .norm());
  }
  const double drift = std::abs(pendulumEnergy(a) - e0) / exchanged;
  const double step_drift = std::abs(pendulumEnergy(step) - e0) / exchanged;
  std::printf(
      "auto: %d of %d frames accurate, %.3g m from \"accurate\", energy drift %.3g of the "
      "exchanged (the step's %.3g)\n",
      frames_accurate, frames, apart, drift, step_drift);
  EXPECT_EQ(frames_accurate, frames);
  EXPECT_LT(apart, 1e-14);
  EXPECT_LT(drift, 1e-6);
  EXPECT_GT(step_drift, 100.0 * drift);
}

TEST(AutoIntegrator, GivesTheStepWhatOneStepCannotHoldAndTriesAgainLater) {
  // At tolerance 1e-12 one step of 10 ms misses on a pendulum released horizontal: the island
  // takes the step, and moves exactly as with "step" (the try is undone), trying again 8, 16, 32,
  // ... frames after each miss.
  const double angle = std::numbers::pi / 2.0, h = 0.01;
  // (Both take their first frame by the step: released at rest, a body's velocity is exact, and
  // "auto" hands the step a velocity half a step behind, as the step's own are.)
  World a = autoPendulum(IntegratorType::Step, 1e-12, angle, h);
  World step = autoPendulum(IntegratorType::Step, 1e-12, angle, h);
  a.step();
  step.step();
  a.settings().integrator.type = IntegratorType::Auto;
  std::vector<int> tries;
  double apart = 0.0;
  for (int frame = 0; frame < 600; ++frame) {
    a.step();
    step.step();
    const IntegratorReport& r = a.lastIntegratorReport();
    EXPECT_EQ(r.bodies, 0) << "frame " << frame;
    if (r.rejected > 0) tries.push_back(frame);
    apart = std::max(
        apart,
        (a.body(a.bodyIds()[0]).position() - step.body(step.bodyIds()[0]).position()).norm());
  }
  EXPECT_EQ(tries, (std::vector<int>{0, 8, 24, 56, 120, 248, 504}));
  EXPECT_EQ(apart, 0.0);
}

TEST(AutoIntegrator, ASavedStateCarriesTheWaits) {
  // Saved in the middle of a wait (tries at frames 0, 8, 24, 56, 120, ..., all missing), a world
  // tries again on the frames the one it was saved from does, and moves as it does.
  World a = autoPendulum(IntegratorType::Auto, 3e-11, std::numbers::pi / 4.0, 0.01);
  for (int i = 0; i < 30; ++i) a.step();
  const WorldState saved = a.saveState();
  std::vector<int> tries, again;
  std::vector<Vec3> path;
  for (int i = 30; i < 300; ++i) {
    a.step();
    if (a.lastIntegratorReport().rejected > 0) tries.push_back(i);
    path.push_back(a.body(a.bodyIds()[0]).position());
  }
  a.restoreState(saved);
  double apart = 0.0;
  for (int i = 30; i < 300; ++i) {
    a.step();
    if (a.lastIntegratorReport().rejected > 0) again.push_back(i);
    apart = std::max(
        apart, (a.body(a.bodyIds()[0]).position() - path[static_cast<std::size_t>(i - 30)]).norm());
  }
  EXPECT_EQ(tries, (std::vector<int>{56, 120, 248}));
  EXPECT_EQ(again, tries);
  EXPECT_EQ(apart, 0.0);
}

TEST(AccurateIntegrator, JointReactionsWithTheSoftSolver) {
  // The soft step measures its joints' loads in its substeps; those of an island the accurate
  // integrator moved are its impulses over the frame: a bob hanging still pulls its pivot with
  // its weight, m g = 9.81 N up on the bob, for either integrator.
  for (const IntegratorType type : {IntegratorType::Accurate, IntegratorType::Auto}) {
    World w = autoPendulum(type, 1e-10, 0.0, 0.01);
    w.settings().solver.type = SolverType::Soft;
    for (int i = 0; i < 10; ++i) w.step();
    const JointReaction r = w.jointReaction(w.jointIds()[0]);
    EXPECT_EQ(w.lastIntegratorReport().bodies, 1);
    EXPECT_LT((r.force - Vec3(0, 9.81, 0)).norm(), 1e-9) << integratorTypeName(type);
  }
}

}  // namespace
}  // namespace linx
