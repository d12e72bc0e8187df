// Serial joint (hinges and slides in series, a body with several joints in MJCF): the same motion
// as the joint types it can spell (a hinge, a universal joint, a cylindrical joint), an offset
// three-hinge chain that keeps its constraint, momentum and energy while it tumbles, a pendulum
// with armature that swings with the period of its closed form, and limits that stop motion.
#include "support.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>
#include <stdexcept>

namespace linx {
namespace {

constexpr double kPi = std::numbers::pi;

SerialAxis hinge(const Vec3& axis, const Vec3& anchor) {
  return SerialAxis{.linear = false, .axis = axis, .anchor = anchor};
}
SerialAxis slide(const Vec3& axis) {
  return SerialAxis{.linear = true, .axis = axis};
}

// Two boxes that tumble without gravity, joined by `type` with `def` (bodies filled in).
struct Tumble {
  World world;
  BodyId a, b;
  JointId joint;
};

Tumble tumble(const std::string& type, JointDef def) {
  WorldSettings s;
  s.gravity.setZero();
  Tumble t{World(s), {}, {}, {}};
  BodyDef a = test::boxBody("a", 2.0, Vec3(0.3, 0.2, 0.1), Vec3(0, 0, 0));
  a.angular_velocity = Vec3(1.0, -2.0, 0.5);
  BodyDef b = test::boxBody("b", 1.0, Vec3(0.1, 0.4, 0.2), Vec3(0, 0, -0.4));
  b.linear_velocity = Vec3(0.3, 0, 0);
  t.a = t.world.createBody(a);
  t.b = t.world.createBody(b);
  def.body1 = t.a;
  def.body2 = t.b;
  t.joint = t.world.createJoint(type, def);
  return t;
}

// Largest distance between the two worlds' bodies over `steps` steps, and between their joint
// coordinates (`order` maps the first world's coordinates onto the second's).
std::pair<double, double> largestDifference(Tumble& x, Tumble& y, int steps,
                                            std::vector<int> order) {
  double pose = 0.0, coordinate = 0.0;
  for (int i = 0; i < steps; ++i) {
    x.world.step();
    y.world.step();
    for (const auto& [p, q] : {std::pair{x.a, y.a}, std::pair{x.b, y.b}}) {
      pose = std::max(pose, (x.world.body(p).position() - y.world.body(q).position()).norm());
      pose = std::max(pose,
                      x.world.body(p).orientation().angularDistance(y.world.body(q).orientation()));
    }
    const JointCoordinates qx = x.world.jointCoordinates(x.joint);
    const JointCoordinates qy = y.world.jointCoordinates(y.joint);
    for (std::size_t k = 0; k < order.size(); ++k)
      coordinate = std::max(coordinate, std::abs(qx[static_cast<Eigen::Index>(k)] - qy[order[k]]));
  }
  return {pose, coordinate};
}

TEST(SerialJoint, TwoHingesThroughOnePointAreAUniversalJoint) {
  // axes[0] is fixed in body 2, axes[1] in body 1: the universal joint's axis2 and axis.
  const Vec3 anchor(0, 0, -0.2), a1(1, 1, 0), a2(1, -1, 0.5);
  Tumble universal =
      tumble("universal", JointDef{.name = "j", .anchor = anchor, .axis = a1, .axis2 = a2});
  Tumble serial =
      tumble("serial", JointDef{.name = "j", .axes = {hinge(a2, anchor), hinge(a1, anchor)}});
  const auto [pose, coordinate] = largestDifference(serial, universal, 2000, {1, 0});
  std::printf(
      "serial vs universal over 2 s: poses %.2e (m or rad), coordinates %.2e rad, "
      "joint error %.2e\n",
      pose, coordinate, serial.world.jointError(serial.joint));
  // Both exact, and both moved by the accurate integrator ("auto") to its tolerance. (With the
  // step their rows differ, the held directions and the error measures, which the correction of
  // its first-order drift sees: 2e-6, far below the drift itself.)
  EXPECT_LT(pose, 1e-9);
  EXPECT_LT(coordinate, 1e-9);
  EXPECT_LT(serial.world.jointError(serial.joint), 1e-9);
}

TEST(SerialJoint, ASlideAndAHingeOnOneAxisAreACylindricalJoint) {
  const Vec3 anchor(0.05, 0.02, -0.2), axis(0.2, 1, -0.3);
  Tumble cylindrical = tumble("cylindrical", JointDef{.name = "j", .anchor = anchor, .axis = axis});
  Tumble serial =
      tumble("serial", JointDef{.name = "j", .axes = {slide(axis), hinge(axis, anchor)}});
  const auto [pose, coordinate] = largestDifference(serial, cylindrical, 2000, {0, 1});
  std::printf("serial vs cylindrical over 2 s: poses %.2e, coordinates %.2e\n", pose, coordinate);
  EXPECT_LT(pose, 1e-9);
  EXPECT_LT(coordinate, 1e-9);
}

TEST(SerialJoint, OffsetHingesKeepTheConstraintMomentumAndEnergy) {
  // Three hinges at three different points (an ankle-like pair and a knee-like third, not
  // perpendicular): the joint's forces are internal, so the linear momentum stays to round-off,
  // the angular momentum and energy up to the step's first-order error, and the chain holds.
  Tumble t = tumble("serial", JointDef{.name = "j",
                                       .axes = {hinge(Vec3(0, 1, 0), Vec3(0, 0, -0.15)),
                                                hinge(Vec3(1, 0, 0.5), Vec3(0.02, 0, -0.25)),
                                                hinge(Vec3(0.3, 0.2, 1), Vec3(0, 0.03, -0.1))}});
  World& w = t.world;
  const auto momentum = [&] {
    Vec3 p = Vec3::Zero(), l = Vec3::Zero();
    for (const BodyId id : {t.a, t.b}) {
      const Body& body = w.body(id);
      p += body.mass() * body.linearVelocity();
      l += body.position().cross(body.mass() * body.linearVelocity()) + body.angularMomentum();
    }
    return std::pair{p, l};
  };
  const auto energy = [&] { return w.body(t.a).kineticEnergy() + w.body(t.b).kineticEnergy(); };
  const auto [p0, l0] = momentum();
  w.step();  // the starting velocities open the joint: the first step is an inelastic impact
  const double e1 = energy();
  double worst = 0.0, dp = 0.0, dl = 0.0, de = 0.0;
  for (int i = 0; i < 3000; ++i) {
    w.step();
    worst = std::max(worst, w.jointError(t.joint));
    const auto [p, l] = momentum();
    dp = std::max(dp, (p - p0).norm());
    dl = std::max(dl, (l - l0).norm() / l0.norm());
    de = std::max(de, std::abs(energy() - e1) / e1);
  }
  const JointCoordinates q = w.jointCoordinates(t.joint);
  std::printf(
      "3 s: joint error %.2e, momentum %.2e kg m/s, angular momentum %.2e, energy %.2e; "
      "coordinates %.3f %.3f %.3f rad\n",
      worst, dp, dl, de, q[0], q[1], q[2]);
  EXPECT_LT(worst, 1e-9);
  EXPECT_LT(dp, 1e-12);
  EXPECT_LT(dl, 1e-3);
  EXPECT_LT(de, 1e-3);
  EXPECT_EQ(q.size(), 3);
}

TEST(SerialJoint, ArmatureAddsItsInertiaToThePendulumsPeriod) {
  // A rod on one hinge about an oblique axis, with the armature A of a rotor on the hinge: it
  // swings as a physical pendulum whose moment about the axis is I + A (the exact, large-amplitude
  // period). The same armature on a hinge joint swings alike.
  const Vec3 pivot(0, 0, 1), axis = Vec3(1, 0.3, 0.1).normalized(), com(0, 0.5, 1.2);
  const double armature = 0.07;
  for (const std::string_view type : {"serial", "hinge"}) {
    WorldSettings s = test::solverSettings(SolverType::Auto);
    World w(s);
    BodyDef rod = test::boxBody("rod", 1.5, Vec3(0.05, 0.6, 0.05), com);
    const BodyId id = w.createBody(rod);
    CoordinateDef c{.armature = armature};
    JointDef def{.name = "pivot", .body1 = id, .anchor = pivot, .axis = axis, .coordinates = {c}};
    if (type == "serial") def.axes = {hinge(axis, pivot)};
    const JointId j = w.createJoint(type, def);
    const test::PendulumOnAxis bare =
        test::pendulumOnAxis(pivot, axis, com, w.body(id).inertiaWorld(), 1.5, s.gravity);
    // The rotor adds A to the moment about the axis: pendulumPeriod is proportional to the
    // square root of that moment, I_axis + m d^2.
    const Vec3 r = com - pivot;
    const double d = (r - r.dot(axis) * axis).norm();
    const double moment = axis.dot(w.body(id).inertiaWorld() * axis) + 1.5 * d * d;
    const double period = bare.period * std::sqrt((moment + armature) / moment);
    const test::Oscillation o = test::jointOscillation(w, j, 6000);
    std::printf("%s: period %.6f s, closed form %.6f s (%.2e relative; %.6f without armature)\n",
                std::string(type).c_str(), o.period, period, o.period / period - 1.0, bare.period);
    EXPECT_NEAR(o.period / period, 1.0, 2e-3) << type;
  }
}

TEST(SerialJoint, ArmatureAddsItsMassToASlidersPeriod) {
  // A block on a spring along an oblique slide, without gravity: period 2 pi sqrt((m + A) / k).
  const double m = 2.0, k = 300.0, armature = 0.5;
  const Vec3 axis = Vec3(1, 0.5, -0.2).normalized();
  for (const std::string_view type : {"serial", "slider"}) {
    WorldSettings s = test::solverSettings(SolverType::Auto);
    s.gravity.setZero();
    World w(s);
    BodyDef block = test::boxBody("block", m, Vec3(0.2, 0.1, 0.1), Vec3(0.1, 0.2, 0.3));
    block.linear_velocity = 0.4 * axis;
    const BodyId id = w.createBody(block);
    JointDef def{.name = "j", .body1 = id, .axis = axis};
    def.coordinates[0] = CoordinateDef{.spring = JointSpring{.stiffness = k}, .armature = armature};
    if (type == "serial") def.axes = {slide(axis)};
    const JointId j = w.createJoint(type, def);
    const double period = 2.0 * kPi * std::sqrt((m + armature) / k);
    const test::Oscillation o = test::jointOscillation(w, j, 3000);
    std::printf("%s: period %.6f s, closed form %.6f s (%.2e relative)\n",
                std::string(type).c_str(), o.period, period, o.period / period - 1.0);
    EXPECT_NEAR(o.period / period, 1.0, 1e-3) << type;
  }
}

TEST(SerialJoint, AnAppliedForceAcceleratesTheCoordinateAsNewtonSays) {
  // A torque T along a hinge (offset from the body's centre, without gravity) turns it with
  // theta = T t^2 / (2 I_pivot); a force table along a slide moves it by F t^2 / (2 (m + A)).
  const Vec3 pivot(0, 0, 1), axis = Vec3(0.3, 1, 0.2).normalized(), com(0.2, 0, 1.1);
  const double torque = 0.8, m = 1.5;
  for (const std::string_view type : {"serial", "hinge"}) {
    WorldSettings s = test::solverSettings(SolverType::Auto);
    s.gravity.setZero();
    World w(s);
    const BodyId id = w.createBody(test::boxBody("rod", m, Vec3(0.05, 0.6, 0.05), com));
    JointDef def{.name = "pivot", .body1 = id, .anchor = pivot, .axis = axis};
    def.coordinates[0].force = Signal(torque);
    if (type == "serial") def.axes = {hinge(axis, pivot)};
    const JointId j = w.createJoint(type, def);
    const Vec3 r = com - pivot;
    const double d = (r - r.dot(axis) * axis).norm();
    const double moment = axis.dot(w.body(id).inertiaWorld() * axis) + m * d * d;
    for (int i = 0; i < 1000; ++i) w.step();
    const double t = w.time(), expected = torque * t * t / (2.0 * moment);
    const double angle = w.jointCoordinates(j)[0];
    std::printf("%s: %.6f rad after %.1f s, closed form %.6f (%.2e relative)\n",
                std::string(type).c_str(), angle, t, expected, angle / expected - 1.0);
    // Symplectic Euler: theta_n = T h^2 n (n + 1) / (2 I), h / t above the closed form.
    EXPECT_NEAR(angle / expected, 1.0, 2e-3) << type;
  }
  WorldSettings s = test::solverSettings(SolverType::Auto);
  s.gravity.setZero();
  World w(s);
  const BodyId id = w.createBody(test::boxBody("block", m, Vec3(0.1, 0.1, 0.1), Vec3::Zero()));
  JointDef def{.name = "slide", .body1 = id, .axes = {slide(Vec3(1, 1, 0))}};
  def.coordinates[0].force = Signal({0.0, 1.0}, {2.0, 2.0});  // 2 N for the first second
  def.coordinates[0].armature = 0.5;
  const JointId j = w.createJoint("serial", def);
  for (int i = 0; i < 1000; ++i) w.step();
  // Symplectic Euler's own closed form: x_n = F h^2 n (n + 1) / (2 (m + A)).
  const double h = s.timestep, n = 1000.0;
  const double x = w.jointCoordinates(j)[0],
               expected = 2.0 * h * h * n * (n + 1) / (2.0 * (m + 0.5));
  std::printf("slide: %.9f m after 1 s, symplectic Euler's closed form %.9f (%.2e relative)\n", x,
              expected, x / expected - 1.0);
  EXPECT_NEAR(x / expected, 1.0, 1e-9);
}

TEST(SerialJoint, LimitsStopEachCoordinate) {
  // A body on a vertical slide then a hinge, released: it falls onto the slide's lower limit and
  // swings down onto the hinge's upper one, each held there.
  WorldSettings s = test::solverSettings(SolverType::Auto);
  World w(s);
  const BodyId id =
      w.createBody(test::boxBody("bob", 1.0, Vec3(0.5, 0.05, 0.05), Vec3(0.25, 0, 1)));
  JointDef def{.name = "j", .body1 = id};
  def.axes = {slide(Vec3::UnitZ()), hinge(Vec3::UnitY(), Vec3(0, 0, 1))};
  def.coordinates[0].limits = JointLimits{.lower = -0.3};
  def.coordinates[1].limits = JointLimits{.upper = 0.5};
  const JointId j = w.createJoint("serial", def);
  for (int i = 0; i < 3000; ++i) w.step();
  const JointCoordinates q = w.jointCoordinates(j);
  std::printf("resting at position %.6f m (limit -0.3), angle %.6f rad (limit 0.5), error %.2e\n",
              q[0], q[1], w.jointError(j));
  EXPECT_NEAR(q[0], -0.3, 1e-3);
  EXPECT_NEAR(q[1], 0.5, 1e-3);
  EXPECT_LT(w.jointError(j), 1e-6);
}

TEST(SerialJoint, CoordinatesAreSetAndReadBack) {
  // A model built straight and set bent (World::setJointCoordinate, a scene's "initial"): each
  // coordinate lands where it is set, the others keep theirs, and the chain stays closed.
  Tumble t = tumble(
      "serial", JointDef{.name = "j",
                         .axes = {hinge(Vec3(0, 1, 0), Vec3(0, 0, -0.15)), slide(Vec3(0.2, 0, 1)),
                                  hinge(Vec3(0.3, 0.2, 1), Vec3(0, 0.03, -0.1))}});
  const double goal[] = {0.7, -0.05, 2.5};
  for (int i = 0; i < 3; ++i) t.world.setJointCoordinate(t.joint, i, goal[i]);
  const JointCoordinates q = t.world.jointCoordinates(t.joint);
  std::printf("set to %.12f %.12f %.12f, joint error %.2e\n", q[0], q[1], q[2],
              t.world.jointError(t.joint));
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(q[i], goal[i], 1e-9);
  EXPECT_LT(t.world.jointError(t.joint), 1e-9);
}

TEST(SerialJoint, RefusesDependentOrMissingAxes) {
  World w;
  const BodyId id = w.createBody(test::boxBody("b", 1.0, Vec3(0.1, 0.1, 0.1), Vec3::Zero()));
  const auto refused = [&](JointDef def) {
    def.body1 = id;
    try {
      w.createJoint("serial", def);
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  EXPECT_NE(refused(JointDef{.name = "j"}).find("1 to 6 axes"), std::string::npos);
  EXPECT_NE(refused(JointDef{.name = "j",
                             .axes = {hinge(Vec3::UnitX(), Vec3::Zero()),
                                      hinge(Vec3::UnitX(), Vec3::Zero())}})
                .find("axes[1]: adds no motion"),
            std::string::npos);
  EXPECT_NE(refused(JointDef{.name = "j", .axes = {slide(Vec3::Zero())}}).find("axes[0].axis"),
            std::string::npos);
  JointDef limited{.name = "j", .axes = {slide(Vec3::UnitX())}};
  limited.coordinates[1].limits = JointLimits{};
  EXPECT_NE(refused(limited).find("coordinates[1]: a serial joint has 1 free"), std::string::npos);
}

}  // namespace
}  // namespace linx
