// Actuators with controls against closed forms: a servo holds a pendulum where its torque balances
// gravity's (found by bisection), and moves it when its control changes; a motor spins a flywheel
// at gear u / I, clamped by its force range, with the control written through World::controls()
// or given as a table in time (the speed is the table's integral); the reported force is the
// balance's. Bad definitions are refused with the field and the problem.
#include "support.hpp"

#include <linx/world.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <functional>
#include <stdexcept>
#include <string>

namespace linx {
namespace {

constexpr double kMass = 2.0, kLength = 0.5, kGravity = 9.81, kSmall = 1e-3;

// A pendulum bob hanging from a hinge about y at the origin, or (no gravity) a flywheel.
struct Pendulum {
  World world;
  BodyId bob;
  JointId hinge;
  explicit Pendulum(bool gravity = true) {
    world.settings().gravity = gravity ? Vec3(0, 0, -kGravity) : Vec3::Zero();
    world.settings().timestep = 1e-3;
    BodyDef def;
    def.name = "bob";
    def.mass = kMass;
    def.inertia = kSmall * Mat3::Identity();
    def.position = Vec3(0, 0, -kLength);
    bob = world.createBody(def);
    hinge = world.createJoint(
        HingeDef{.name = "pivot", .body1 = bob, .anchor = Vec3::Zero(), .axis = Vec3::UnitY()});
  }
  double angle() const { return world.jointCoordinates(hinge)[0]; }
  void run(double seconds) {
    for (int i = 0; i < static_cast<int>(std::lround(seconds / world.settings().timestep)); ++i)
      world.step();
  }
};

ActuatorDef servo(JointId joint, double kp, double kv, double gear, double control) {
  return ActuatorDef{.name = "servo",
                     .joint = joint,
                     .gear = gear,
                     .gain = kp,
                     .bias_length = -kp,
                     .bias_velocity = -kv,
                     .control = control};
}

// The root of f in [a, b], f(a) and f(b) of opposite signs.
double bisect(const std::function<double(double)>& f, double a, double b) {
  for (int i = 0; i < 200; ++i) {
    const double m = 0.5 * (a + b);
    (f(a) < 0) == (f(m) < 0) ? a = m : b = m;
  }
  return 0.5 * (a + b);
}

TEST(Actuators, ServoHoldsThePendulumWhereItsTorqueBalancesGravity) {
  Pendulum p;
  const double kp = 40.0, kv = 4.0, gear = 2.0;
  const ActuatorId id = p.world.createActuator(servo(p.hinge, kp, kv, gear, 0.6));
  EXPECT_EQ(p.world.actuatorCount(), 1);
  EXPECT_EQ(p.world.findActuator("servo"), id);
  // At rest: gear kp (u - gear q) = m g l sin q (gravity pulls the bob back under the pivot).
  const auto rest = [&](double u) {
    return bisect(
        [&](double q) {
          return gear * kp * (u - gear * q) - kMass * kGravity * kLength * std::sin(q);
        },
        -M_PI / 2, M_PI / 2);
  };
  p.run(4.0);
  const double first = rest(0.6);
  std::printf("control 0.6: rests at %.9f rad (closed form %.9f)\n", p.angle(), first);
  EXPECT_NEAR(p.angle(), first, 1e-6);
  // Its force along its length: the balance's, m g l sin q / gear.
  EXPECT_NEAR(p.world.actuatorForce(id), kMass * kGravity * kLength * std::sin(first) / gear, 1e-5);
  p.world.setControl(id, -0.3);
  p.run(4.0);
  std::printf("control -0.3: rests at %.9f rad (closed form %.9f)\n", p.angle(), rest(-0.3));
  EXPECT_NEAR(p.angle(), rest(-0.3), 1e-6);
}

TEST(Actuators, MotorSpinsAFlywheelAtGearTimesControlOverInertia) {
  Pendulum p(false);
  const double inertia = kSmall + kMass * kLength * kLength, gear = 3.0;
  const ActuatorId id = p.world.createActuator(ActuatorDef{
      .name = "motor", .joint = p.hinge, .gear = gear, .force_range = ActuatorRange{-0.5, 0.5}});
  EXPECT_EQ(p.world.controls()[0], 0.0);
  p.world.controls()[0] = 0.2;  // MuJoCo's data.ctrl habit
  p.run(1.0);
  const double rate = p.world.jointRates(p.hinge)[0];
  EXPECT_NEAR(rate, gear * 0.2 / inertia * 1.0, 1e-6 * std::abs(rate));
  EXPECT_NEAR(p.world.actuatorForce(id), 0.2, 1e-12);
  p.world.setControl(id, 5.0);  // beyond the force range: 0.5
  p.run(1.0);
  EXPECT_NEAR(p.world.jointRates(p.hinge)[0], rate + gear * 0.5 / inertia, 1e-6 * rate);
  EXPECT_NEAR(p.world.actuatorForce(id), 0.5, 1e-12);
}

TEST(Actuators, ControlGivenAsATableDrivesItInTime) {
  Pendulum p(false);
  const double inertia = kSmall + kMass * kLength * kLength;
  // u ramps from 0 to 1 over a second and holds: the speed is its integral, 1/2 then + 1 a second.
  p.world.createActuator(
      ActuatorDef{.name = "ramp", .joint = p.hinge, .control = Signal({0.0, 1.0}, {0.0, 1.0})});
  p.run(2.0);
  const double expected = (0.5 + 1.0) / inertia;
  const double rate = p.world.jointRates(p.hinge)[0];
  std::printf("ramped motor: %.9f rad/s after 2 s (closed form %.9f)\n", rate, expected);
  EXPECT_NEAR(rate, expected, 2e-3 * expected);  // the control is taken at each step's start
  EXPECT_NEAR(p.world.controls()[0], 1.0, 1e-12);
}

TEST(Actuators, BadDefinitionsAreRefusedWithTheirField) {
  const auto refused = [](const std::function<void(Pendulum&)>& make, const std::string& problem) {
    Pendulum p;
    try {
      make(p);
      ADD_FAILURE() << "accepted; expected: " << problem;
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find(problem), std::string::npos) << e.what();
    }
  };
  refused([](Pendulum& p) { p.world.createActuator(ActuatorDef{.joint = p.hinge}); },
          "name: must not be empty");
  refused(
      [](Pendulum& p) {
        p.world.createActuator(ActuatorDef{.name = "a", .joint = p.hinge, .coordinate = 1});
      },
      "coordinate: joint 'pivot' has 1 free coordinates, got 1");
  refused(
      [](Pendulum& p) {
        p.world.createActuator(servo(p.hinge, 1, 0, 1, 0));
        p.world.createActuator(servo(p.hinge, 1, 0, 1, 0));
      },
      "name: a second actuator named 'servo'");
  refused(
      [](Pendulum& p) {
        p.world.createActuator(servo(p.hinge, 1, 0, 1, 0));
        ActuatorDef second = servo(p.hinge, 1, 0, 1, 0);
        second.name = "second";
        p.world.createActuator(second);
      },
      "has a servo or damper already");
  refused(
      [](Pendulum& p) {
        p.world.createActuator(ActuatorDef{.name = "a", .joint = p.hinge, .bias_length = 1.0});
      },
      "pushes away from where it is");
  refused(
      [](Pendulum& p) {  // a gain growing with the length needs its control bounded
        p.world.createActuator(ActuatorDef{.name = "a", .joint = p.hinge, .gain_length = -1.0});
      },
      "pushes away from where it is");
  refused(
      [](Pendulum& p) {
        p.world.createActuator(
            ActuatorDef{.name = "a", .joint = p.hinge, .force_range = ActuatorRange{0.5, 1.0}});
      },
      "force_range: must contain zero");
  refused(
      [](Pendulum& p) {
        p.world.joint(p.hinge).setMotor(JointMotor{.max_force = 1.0});
        p.world.createActuator(ActuatorDef{.name = "a", .joint = p.hinge});
      },
      "has a motor or force of its own");
  refused(
      [](Pendulum& p) {
        const ActuatorId id = p.world.createActuator(ActuatorDef{.name = "a", .joint = p.hinge});
        p.world.setControl(id, std::nan(""));
      },
      "control must be finite");
  // With a bounded control a gain that grows with the length is a servo of varying stiffness.
  Pendulum p;
  EXPECT_NO_THROW(p.world.createActuator(ActuatorDef{.name = "a",
                                                     .joint = p.hinge,
                                                     .gain_length = -1.0,
                                                     .control_range = ActuatorRange{0.0, 1.0}}));
}

}  // namespace
}  // namespace linx
