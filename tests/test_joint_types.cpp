// The joint types with several free coordinates (cylindrical, hinge-2, universal, and the
// one-coordinate hinge and slider) against their own definitions and closed forms:
// - every coordinate row's J u is the time derivative of the coordinate it reports, for any motion
//   the joint allows (finite differences at random poses);
// - a cylindrical joint's body slides and spins freely at constant rates, its sprung position
//   oscillates with period 2 pi sqrt(m / k), a limit on its angle stops it;
// - a hinge-2 wheel hangs on its suspension spring with the static deflection m g / k and the
// period
//   of a mass on a spring, steers to a servo's target, and spins at its motor's rate.
#include "random_state.hpp"
#include "support.hpp"

#include "joints/row_parts.hpp"
#include "math/rotation.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <optional>
#include <random>
#include <vector>

namespace linx {
namespace {

constexpr double kG = 9.81;

BodyState advance(const BodyState& s, double dt) {
  return BodyState{Pose{s.pose.position + dt * s.v, math::integrate(s.pose.orientation, s.w, dt)},
                   s.v, s.w};
}

Eigen::Matrix<double, 12, 1> velocities(const BodyState& b1, const BodyState& b2) {
  Eigen::Matrix<double, 12, 1> u;
  u << b1.v, b1.w, b2.v, b2.w;
  return u;
}

Eigen::Matrix<double, 1, 12> jacobian(const Row& r) {
  Eigen::Matrix<double, 1, 12> j;
  j << r.Ja.transpose(), r.Jb.transpose();
  return j;
}

// |d(phi)/dt - J u| of a one-row joint's row: its central difference along the bodies' motion
// against its Jacobian.
double firstRowRateMiss(const Joint& joint, const BodyState& b1, const BodyState& b2) {
  const auto row = [&](const BodyState& s1, const BodyState& s2) {
    std::vector<Row> rows(static_cast<std::size_t>(joint.maxRows()));
    joint.fill(JointContext{s1, s2, 0.01}, rows);
    return rows[0];
  };
  constexpr double eps = 1e-6;
  const double rate = (row(advance(b1, eps), advance(b2, eps)).phi -
                       row(advance(b1, -eps), advance(b2, -eps)).phi) /
                      (2 * eps);
  return std::abs(rate - jacobian(row(b1, b2)) * velocities(b1, b2));
}

TEST(JointTypes, CoordinateRowsAreTheRatesOfTheCoordinates) {
  // At a random pose of creation, random velocities projected onto what the joint allows
  // (J_eq u = 0): the coordinates' finite-difference rates equal their rows' J u. Friction on
  // every coordinate makes fill() write each coordinate's row.
  std::mt19937 rng(3);
  int checked = 0;
  for (const JointTypeInfo& type : jointTypes()) {
    if (type.freeCoordinates() == 0) continue;
    for (int trial = 0; trial < 20; ++trial) {
      BodyState b1 = test::randomState(rng), b2 = test::randomState(rng);
      JointDef def{.name = "j", .anchor = test::randomVec(rng, 1.0)};
      def.axis = test::randomVec(rng, 1.0);
      def.axis2 = def.axis.unitOrthogonal();
      if (type.usesAxes())  // a serial joint: a hinge, a slide and a hinge, anywhere
        def.axes = {{false, test::randomVec(rng, 1.0), test::randomVec(rng, 1.0)},
                    {true, test::randomVec(rng, 1.0), Vec3::Zero()},
                    {false, test::randomVec(rng, 1.0), test::randomVec(rng, 1.0)}};
      const int free = type.freeCoordinates(def);
      for (int i = 0; i < free; ++i)  // a ball joint's angle takes no friction: not smooth at 0
        if (!type.coordinates[static_cast<std::size_t>(i)].limits_only)
          def.coordinates[static_cast<std::size_t>(i)].friction = 1.0;
      std::unique_ptr<Joint> joint = makeJoint(type.name, def, b1, b2);
      // A generic joint constrains nothing of itself: every pose is one it allows, so it is
      // checked away from its pose of creation (angles up to a radian, ry off gimbal lock).
      if (type.name == "generic") {
        b1.pose.orientation = math::expMap(test::randomVec(rng, 0.6)) * b1.pose.orientation;
        b1.pose.position += test::randomVec(rng, 0.5);
      }
      // A cone-twist joint allows any turn about its anchor.
      if (type.name == "cone_twist") {
        const Quat turn = math::expMap(test::randomVec(rng, 1.0));
        b1.pose.position = *def.anchor + turn * (b1.pose.position - *def.anchor);
        b1.pose.orientation = turn * b1.pose.orientation;
      }
      std::vector<Row> rows(static_cast<std::size_t>(joint->maxRows()));
      rows.resize(static_cast<std::size_t>(joint->fill(JointContext{b1, b2, 0.01}, rows)));

      Eigen::MatrixXd eq(0, 12);
      for (const Row& r : rows) {
        if (r.key >= static_cast<std::uint64_t>(joints::coordinateSlot(0, 0))) continue;
        eq.conservativeResize(eq.rows() + 1, 12);
        eq.row(eq.rows() - 1) = jacobian(r);
      }
      Eigen::Matrix<double, 12, 1> u = velocities(b1, b2);
      u -= eq.transpose() * (eq * eq.transpose()).ldlt().solve(eq * u);
      b1.v = u.segment<3>(0), b1.w = u.segment<3>(3), b2.v = u.segment<3>(6),
      b2.w = u.segment<3>(9);

      constexpr double eps = 1e-6;
      const JointCoordinates rate = (joint->coordinates(advance(b1, eps), advance(b2, eps)) -
                                     joint->coordinates(advance(b1, -eps), advance(b2, -eps))) /
                                    (2 * eps);
      for (int i = 0; i < free; ++i) {
        if (type.coordinates[static_cast<std::size_t>(i)].limits_only) continue;  // test_ball_joint
        const auto row = std::find_if(rows.begin(), rows.end(), [&](const Row& r) {
          return r.key == static_cast<std::uint64_t>(joints::coordinateSlot(i, 4));
        });
        ASSERT_NE(row, rows.end()) << type.name << " coordinate " << i;
        EXPECT_NEAR(rate[i], jacobian(*row) * u, 1e-7)
            << type.name << " " << type.coordinates[static_cast<std::size_t>(i)].name << " trial "
            << trial;
        ++checked;
      }
    }
  }
  // slider, hinge, universal, cylindrical, hinge2, cone-twist, planar, generic, spring, serial
  EXPECT_EQ(checked, 20 * (1 + 1 + 2 + 2 + 3 + 1 + 3 + 6 + 1 + 3));
}

WorldSettings settings(bool gravity) {
  WorldSettings s;
  s.timestep = 1e-3;
  s.sleep.enabled = false;
  if (!gravity) s.gravity.setZero();
  return s;
}

// A 2 kg box on a cylindrical joint to the world along a tilted axis through its centre.
struct Piston {
  World world;
  BodyId box;
  JointId joint;
  Vec3 axis;
  double mass = 2.0, inertia = 0.0;  // about the axis
};

Piston makePiston(bool gravity, const CoordinateDef& position, const CoordinateDef& angle,
                  double v0, double w0) {
  Piston p{World(settings(gravity)), {}, {}, Vec3(1, 2, 2).normalized()};
  BodyDef d = test::boxBody("box", p.mass, Vec3(0.3, 0.3, 0.3), Vec3(0, 0, 1));  // a cube
  p.inertia = p.mass * 0.3 * 0.3 / 6.0;  // a cube's, about any axis through its centre
  d.linear_velocity = v0 * p.axis + Vec3(0.4, -0.2, 0.1).cross(p.axis);  // and some across it
  d.angular_velocity = w0 * p.axis + Vec3(0.3, 0.1, -0.5).cross(p.axis);
  p.box = p.world.createBody(d);
  JointDef def{.name = "piston", .body1 = p.box, .anchor = d.position, .axis = p.axis};
  def.coordinates[0] = position;
  def.coordinates[1] = angle;
  p.joint = p.world.createJoint("cylindrical", def);
  return p;
}

TEST(Cylindrical, SlidesAndSpinsFreelyAlongItsAxis) {
  // The first step removes the velocities across the axis (an inelastic impulse); then the body
  // slides at v0 and spins at w0: s = v0 t, theta = w0 t.
  const double v0 = 0.7, w0 = -1.3;
  Piston p = makePiston(false, {}, {}, v0, w0);
  double worst = 0.0;
  for (int n = 1; n <= 1000; ++n) {
    p.world.step();
    const JointCoordinates q = p.world.jointCoordinates(p.joint);
    const double t = p.world.time();
    worst = std::max({worst, std::abs(q[0] - v0 * t), std::abs(q[1] - w0 * t)});
  }
  std::printf("s, theta within %.2e of v0 t, w0 t; joint error %.2e\n", worst,
              p.world.maxJointError());
  EXPECT_LT(worst, 1e-9);
  EXPECT_LT(p.world.maxJointError(), 1e-9);
}

TEST(Cylindrical, SprungPositionOscillatesAndALimitStopsTheAngle) {
  // Position: m s'' = -k s from s = 0, s' = v0: s = (v0 / omega) sin(omega t), 100 steps a
  // period; the angle meanwhile spins at w0 until its upper limit of 1 rad stops it.
  const double period = 0.1, v0 = 0.5, w0 = 2.0;
  const double omega = 2.0 * M_PI / period, k = 2.0 * omega * omega;
  Piston p = makePiston(false, CoordinateDef{.spring = JointSpring{.stiffness = k}},
                        CoordinateDef{.limits = JointLimits{-kInfinity, 1.0}}, v0, w0);
  double highest = 0.0, highest_angle = 0.0;
  while (p.world.time() < 10.0 * period - 1e-9) {
    p.world.step();
    const JointCoordinates q = p.world.jointCoordinates(p.joint);
    highest = std::max(highest, std::abs(q[0]));
    highest_angle = std::max(highest_angle, q[1]);
  }
  std::printf("amplitude %.6f m (closed form %.6f), angle stopped at %.9f rad\n", highest,
              v0 / omega, highest_angle);
  EXPECT_NEAR(highest / (v0 / omega), 1.0, 5e-3);
  EXPECT_NEAR(highest_angle, 1.0, 1e-9);
  EXPECT_NEAR(p.world.jointCoordinates(p.joint)[1], 1.0, 1e-6);
}

// A 10 kg wheel on a hinge-2 to the world (the chassis): axle along y, steering axis vertical.
struct Wheel {
  World world;
  BodyId wheel;
  JointId joint;
};

Wheel makeWheel(const CoordinateDef& wheel, const CoordinateDef& steering,
                const CoordinateDef& suspension) {
  Wheel w{World(settings(true)), {}, {}};
  w.wheel = w.world.createBody(test::boxBody("wheel", 10.0, Vec3(0.6, 0.2, 0.6), Vec3(0, 0, 0.5)));
  JointDef def{.name = "hub",
               .body1 = w.wheel,
               .anchor = Vec3(0, 0, 0.5),
               .axis = Vec3::UnitY(),
               .axis2 = Vec3::UnitZ()};
  def.coordinates[0] = wheel;
  def.coordinates[1] = steering;
  def.coordinates[2] = suspension;
  w.joint = w.world.createJoint("hinge2", def);
  return w;
}

TEST(Hinge2, WheelHangsOnItsSuspensionSpring) {
  // Released at the spring's rest: s oscillates about -m g / k between 0 and -2 m g / k with
  // period 2 pi sqrt(m / k).
  const double m = 10.0, k = 4e4;
  Wheel w = makeWheel({}, {}, CoordinateDef{.spring = JointSpring{.stiffness = k}});
  const double period = 2.0 * M_PI * std::sqrt(m / k), sag = m * kG / k;
  double lowest = 0.0, sum = 0.0;
  int steps = 0;
  while (w.world.time() < 10.0 * period) {
    w.world.step();
    const double s = w.world.jointCoordinates(w.joint)[2];
    lowest = std::min(lowest, s);
    sum += s;
    ++steps;
  }
  std::printf("lowest %.6f m (closed form %.6f), mean %.6f (%.6f), joint error %.2e\n", lowest,
              -2.0 * sag, sum / steps, -sag, w.world.maxJointError());
  EXPECT_NEAR(lowest / (-2.0 * sag), 1.0, 5e-3);
  EXPECT_NEAR(sum / steps / -sag, 1.0, 2e-2);  // the mean over whole periods
  EXPECT_LT(w.world.maxJointError(), 1e-9);
}

TEST(Hinge2, SteersToTheServoTargetWhileTheMotorSpinsTheWheel) {
  Wheel w = makeWheel(
      CoordinateDef{.motor = JointMotor{.target_velocity = 10.0}},
      CoordinateDef{.motor =
                        JointMotor{.target_position = 0.3, .stiffness = 500.0, .damping = 60.0}},
      CoordinateDef{.limits = JointLimits{0.0, 0.0}});
  for (int n = 0; n < 2000; ++n) w.world.step();
  const JointCoordinates q = w.world.jointCoordinates(w.joint);
  const Vec3 spin = w.world.body(w.wheel).angularVelocity();
  const Vec3 axle = w.world.body(w.wheel).orientation() * Vec3::UnitY();
  std::printf("wheel %.6f rad, steering %.9f rad, suspension %.2e m, axle rate %.9f rad/s\n", q[0],
              q[1], q[2], spin.dot(axle));
  EXPECT_NEAR(q[1], 0.3, 1e-6);  // settled on the target
  EXPECT_NEAR(spin.dot(axle), 10.0, 1e-6);
  EXPECT_NEAR(q[2], 0.0, 1e-6);  // the suspension locked by its limits
  EXPECT_NEAR(axle.dot(Vec3(-std::sin(0.3), std::cos(0.3), 0)), 1.0, 1e-9);  // steered by 0.3
  EXPECT_LT(w.world.maxJointError(), 1e-9);
}

// A 1 kg ball (radius 2 cm) at (x0, 0, z0), tied to the world point (0, 0, 2) by a distance joint.
struct Tether {
  World world;
  BodyId ball;
  JointId joint;
};

Tether makeTether(const Vec3& start, std::optional<double> length, bool rope) {
  Tether t{World(settings(true)), {}, {}};
  BodyDef d = test::boxBody("ball", 1.0, Vec3(0.04, 0.04, 0.04), start);
  t.ball = t.world.createBody(d);
  t.joint = t.world.createJoint("distance", JointDef{.name = "rod",
                                                     .body1 = t.ball,
                                                     .anchor2 = Vec3(0, 0, 2),
                                                     .length = length,
                                                     .rope = rope});
  return t;
}

TEST(Distance, RodPendulumSwingsWithThePointMassPeriod) {
  // The rod holds the body's centre: its own rotation is free, so it swings as a point mass,
  // T = 4 sqrt(L / g) K(sin(theta0 / 2)).
  const double length = 1.0, theta0 = 0.5;
  Tether t = makeTether(Vec3(length * std::sin(theta0), 0, 2 - length * std::cos(theta0)),
                        std::nullopt, false);
  const double period = test::pendulumPeriod(length * length, 1.0, kG, length, theta0);
  double last = 1.0, first = -1.0, crossing = -1.0, worst = 0.0;
  int crossings = 0;
  while (t.world.time() < 5.0 * period) {
    t.world.step();
    const double x = t.world.body(t.ball).position().x();
    worst = std::max(worst, std::abs(t.world.jointCoordinates(t.joint)[0] - length));
    if (last > 0.0 && x <= 0.0) {
      crossing = t.world.time() - t.world.settings().timestep * x / (x - last);
      if (first < 0.0) first = crossing;
      ++crossings;
    }
    last = x;
  }
  const double measured = (crossing - first) / (crossings - 1);
  std::printf("period %.6f s (closed form %.6f), length kept to %.2e m\n", measured, period, worst);
  EXPECT_NEAR(measured / period, 1.0, 1e-3);
  EXPECT_LT(worst, 1e-9);
}

TEST(Distance, RopeFallsSlackThenHoldsTaut) {
  // 0.5 m of slack: free fall (symplectic Euler: z_n = z0 - h^2 g n (n + 1) / 2) until the rope is
  // taut, which stops the ball there (an inelastic rope) and holds it at its length.
  Tether t = makeTether(Vec3(0, 0, 1.5), 1.0, true);
  const double h = t.world.settings().timestep;
  double worst_fall = 0.0, longest = 0.0;
  for (int n = 1; n <= 1000; ++n) {
    t.world.step();
    const double z = t.world.body(t.ball).position().z();
    const double free = 1.5 - 0.5 * h * h * kG * n * (n + 1.0);
    if (free > 1.0 + 1e-3) worst_fall = std::max(worst_fall, std::abs(z - free));
    longest = std::max(longest, t.world.jointCoordinates(t.joint)[0]);
  }
  std::printf("free fall within %.2e m, longest %.12f m, hangs at %.9f m\n", worst_fall, longest,
              t.world.body(t.ball).position().z());
  EXPECT_LT(worst_fall, 1e-12);
  EXPECT_LT(longest, 1.0 + 1e-9);
  EXPECT_NEAR(t.world.body(t.ball).position().z(), 1.0, 1e-9);
  EXPECT_LT(t.world.body(t.ball).linearVelocity().norm(), 1e-9);
}

TEST(ConeTwist, ConeRowIsTheRateOfItsConstraintAnywhere) {
  // Body 1 turned about the anchor by up to a radian and a half: the cone row (at, near or past
  // the elliptical cone) has J u = dC/dt by finite differences, for any velocities.
  std::mt19937 rng(17);
  int checked = 0;
  for (int trial = 0; trial < 200; ++trial) {
    const BodyState c1 = test::randomState(rng), c2 = test::randomState(rng);
    const Vec3 anchor = test::randomVec(rng, 1.0), axis = test::randomVec(rng, 1.0);
    const JointDef def{.name = "c",
                       .anchor = anchor,
                       .axis = axis,
                       .axis2 = axis.unitOrthogonal(),
                       .cone = ConeLimit{0.3, 0.7}};
    std::unique_ptr<Joint> joint = makeJoint("cone_twist", def, c1, c2);
    const Quat turn = math::expMap(test::randomVec(rng, 1.5));
    BodyState b1 = c1;
    b1.pose.position = anchor + turn * (c1.pose.position - anchor);
    b1.pose.orientation = turn * c1.pose.orientation;
    const auto coneRow = [&](const BodyState& s1, const BodyState& s2) -> std::optional<Row> {
      std::vector<Row> rows(static_cast<std::size_t>(joint->maxRows()));
      rows.resize(static_cast<std::size_t>(joint->fill(JointContext{s1, s2, 1e-9}, rows)));
      for (const Row& r : rows)
        if (r.key == 3) return r;
      return std::nullopt;
    };
    const std::optional<Row> now = coneRow(b1, c2);
    if (!now) continue;  // well inside the cone: no row
    constexpr double eps = 1e-6;
    const std::optional<Row> ahead = coneRow(advance(b1, eps), advance(c2, eps));
    const std::optional<Row> behind = coneRow(advance(b1, -eps), advance(c2, -eps));
    ASSERT_TRUE(ahead && behind);
    const double rate = (ahead->phi - behind->phi) / (2 * eps);
    EXPECT_NEAR(
        rate,
        jacobian(*now) * (Eigen::Matrix<double, 12, 1>() << b1.v, b1.w, c2.v, c2.w).finished(),
        1e-6)
        << "trial " << trial;
    ++checked;
  }
  EXPECT_GT(checked, 100);
}

// A 1 kg bar hanging 0.5 m below a cone-twist joint (twist axis down the bar), pushed sideways.
struct Shoulder {
  World world;
  BodyId arm;
  JointId joint;
};

Shoulder makeShoulder(const Vec3& push, const Vec3& spin, const CoordinateDef& twist) {
  Shoulder s{World(settings(true)), {}, {}};
  BodyDef d = test::boxBody("arm", 1.0, Vec3(0.04, 0.04, 0.5), Vec3(0, 0, 0.75));
  d.linear_velocity = push;
  d.angular_velocity = spin;
  s.arm = s.world.createBody(d);
  JointDef def{.name = "shoulder",
               .body1 = s.arm,
               .anchor = Vec3(0, 0, 1),
               .axis = Vec3(0, 0, -1),
               .axis2 = Vec3::UnitX(),
               .cone = ConeLimit{0.3, 0.6}};
  def.coordinates[0] = twist;
  s.joint = s.world.createJoint("cone_twist", def);
  return s;
}

TEST(ConeTwist, SwingStopsOnTheEllipseInEachDirection) {
  // Pushed towards x (the cone's swing1, 0.3 rad) and towards y (swing2, 0.6 rad), hard enough to
  // pass them freely: the swing stops at the bound.
  for (const auto& [push, bound] : {std::pair{Vec3(3, 0, 0), 0.3}, std::pair{Vec3(0, 3, 0), 0.6}}) {
    Shoulder s = makeShoulder(push, Vec3::Zero(), {});
    double widest = 0.0;
    for (int n = 0; n < 1000; ++n) {
      s.world.step();
      widest = std::max(widest, s.world.jointCoordinates(s.joint)[1]);
    }
    std::printf("swing stopped at %.9f rad (bound %.1f), joint error %.2e\n", widest, bound,
                s.world.maxJointError());
    EXPECT_NEAR(widest, bound, 1e-6);
  }
}

TEST(ConeTwist, TwistHasItsOwnLimitsAndMotor) {
  Shoulder limited = makeShoulder(Vec3::Zero(), Vec3(0, 0, -4.0),  // spinning about the bar
                                  CoordinateDef{.limits = JointLimits{-0.5, 0.5}});
  double widest = 0.0;
  for (int n = 0; n < 1000; ++n) {
    limited.world.step();
    widest = std::max(widest, limited.world.jointCoordinates(limited.joint)[0]);
  }
  EXPECT_NEAR(widest, 0.5, 1e-6);  // spinning positively about the twist axis (0, 0, -1)
  Shoulder driven = makeShoulder(Vec3::Zero(), Vec3::Zero(),
                                 CoordinateDef{.motor = JointMotor{.target_velocity = 1.5}});
  for (int n = 0; n < 1000; ++n) driven.world.step();
  EXPECT_NEAR(driven.world.jointCoordinates(driven.joint)[0], 1.5, 1e-9);
  EXPECT_LT(driven.world.jointCoordinates(driven.joint)[1], 1e-9);  // no swing
}

// Locks for a generic joint's coordinates, by index (x, y, z, rx, ry, rz).
JointDef genericDef(BodyId body, const Vec3& anchor, std::initializer_list<int> locked) {
  JointDef def{.name = "six",
               .body1 = body,
               .anchor = anchor,
               .axis = Vec3(1, 0, 1).normalized(),  // x: tilted, so that nothing is world-aligned
               .axis2 = Vec3(0, 1, 0)};
  for (const int k : locked) def.coordinates[static_cast<std::size_t>(k)].locked = true;
  return def;
}

TEST(Generic, AsAHingeSwingsWithThePhysicalPendulumPeriod) {
  // x, y, z, rx, ry locked: a hinge about the joint's z = x cross y = (-1, 0, 1) / sqrt 2, tilted
  // 45 degrees from the vertical: gravity's share across it is g cos 45.
  World world(settings(true));
  const double m = 2.0, len = 0.6;
  const Vec3 axis = Vec3(-1, 0, 1).normalized();
  // A bar along the joint's x, hinged at one end, released 0.4 rad about the axis from hanging.
  const double theta0 = 0.4;
  const Vec3 down = Vec3(0, 0, -1) - axis * axis.dot(Vec3(0, 0, -1));  // hanging, across the axis
  const Vec3 start = Eigen::AngleAxisd(theta0, axis) * down.normalized();
  BodyDef d = test::boxBody("bar", m, Vec3(len, 0.02, 0.02), 0.5 * len * start);
  d.orientation = Quat::FromTwoVectors(Vec3::UnitX(), start);
  const BodyId bar = world.createBody(d);
  const JointId j = world.createJoint("generic", genericDef(bar, Vec3::Zero(), {0, 1, 2, 3, 4}));
  const double g_across = kG * down.norm();
  const double period = test::pendulumPeriod(m * len * len / 3.0, m, g_across, 0.5 * len, theta0);
  const double h = world.settings().timestep;
  double last = world.jointCoordinates(j)[5], crossing = -1.0, first = -1.0, worst = 0.0;
  int crossings = 0;
  while (world.time() < 5.0 * period) {
    world.step();
    const JointCoordinates q = world.jointCoordinates(j);
    worst = std::max({worst, q.head<5>().cwiseAbs().maxCoeff()});
    const double angle = q[5] + theta0;  // the swing from hanging (rz is zero at the release)
    if (last + theta0 > 0.0 && angle <= 0.0) {
      crossing = world.time() - h * angle / (angle - (last + theta0));
      if (first < 0.0) first = crossing;
      ++crossings;
    }
    last = q[5];
  }
  const double measured = (crossing - first) / (crossings - 1);
  std::printf("period %.6f s (closed form %.6f), locked coordinates within %.2e\n", measured,
              period, worst);
  EXPECT_NEAR(measured / period, 1.0, 1e-3);
  EXPECT_LT(worst, 1e-9);
}

TEST(Generic, AsAPlanarJointMovesFreelyInItsPlane) {
  // z, rx, ry locked: body 1 slides in the joint's x-y plane and turns about z. Without gravity,
  // after the first step has removed the velocities out of the plane, x, y and rz grow at
  // constant rates (the anchor at the body's centre: no coupling).
  World world(settings(false));
  BodyDef d = test::boxBody("puck", 1.0, Vec3(0.2, 0.2, 0.2), Vec3(0.1, 0.2, 0.3));  // a cube
  const Mat3 frame =
      (Mat3() << Vec3(1, 0, 1).normalized(), Vec3(0, 1, 0), Vec3(-1, 0, 1).normalized()).finished();
  d.linear_velocity = frame * Vec3(0.3, -0.4, 0.25);
  d.angular_velocity = frame * Vec3(0.5, -0.2, 1.1);
  const BodyId puck = world.createBody(d);
  const JointId j = world.createJoint("generic", genericDef(puck, d.position, {2, 3, 4}));
  double worst = 0.0;
  for (int n = 0; n < 1000; ++n) {
    world.step();
    const JointCoordinates q = world.jointCoordinates(j);
    const double t = world.time();
    Eigen::Matrix<double, 6, 1> exact;
    exact << 0.3 * t, -0.4 * t, 0, 0, 0, 1.1 * t;
    worst = std::max(worst, (q - exact).cwiseAbs().maxCoeff());
  }
  std::printf("x, y, rz at their rates and z, rx, ry at zero to %.2e\n", worst);
  EXPECT_LT(worst, 1e-9);
}

TEST(Generic, LimitOnATranslationStopsIt) {
  World world(settings(true));
  const BodyId b = world.createBody(test::boxBody("b", 1.0, Vec3(0.1, 0.1, 0.1), Vec3(0, 0, 1)));
  JointDef def = genericDef(b, Vec3(0, 0, 1), {1, 2, 3, 4, 5});  // only x free: a slider
  def.coordinates[0].limits = JointLimits{-0.25, 0.25};
  const JointId j = world.createJoint("generic", def);
  for (int n = 0; n < 2000; ++n) world.step();
  // Down the x axis (1, 0, 1) / sqrt 2 gravity pulls towards negative x, onto the lower limit.
  EXPECT_NEAR(world.jointCoordinates(j)[0], -0.25, 1e-9);
  EXPECT_LT(world.maxJointError(), 1e-9);
}

TEST(Planar, PuckSlidesDownItsTiltedPlaneAtGSinAlpha) {
  // The plane's y rises at alpha = 0.3 rad: y'' = -g sin(alpha), x and the angle stay at zero;
  // symplectic Euler's y_n with the step, the motion's own with "auto".
  for (const IntegratorType integrator : {IntegratorType::Step, IntegratorType::Auto}) {
    WorldSettings s = settings(true);
    s.integrator.type = integrator;
    World world(s);
    const double alpha = 0.3;
    BodyDef d = test::boxBody("puck", 1.0, Vec3(0.2, 0.2, 0.05), Vec3(0, 0, 1));
    // Lying on the plane (its thin side along the normal, a principal axis: a spin about it
    // stays), spinning on it.
    d.orientation = Quat(Eigen::AngleAxisd(alpha, Vec3::UnitX()));
    d.angular_velocity = Vec3(0, -std::sin(alpha), std::cos(alpha)) * 0.7;
    const BodyId puck = world.createBody(d);
    const JointId j =
        world.createJoint("planar", JointDef{.name = "table",
                                             .body1 = puck,
                                             .anchor = d.position,
                                             .axis = Vec3::UnitX(),
                                             .axis2 = Vec3(0, std::cos(alpha), std::sin(alpha))});
    const double h = world.settings().timestep, a = -kG * std::sin(alpha);
    double worst = 0.0;
    for (int n = 1; n <= 1000; ++n) {
      world.step();
      const JointCoordinates q = world.jointCoordinates(j);
      const Vec3 exact(0.0, test::distanceFromRest(integrator, a, h, n), 0.7 * world.time());
      worst = std::max(worst, (q - exact).cwiseAbs().maxCoeff());
    }
    std::printf("%s: x, y, angle within %.2e of 0, -g sin(a) t^2 / 2, w t; joint error %.2e\n",
                std::string(integratorTypeName(integrator)).c_str(), worst, world.maxJointError());
    EXPECT_LT(worst, 1e-9);
    EXPECT_LT(world.maxJointError(), 1e-9);
  }
}

TEST(Gear, RowIsTheRateOfItsConstraintAnywhere) {
  std::mt19937 rng(23);
  for (int trial = 0; trial < 100; ++trial) {
    const BodyState c1 = test::randomState(rng), c2 = test::randomState(rng);
    const JointDef def{.name = "g",
                       .axis = test::randomVec(rng, 1.0),
                       .axis2 = test::randomVec(rng, 1.0),
                       .ratio = -1.7};
    std::unique_ptr<Joint> joint = makeJoint("gear", def, c1, c2);
    BodyState b1 = c1, b2 = c2;  // turned by up to 1.5 rad each
    b1.pose.orientation = math::expMap(test::randomVec(rng, 0.85)) * c1.pose.orientation;
    b2.pose.orientation = math::expMap(test::randomVec(rng, 0.85)) * c2.pose.orientation;
    ASSERT_LT(firstRowRateMiss(*joint, b1, b2), 1e-7) << "trial " << trial;
  }
}

TEST(Gear, MeshingWheelsShareTheirMomentumByTheRatio) {
  // Two wheels on parallel vertical axles, the second at twice the first's rate the other way.
  // Wheel 1 spun at w0, wheel 2 at rest: the first step meshes them, keeping
  // I1 w1 + r I2 w2 (the gear's impulse acts as r on wheel 1 for each -1 on wheel 2), so
  // w1 = I1 w0 / (I1 + r^2 I2), w2 = r w1; then both turn steadily.
  World world(settings(false));
  const double r = -2.0, w0 = 3.0;
  BodyDef d1 = test::boxBody("big", 4.0, Vec3(0.4, 0.4, 0.05), Vec3::Zero());
  d1.angular_velocity = Vec3(0, 0, w0);
  const BodyId big = world.createBody(d1);
  const BodyId small =
      world.createBody(test::boxBody("small", 1.0, Vec3(0.2, 0.2, 0.05), Vec3(0.3, 0, 0)));
  for (const auto& [body, x] : {std::pair{big, 0.0}, std::pair{small, 0.3}})
    world.createJoint("hinge", JointDef{.name = x == 0.0 ? "axle1" : "axle2",
                                        .body1 = body,
                                        .anchor = Vec3(x, 0, 0),
                                        .axis = Vec3::UnitZ()});
  const JointId gear = world.createJoint("gear", JointDef{.name = "mesh",
                                                          .body1 = big,
                                                          .body2 = small,
                                                          .axis = Vec3::UnitZ(),
                                                          .axis2 = Vec3::UnitZ(),
                                                          .ratio = r});
  const double i1 = world.body(big).inertiaWorld()(2, 2),
               i2 = world.body(small).inertiaWorld()(2, 2);
  const double w1 = i1 * w0 / (i1 + r * r * i2);
  double worst = 0.0;
  for (int n = 0; n < 2000; ++n) {
    world.step();
    worst = std::max({worst, std::abs(world.body(big).angularVelocity().z() - w1),
                      std::abs(world.body(small).angularVelocity().z() - r * w1)});
  }
  const JointCoordinates q = world.jointCoordinates(gear);
  std::printf("rates within %.2e of %.6f and %.6f rad/s; turned %.6f and %.6f rad\n", worst, w1,
              r * w1, q[0], q[1]);
  EXPECT_LT(worst, 1e-9);
  EXPECT_NEAR(q[0], w1 * world.time(), 1e-9);
  EXPECT_NEAR(q[1], r * q[0], 1e-9);
  EXPECT_GT(std::abs(q[1]), 2.0 * M_PI);  // past a turn: counted
}

TEST(RackAndPinion, RowIsTheRateOfItsConstraintAnywhere) {
  std::mt19937 rng(29);
  for (int trial = 0; trial < 100; ++trial) {
    const BodyState c1 = test::randomState(rng), c2 = test::randomState(rng);
    const JointDef def{.name = "rp",
                       .body2 = BodyId{1},
                       .axis = test::randomVec(rng, 1.0),
                       .axis2 = test::randomVec(rng, 1.0),
                       .ratio = 0.07};
    std::unique_ptr<Joint> joint = makeJoint("rack_and_pinion", def, c1, c2);
    BodyState b1 = c1, b2 = c2;  // the pinion turned by up to 1.5 rad, the rack moved
    b1.pose.orientation = math::expMap(test::randomVec(rng, 0.85)) * c1.pose.orientation;
    b2.pose.position += test::randomVec(rng, 1.0);
    ASSERT_LT(firstRowRateMiss(*joint, b1, b2), 1e-7) << "trial " << trial;
  }
}

TEST(RackAndPinion, FallingRackSpinsThePinionAtTheEffectiveMass) {
  // A 2 kg rack on a vertical slider meshes with a pinion of pitch radius 0.1 m and inertia
  // 0.02 kg m^2 on a horizontal axle: the rack falls at a = g m / (m + I / r^2) = g / 2, the pinion
  // turning s / r: from rest, s_n = -a h^2 n (n + 1) / 2 by symplectic Euler (the step), and
  // s = -a t^2 / 2 with "auto" (the accurate integrator).
  for (const IntegratorType integrator : {IntegratorType::Step, IntegratorType::Auto}) {
    WorldSettings s = settings(true);
    s.integrator.type = integrator;
    World world(s);
    constexpr double m = 2.0, inertia = 0.02, r = 0.1, h = 1e-3;
    BodyDef pinion_def;
    pinion_def.name = "pinion";
    pinion_def.mass = 1.0;
    pinion_def.inertia = Vec3(0.01, inertia, 0.01).asDiagonal();
    const BodyId pinion = world.createBody(pinion_def);
    const BodyId rack =
        world.createBody(test::boxBody("rack", m, Vec3(0.02, 0.02, 0.5), Vec3(r, 0, 0)));
    world.createJoint(
        "hinge",
        JointDef{.name = "axle", .body1 = pinion, .anchor = Vec3::Zero(), .axis = Vec3::UnitY()});
    world.createJoint("slider", JointDef{.name = "guide", .body1 = rack, .axis = Vec3::UnitZ()});
    // At x = r, a turn about +y moves the pitch point by w x r = (0, w, 0) x (r, 0, 0) = -w r z:
    // the rack travels along -z by r per radian.
    const JointId mesh = world.createJoint("rack_and_pinion", JointDef{.name = "mesh",
                                                                       .body1 = pinion,
                                                                       .body2 = rack,
                                                                       .axis = Vec3::UnitY(),
                                                                       .axis2 = -Vec3::UnitZ(),
                                                                       .ratio = r});
    const double a = 9.81 * m / (m + inertia / (r * r));
    double worst = 0.0;
    for (int n = 1; n <= 1000; ++n) {
      world.step();
      const double z = -test::distanceFromRest(integrator, a, h, n);
      worst = std::max(worst, std::abs(world.body(rack).position().z() - z));
    }
    const JointCoordinates q = world.jointCoordinates(mesh);
    std::printf(
        "%s: rack fell %.9f m (closed form %.9f), worst %.2e m; pinion %.9f rad, travel %.9f m\n",
        std::string(integratorTypeName(integrator)).c_str(), -world.body(rack).position().z(),
        test::distanceFromRest(integrator, a, h, 1000), worst, q[0], q[1]);
    EXPECT_LT(worst, 1e-9);
    EXPECT_NEAR(q[1], r * q[0], 1e-12);
    EXPECT_NEAR(q[1], -world.body(rack).position().z(), 1e-12);
    EXPECT_GT(q[0], 2.0 * M_PI);  // past a turn: counted
    EXPECT_THROW(world.createJoint("rack_and_pinion", JointDef{.name = "x",
                                                               .body1 = pinion,
                                                               .axis = Vec3::UnitY(),
                                                               .axis2 = Vec3::UnitZ(),
                                                               .ratio = r}),
                 std::invalid_argument);
  }
}

TEST(Locked, ALockedHingeAngleHoldsLikeAWeld) {
  World world(settings(true));
  const BodyId arm =
      world.createBody(test::boxBody("arm", 1.0, Vec3(0.5, 0.05, 0.05), Vec3(0.25, 0, 0)));
  const JointId j =
      world.createJoint("hinge", JointDef{.name = "h",
                                          .body1 = arm,
                                          .anchor = Vec3::Zero(),
                                          .axis = Vec3::UnitY(),
                                          .coordinates = {CoordinateDef{.locked = true}}});
  for (int n = 0; n < 1000; ++n) world.step();
  EXPECT_NEAR(world.jointCoordinates(j)[0], 0.0, 1e-9);
  // The weight's torque about the anchor is (L / 2) x cross (-m g z) = +m g L / 2 about y; the
  // locked angle's torque on the arm cancels it.
  EXPECT_NEAR(world.jointReaction(j).torque.y(), -kG * 0.25, 1e-6);
  EXPECT_THROW(world.joint(j).setFriction(1.0), std::invalid_argument);  // locked takes nothing
}

TEST(Distance, RefusesPointsThatMeetAndANonPositiveLength) {
  World world;
  const BodyId b = world.createBody(test::boxBody("b", 1.0, Vec3(0.1, 0.1, 0.1), Vec3::Zero()));
  const auto message = [&](const JointDef& def) {
    try {
      world.createJoint("distance", def);
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  EXPECT_EQ(message(JointDef{.name = "d", .body1 = b, .anchor2 = Vec3::Zero()}).substr(0, 42),
            "anchor2: must be apart from the point on b");
  EXPECT_EQ(message(JointDef{.name = "d", .body1 = b, .anchor2 = Vec3(1, 0, 0), .length = 0.0}),
            "length: must be finite and > 0");
}

}  // namespace
}  // namespace linx
