// Springs between points, standing loads, the force callback and body damping, against closed
// forms: a mass on a spring oscillates with period 2 pi sqrt(m / k) about m g / k below its rest
// length and keeps its amplitude; critically damped it does not overshoot; two free bodies on a
// spring oscillate at the reduced mass and keep their momentum; a force table integrates to the
// momentum it gives; damping decays as 1 / (1 + h c)^n, the implicit form of exp(-c t).
#include "support.hpp"

#include <linx/scene.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <stdexcept>

namespace linx {
namespace {

constexpr double kG = 9.81;

WorldSettings settings(bool gravity) {
  WorldSettings s;
  s.timestep = 1e-3;
  s.sleep.enabled = false;
  if (!gravity) s.gravity.setZero();
  return s;
}

BodyDef ball(const std::string& name, double m, const Vec3& position) {
  BodyDef b;
  b.name = name;
  b.mass = m;
  b.inertia = 0.4 * m * 0.05 * 0.05 * Mat3::Identity();  // a 5 cm ball
  b.position = position;
  return b;
}

// A spring joint from the world point (0, 0, 1) to the body's centre.
JointId hang(World& world, BodyId body, double k, double c, double rest) {
  return world.createJoint(
      "spring", JointDef{.name = "spring",
                         .body1 = body,
                         .anchor = world.body(body).position(),
                         .anchor2 = Vec3(0, 0, 1),
                         .coordinates = {CoordinateDef{
                             .spring = JointSpring{.stiffness = k, .damping = c, .rest = rest}}}});
}

TEST(PointSpring, MassOscillatesWithItsPeriodAboutItsSag) {
  // Period 0.1 s, 100 steps a period; released at the rest length, 0.5 m below the point.
  constexpr double m = 1.0, period = 0.1, rest = 0.5;
  const double k = m * std::pow(2 * M_PI / period, 2), sag = m * kG / k;
  World world(settings(true));
  const BodyId b = world.createBody(ball("bob", m, Vec3(0, 0, 1 - rest)));
  const JointId spring = hang(world, b, k, 0.0, rest);
  std::vector<double> times, offsets;
  double first_low = 0.0, last_low = 0.0;
  for (int n = 1; n <= 1000; ++n) {
    world.step();
    const double z = world.body(b).position().z() - (1 - rest - sag);  // from equilibrium
    times.push_back(world.time());
    offsets.push_back(z);
    if (n <= 100) first_low = std::min(first_low, z);
    if (n > 900) last_low = std::min(last_low, z);
  }
  const std::vector<double> up = test::upwardCrossings(times, offsets);
  ASSERT_GE(up.size(), 9u);
  const double measured = (up.back() - up.front()) / static_cast<double>(up.size() - 1);
  std::printf(
      "period %.6f s (2 pi sqrt(m/k) = %.6f), amplitude %.6e then %.6e m (m g / k = "
      "%.6e), length %.6f m\n",
      measured, period, -first_low, -last_low, sag, world.jointCoordinates(spring)[0]);
  EXPECT_NEAR(measured, period, 2e-3 * period);
  EXPECT_NEAR(-first_low, sag, 5e-3 * sag);
  EXPECT_NEAR(last_low, first_low, 5e-3 * sag);  // the amplitude kept over 10 periods
  EXPECT_LT(world.body(b).position().head<2>().norm(), 1e-12);  // stays on its line
}

TEST(PointSpring, CriticallyDampedDoesNotOvershoot) {
  constexpr double m = 2.0, k = 800.0, rest = 0.5;
  const double c = 2 * std::sqrt(k * m), low = 1 - rest - m * kG / k;
  World world(settings(true));
  const BodyId b = world.createBody(ball("bob", m, Vec3(0, 0, 1 - rest)));
  hang(world, b, k, c, rest);
  double lowest = 1.0;
  for (int n = 0; n < 3000; ++n) {
    world.step();
    lowest = std::min(lowest, world.body(b).position().z());
  }
  std::printf("lowest %.9f m, equilibrium %.9f m, end %.9f m\n", lowest, low,
              world.body(b).position().z());
  EXPECT_GE(lowest, low - 1e-9);
  EXPECT_NEAR(world.body(b).position().z(), low, 1e-6);
}

TEST(PointSpring, TwoFreeBodiesOscillateAtTheReducedMassAndKeepMomentum) {
  constexpr double m1 = 1.0, m2 = 3.0, k = 300.0, rest = 1.0;
  const double mu = m1 * m2 / (m1 + m2), period = 2 * M_PI * std::sqrt(mu / k);
  World world(settings(false));
  const BodyId a = world.createBody(ball("a", m1, Vec3(0, 0, 0)));
  BodyDef def_b = ball("b", m2, Vec3(1.1, 0, 0));  // stretched by 0.1 m, drifting
  def_b.linear_velocity = Vec3(0, 0.2, 0);
  const BodyId b = world.createBody(def_b);
  const JointId spring = world.createJoint(
      "spring", JointDef{.name = "s",
                         .body1 = a,
                         .body2 = b,
                         .coordinates = {
                             CoordinateDef{.spring = JointSpring{.stiffness = k, .rest = rest}}}});
  const Vec3 momentum = m1 * world.body(a).linearVelocity() + m2 * world.body(b).linearVelocity();
  std::vector<double> times, stretch;
  for (int n = 0; n < 2000; ++n) {
    world.step();
    times.push_back(world.time());
    stretch.push_back(world.jointCoordinates(spring)[0] - rest);
  }
  const std::vector<double> up = test::upwardCrossings(times, stretch);
  ASSERT_GE(up.size(), 3u);
  const double measured = (up.back() - up.front()) / static_cast<double>(up.size() - 1);
  const Vec3 after = m1 * world.body(a).linearVelocity() + m2 * world.body(b).linearVelocity();
  std::printf("period %.6f s (2 pi sqrt(mu/k) = %.6f), momentum change %.2e\n", measured, period,
              (after - momentum).norm());
  EXPECT_NEAR(measured, period, 5e-3 * period);
  EXPECT_LT((after - momentum).norm(), 1e-12);
}

TEST(StandingLoads, ForceTableGivesItsImpulseAndAPointItsTorque) {
  // A force growing as F = (3 t, 0, 0) N at a point 0.1 m off the centre along y: each step adds
  // F(t_start) h / m, so v_n = 3 h^2 n (n - 1) / (2 m); the torque r x F = (0, 0, -0.1 F).
  constexpr double m = 2.0, h = 1e-3;
  World world(settings(false));
  const BodyId b = world.createBody(ball("b", m, Vec3(0, 0, 0)));
  const LoadId load =
      world.addLoad(LoadDef{.body = b,
                            .force = VectorSignal({Signal({0.0, 10.0}, {0.0, 30.0}), 0.0, 0.0}),
                            .point = Vec3(0, 0.1, 0)});
  EXPECT_EQ(load.index, 0);
  EXPECT_EQ(world.loadCount(), 1);
  world.step();
  world.step();  // F = 3 h during the second step
  EXPECT_NEAR(world.body(b).angularVelocity().z(),
              -0.1 * 3 * h * h / world.body(b).inertiaBody()(0, 0), 1e-15);
  for (int n = 3; n <= 500; ++n) world.step();
  const double expected = 3 * h * h * 500 * 499 / (2 * m);
  std::printf("v after 0.5 s %.12f m/s (closed form %.12f)\n", world.body(b).linearVelocity().x(),
              expected);
  EXPECT_NEAR(world.body(b).linearVelocity().x(), expected, 1e-12);
}

TEST(StandingLoads, ARemovedLoadActsNoMore) {
  // 1 N on a 2 kg ball for 100 steps, then removed: the ball keeps the speed F t / m it had.
  constexpr double m = 2.0, h = 1e-3;
  World world(settings(false));
  const BodyId b = world.createBody(ball("b", m, Vec3::Zero()));
  const LoadId push = world.addLoad(LoadDef{.body = b, .force = Vec3(1, 0, 0)});
  const LoadId twist = world.addLoad(LoadDef{.body = b, .torque = Vec3(0, 0, 0.001)});
  for (int n = 0; n < 100; ++n) world.step();
  world.removeLoad(push);
  EXPECT_EQ(world.loadCount(), 1);
  EXPECT_THROW(world.removeLoad(push), std::out_of_range);
  for (int n = 0; n < 100; ++n) world.step();
  EXPECT_NEAR(world.body(b).linearVelocity().x(), 1.0 * 100 * h / m, 1e-15);
  // The other load still acts: 200 steps of torque.
  EXPECT_NEAR(world.body(b).angularVelocity().z(),
              0.001 * 200 * h / world.body(b).inertiaBody()(2, 2), 1e-12);
  world.removeLoad(twist);
  EXPECT_EQ(world.loadCount(), 0);
}

TEST(StandingLoads, TorqueSpinsABallAtTorqueOverInertia) {
  World world(settings(false));
  const BodyId b = world.createBody(ball("b", 1.0, Vec3::Zero()));
  world.addLoad(LoadDef{.body = b, .torque = Vec3(0, 0, 0.002)});
  for (int n = 0; n < 1000; ++n) world.step();
  const double expected = 0.002 * 1.0 / world.body(b).inertiaBody()(2, 2);
  EXPECT_NEAR(world.body(b).angularVelocity().z(), expected, 1e-12 * expected);
}

TEST(StandingLoads, RefusedWithTheFieldNamed) {
  World world;
  BodyDef fixed;
  fixed.name = "ground";
  fixed.is_static = true;
  const BodyId ground = world.createBody(fixed);
  const BodyId b = world.createBody(ball("b", 1.0, Vec3::Zero()));
  const auto message = [&](const LoadDef& def) -> std::string {
    try {
      world.addLoad(def);
    } catch (const std::invalid_argument& e) {
      return e.what();
    }
    return "accepted";
  };
  EXPECT_EQ(message(LoadDef{.body = ground}), "body: 'ground' is static: no force moves it");
  EXPECT_EQ(message(LoadDef{.body = BodyId{7}}), "body: must be a body of this world");
  EXPECT_EQ(
      message(LoadDef{.body = b, .force = VectorSignal({0.0, Signal({1.0, 0.5}, {0, 0}), 0.0})}),
      "force[1]: times[1]: must be after times[0] (0.5 <= 1)");
  EXPECT_EQ(message(LoadDef{.body = b, .force = Vec3(1, 2, 3)}), "accepted");
}

TEST(ForceCallback, HoldsABodyAgainstGravityAtTheStepsStart) {
  World world(settings(true));
  const BodyId b = world.createBody(ball("b", 1.5, Vec3(0, 0, 1)));
  std::vector<double> seen;
  world.setForceCallback([&](World& w) {
    seen.push_back(w.time());
    w.body(b).applyForce(Vec3(0, 0, 1.5 * kG));
  });
  for (int n = 0; n < 100; ++n) world.step();
  EXPECT_EQ(world.body(b).position().z(), 1.0);  // floats exactly
  ASSERT_EQ(seen.size(), 100u);
  EXPECT_EQ(seen[0], 0.0);
  EXPECT_NEAR(seen[99], 0.099, 1e-15);
  world.setForceCallback({});
  world.step();
  EXPECT_LT(world.body(b).linearVelocity().z(), 0.0);  // falls again
}

TEST(BodyDamping, DecaysAsTheImplicitExponential) {
  constexpr double c = 2.0, h = 1e-3;
  World world(settings(false));
  BodyDef def = ball("b", 1.0, Vec3::Zero());
  def.linear_velocity = Vec3(1, 0, 0);
  def.angular_velocity = Vec3(0, 0, 4);
  def.linear_damping = c;
  def.angular_damping = 2 * c;
  const BodyId b = world.createBody(def);
  for (int n = 0; n < 1000; ++n) world.step();
  const double v = world.body(b).linearVelocity().x(), w = world.body(b).angularVelocity().z();
  std::printf("v(1 s) %.9f (implicit %.9f, exp(-c t) %.9f), w(1 s) %.9f (implicit %.9f)\n", v,
              std::pow(1 + h * c, -1000), std::exp(-c), w, 4 * std::pow(1 + 2 * h * c, -1000));
  EXPECT_NEAR(v, std::pow(1 + h * c, -1000), 1e-12);
  EXPECT_NEAR(w, 4 * std::pow(1 + 2 * h * c, -1000), 1e-12);
  EXPECT_NEAR(v, std::exp(-c), 2e-3 * std::exp(-c));  // first order in h c
  // x = sum of v_n h: the geometric series.
  const double q = 1 / (1 + h * c);
  EXPECT_NEAR(world.body(b).position().x(), h * q * (1 - std::pow(q, 1000)) / (1 - q), 1e-12);

  BodyDef bad = ball("bad", 1.0, Vec3::Zero());
  bad.angular_damping = -1;
  EXPECT_THROW(
      {
        try {
          world.createBody(bad);
        } catch (const std::invalid_argument& e) {
          EXPECT_STREQ(e.what(), "angular_damping: must be finite and >= 0");
          throw;
        }
      },
      std::invalid_argument);
}

TEST(LoadsInScenes, SpringsForcesTorquesAndDamping) {
  const Scene scene = parseScene(R"({
    "bodies": [
      {"name": "a", "mass": 1, "inertia": [1, 1, 1], "position": [0, 0, 0], "linear_damping": 0.5},
      {"name": "b", "mass": 1, "inertia": [1, 1, 1], "position": [1, 0, 0], "angular_damping": 2}
    ],
    "springs": [
      {"body1": "a", "body2": "b", "stiffness": 100, "damping": 1},
      {"name": "tether", "body1": "b", "anchor2": [1, 0, 2], "stiffness": 5, "rest_length": 1.5}
    ],
    "forces": [{"body": "a", "force": [1, 0, {"times": [0, 1], "values": [0, 2]}], "point": [0, 1, 0]},
               {"body": "b", "force": {"times": [0, 2], "values": [[0, 0, 0], [2, 4, 6]]}}],
    "torques": [{"body": "b", "torque": [0, 0, 3]}]
  })",
                                 "loads.json");
  ASSERT_EQ(scene.springs.size(), 2u);
  EXPECT_EQ(scene.springs[0].def.name, "springs[0]");
  EXPECT_EQ(scene.springs[0].def.coordinates[0].spring->rest, 1.0);  // the initial distance
  EXPECT_EQ(scene.springs[1].def.name, "tether");
  EXPECT_TRUE(scene.springs[1].def.body2.isWorld());
  EXPECT_EQ(scene.springs[1].def.coordinates[0].spring->rest, 1.5);
  ASSERT_EQ(scene.loads.size(), 3u);
  EXPECT_EQ(scene.loads[0].field, "forces[0]");
  EXPECT_EQ(scene.loads[0].def.force.at(0.5), Vec3(1, 0, 1));
  EXPECT_EQ(scene.loads[1].def.force.at(1.0), Vec3(1, 2, 3));
  EXPECT_EQ(scene.loads[2].field, "torques[0]");
  EXPECT_EQ(scene.loads[2].def.torque.at(7.0), Vec3(0, 0, 3));
  EXPECT_EQ(scene.bodies[0].linear_damping, 0.5);
  EXPECT_EQ(scene.bodies[1].angular_damping, 2.0);
  World world = buildWorld(scene);
  EXPECT_EQ(world.jointCount(), 2);
  EXPECT_EQ(world.loadCount(), 3);
  EXPECT_NEAR(world.jointCoordinates(*world.findJoint("tether"))[0], 2.0, 1e-15);

  const auto error = [](const std::string& text) -> std::string {
    try {
      parseScene(text, "bad.json");
    } catch (const SceneError& e) {
      return e.what();
    }
    return "accepted";
  };
  const std::string bodies =
      R"("bodies": [{"name": "a", "mass": 1, "inertia": [1, 1, 1]},
                    {"name": "g", "static": true}])";
  EXPECT_EQ(error("{" + bodies + R"(, "springs": [{"body1": "a", "anchor2": [0, 0, 1]}]})"),
            "bad.json: springs[0]: needs a stiffness, a damping or both (> 0)");
  EXPECT_EQ(error("{" + bodies + R"(, "springs": [{"body1": "a", "stiffness": 1}]})"),
            "bad.json: springs[0].anchor2: missing required field (the point held in the world)");
  EXPECT_EQ(error("{" + bodies + R"(, "forces": [{"body": "g", "force": [0, 0, 1]}]})"),
            "bad.json: forces[0].body: a static body does not move");
  EXPECT_EQ(error("{" + bodies + R"(, "forces": [{"body": "a", "force": [0, 1]}]})"),
            "bad.json: forces[0].force: expected 3 components, got 2");
  EXPECT_EQ(error("{" + bodies +
                  R"(, "torques": [{"body": "a", "torque": [0, 0, 1], "point": [0, 0, 0]}]})"),
            "bad.json: torques[0].point: unknown field");
}

}  // namespace
}  // namespace linx
