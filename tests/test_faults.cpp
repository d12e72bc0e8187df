// Faults a step must not pass silently (issue 15, docs/solver.md "Faults"): a non-finite state and
// energy that undriven steps make. The energy rule is checked against its closed form on bodies
// whose velocities stand in for what a solve did; the worlds check that stable physics never
// trips it, and the contacts' push-out cap that keeps a deep overlap from exploding.
#include <linx/linx.hpp>

#include "step/check.hpp"

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <string>

#include <vector>

namespace linx {
namespace {

std::vector<Body> twoBalls() {
  std::vector<Body> bodies;
  for (const char* name : {"a", "b"}) {
    BodyDef d;
    d.name = name;
    d.mass = 2.0;
    d.inertia = Mat3::Identity();
    bodies.emplace_back(d);
  }
  return bodies;
}

const Vec3 kGravity(0.0, 0.0, -10.0);

// A "step" that leaves body `i` moving at speed v along x, having started from the state given.
void stepTo(step::FaultCheck& check, std::vector<Body>& bodies, int i, double v,
            const FaultSettings& settings, bool motors, std::int64_t step) {
  check.begin(bodies, kGravity);
  bodies[static_cast<std::size_t>(i)].setLinearVelocity(Vec3(v, 0.0, 0.0));
  check.end(bodies, kGravity, settings, motors, step, 0.01 * static_cast<double>(step));
}

TEST(FaultCheck, EnergyMadeByUndrivenStepsBeyondTheBoundStopsTheRun) {
  std::vector<Body> bodies = twoBalls();
  FaultSettings settings;  // kinetic_fraction 0.5, height 0.1 m, speed 3 m/s
  // Allowance: sum m (|g| height + speed^2 / 2) = 2 * 2 * (1 + 4.5) = 22 J.
  step::FaultCheck check;
  // 4 m/s: 16 J made, bound 0.5 * 16 + 22 = 30 J.
  EXPECT_NO_THROW(stepTo(check, bodies, 1, 4.0, settings, false, 1));
  // 7 m/s: 49 J made in all, bound 0.5 * 49 + 22 = 46.5 J: stop, naming b, step and time.
  try {
    stepTo(check, bodies, 1, 7.0, settings, false, 2);
    FAIL() << "no EnergyGrowth";
  } catch (const EnergyGrowth& e) {
    EXPECT_EQ(e.body(), 1);
    EXPECT_EQ(e.step(), 2);
    EXPECT_DOUBLE_EQ(e.produced(), 49.0);
    EXPECT_DOUBLE_EQ(e.bound(), 46.5);
    const std::string what = e.what();
    EXPECT_NE(what.find("bodies[1] (b)"), std::string::npos) << what;
    EXPECT_NE(what.find("step 2 (t = 0.02 s)"), std::string::npos) << what;
  }
}

TEST(FaultCheck, DrivenStepsAndChangesBetweenStepsAreNotCounted) {
  std::vector<Body> bodies = twoBalls();
  FaultSettings settings;
  step::FaultCheck check;
  // A motor drives the step: 100 J made, not counted.
  EXPECT_NO_THROW(stepTo(check, bodies, 0, 10.0, settings, true, 1));
  // An applied force drives it too.
  bodies[0].applyForce(Vec3(1.0, 0.0, 0.0));
  EXPECT_NO_THROW(stepTo(check, bodies, 0, 20.0, settings, false, 2));
  bodies[0].clearLoads();
  // The program sets a velocity between steps: not the solver's doing.
  bodies[1].setLinearVelocity(Vec3(30.0, 0.0, 0.0));
  EXPECT_NO_THROW(stepTo(check, bodies, 1, 30.0, settings, false, 3));
}

TEST(FaultCheck, TheRiseIsMeasuredFromTheLowestEnergy) {
  std::vector<Body> bodies = twoBalls();
  FaultSettings settings;
  settings.height = 0.0;
  settings.speed = 0.0;
  settings.kinetic_fraction = 0.5;
  step::FaultCheck check;
  bodies[0].setLinearVelocity(Vec3(10.0, 0.0, 0.0));  // 100 J, given by the program
  // Friction takes it all: -100 J made; the kinetic peak is 100 J.
  EXPECT_NO_THROW(stepTo(check, bodies, 0, 0.0, settings, false, 1));
  // 7 m/s again: +49 J from the lowest point; bound 0.5 * 100 = 50 J.
  EXPECT_NO_THROW(stepTo(check, bodies, 0, 7.0, settings, false, 2));
  // 7.2 m/s: 51.84 J above the lowest point, past the bound, although the sum is still negative.
  EXPECT_THROW(stepTo(check, bodies, 0, 7.2, settings, false, 3), EnergyGrowth);
  // Switched off (and the speed bound lifted), nothing is checked but finiteness.
  step::FaultCheck off;
  settings.energy = false;
  settings.max_speed = kInfinity;
  EXPECT_NO_THROW(stepTo(off, bodies, 0, 1e6, settings, false, 1));
  EXPECT_THROW(stepTo(off, bodies, 0, std::numeric_limits<double>::infinity(), settings, false, 2),
               NonFiniteState);
}

// Two 1 kg spheres (r = 0.1 m) created 5 cm deep in each other, no gravity. erp / h times the
// depth beyond the slop would part them at 9.9 m/s; the cap parts them at 3 m/s at most, and the
// energy the push-out makes stays within the fault allowance (the run goes on).
// A free body thrown at 2e4 m/s in empty space: it keeps that speed exactly (no force acts), so
// the first step passes the default bound of 1e4 m/s, named with the body, the step and the time.
// The runaway at 1e200 m/s, whose energy is infinite, stops the same way.
TEST(Bounds, ABodyFasterThanTheBoundStopsTheRunNamingIt) {
  for (const double speed : {2e4, 1e200}) {
    WorldSettings settings;
    settings.gravity = Vec3::Zero();
    World world(settings);
    BodyDef d;
    d.name = "bullet";
    d.mass = 0.01;
    d.inertia = Mat3::Identity() * 1e-6;
    d.linear_velocity = Vec3(speed, 0.0, 0.0);
    world.createBody(d);
    try {
      world.step();
      ADD_FAILURE() << "no fault at " << speed << " m/s";
    } catch (const BoundExceeded& e) {
      EXPECT_EQ(e.body(), 0);
      EXPECT_EQ(e.joint(), -1);
      EXPECT_EQ(e.step(), 1);
      EXPECT_EQ(std::string(e.what()),
                fmt::format("bodies[0] (bullet): speed {:.6g} m/s is above faults.max_speed "
                            "(10000 m/s) after step 1 (t = 0.001 s)",
                            speed));
    }
  }
  // Just below the bound: 10 s of flight at 9,999 m/s, exactly 99,990 m.
  WorldSettings settings;
  settings.gravity = Vec3::Zero();
  settings.timestep = 0.01;
  World world(settings);
  BodyDef d;
  d.name = "bullet";
  d.mass = 0.01;
  d.inertia = Mat3::Identity() * 1e-6;
  d.linear_velocity = Vec3(9999.0, 0.0, 0.0);
  d.angular_velocity = Vec3(0.0, 0.0, 9.9e4);  // and spinning just below its bound
  const BodyId id = world.createBody(d);
  for (int i = 0; i < 1000; ++i) world.step();
  EXPECT_NEAR(world.body(id).position().x(), 99990.0, 1e-6);
  world.body(id).setAngularVelocity(Vec3(0.0, 0.0, 1.1e5));
  EXPECT_THROW(world.step(), BoundExceeded);
}

// A pendulum whose bob is carried 5 m off its pivot between steps: the joint's error (5 m, then
// what the error reduction leaves) passes max_joint_error, found at the first step checked.
TEST(Bounds, AJointErrorAboveTheBoundStopsTheRunNamingIt) {
  for (const int every : {1, 10}) {
    World world;
    // The step's error reduction closes the error over many steps, the check sees it; the accurate
    // integrator ("auto") projects the bodies back onto the joints within the step.
    world.settings().integrator.type = IntegratorType::Step;
    world.settings().faults.joint_error_every = every;
    world.settings().solver.post_stabilization = 0;
    world.settings().faults.energy = false;  // the error reduction makes energy closing 5 m
    BodyDef bob;
    bob.name = "bob";
    bob.mass = 1.0;
    bob.inertia = Mat3::Identity() * 0.01;
    bob.position = Vec3(1.0, 0.0, 0.0);
    const BodyId b = world.createBody(bob);
    JointDef pivot;
    pivot.name = "pivot";
    pivot.body1 = b;
    pivot.anchor = Vec3::Zero();
    pivot.axis = Vec3::UnitY();
    world.createJoint("hinge", pivot);
    for (int i = 0; i < 3; ++i) world.step();  // 3 steps: none checked at every = 10
    world.body(b).setPose(Pose{Vec3(6.0, 0.0, 0.0), Quat::Identity()});
    std::int64_t found = 0;
    try {
      for (int i = 0; i < 20; ++i) world.step();
    } catch (const BoundExceeded& e) {
      found = e.step();
      EXPECT_EQ(e.joint(), 0);
      EXPECT_NE(std::string(e.what()).find("joints[0] (pivot): error "), std::string::npos);
      EXPECT_NE(std::string(e.what()).find("is above faults.max_joint_error (1) after step"),
                std::string::npos)
          << e.what();
    }
    EXPECT_EQ(found, every == 1 ? 4 : 10);
  }
}

// With stop off, the faults are kept and the world steps on (--on-fault continue); a non-finite
// state stops it all the same.
TEST(Bounds, WithStopOffTheFaultsAreKeptAndTheWorldStepsOn) {
  WorldSettings settings;
  settings.gravity = Vec3::Zero();
  settings.faults.stop = false;
  World world(settings);
  BodyDef d;
  d.name = "bullet";
  d.mass = 1.0;
  d.inertia = Mat3::Identity();
  d.linear_velocity = Vec3(2e4, 0.0, 0.0);
  const BodyId id = world.createBody(d);
  for (int i = 0; i < 150; ++i) world.step();
  EXPECT_EQ(world.faultCount(), 150);
  EXPECT_EQ(world.faults().size(), World::kKeptFaults);
  EXPECT_NE(world.faults()[99].find("after step 100 (t = 0.1 s)"), std::string::npos);
  EXPECT_NEAR(world.body(id).position().x(), 2e4 * 0.15, 1e-9);
  world.body(id).setLinearVelocity(Vec3(kInfinity, 0.0, 0.0));
  EXPECT_THROW(world.step(), NonFiniteState);
}

// Two spheres created 5 cm deep in each other part by the split impulse: never faster than the
// cap (3 m/s, so 3 mm a step at h = 1 ms: the positions are pushed, by at most max_push_out h
// a step), at the cap while deeper than erp h allows, and with no velocity left in them (the
// push moves positions only: before, they flew apart at 3 m/s).
TEST(PushOut, DeepOverlapPartsNoFasterThanTheCapAndStays) {
  WorldSettings s;
  s.gravity = Vec3::Zero();
  World world(s);
  const ShapeDef ball{.type = ShapeType::Sphere, .radius = 0.1};
  BodyDef a, b;
  a.name = std::string(1, 'a');  // not = "a": GCC 12's -Wrestrict misfires on it here
  b.name = std::string(1, 'b');
  a.mass = b.mass = 1.0;
  a.inertia = b.inertia = Mat3::Identity();
  b.position = Vec3(0.0, 0.0, 0.15);
  a.shapes = b.shapes = {ball};
  const BodyId ia = world.createBody(a), ib = world.createBody(b);
  const auto apart = [&] { return world.body(ib).position().z() - world.body(ia).position().z(); };
  double fastest = 0.0, fastest_velocity = 0.0;
  for (int i = 0; i < 200; ++i) {
    const double before = apart();
    world.step();
    fastest = std::max(fastest, (apart() - before) / s.timestep);
    fastest_velocity = std::max({fastest_velocity, world.body(ia).linearVelocity().norm(),
                                 world.body(ib).linearVelocity().norm()});
  }
  EXPECT_LE(fastest, 3.0 * (1.0 + 1e-9));
  EXPECT_GT(fastest, 2.9);             // pushed at the cap while deeper than it allows
  EXPECT_LT(fastest_velocity, 1e-12);  // and none of it kept in the velocity
  EXPECT_NEAR(apart(), 0.2 - s.contact.slop, 1e-9);  // touching, within the slop
}

}  // namespace
}  // namespace linx
