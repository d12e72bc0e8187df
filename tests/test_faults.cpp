// Faults a step must not pass silently (issue 15, docs/solver.md "Faults"): a non-finite state and
// energy that undriven steps make. The energy rule is checked against its closed form on bodies
// whose velocities stand in for what a solve did; the worlds check that stable physics never
// trips it, and the contacts' push-out cap that keeps a deep overlap from exploding.
#include <linx/linx.hpp>

#include "step/check.hpp"

#include <gtest/gtest.h>

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
  // Switched off, nothing is checked but finiteness.
  step::FaultCheck off;
  settings.energy = false;
  EXPECT_NO_THROW(stepTo(off, bodies, 0, 1e6, settings, false, 1));
  EXPECT_THROW(stepTo(off, bodies, 0, std::numeric_limits<double>::infinity(), settings, false, 2),
               NonFiniteState);
}

// Two 1 kg spheres (r = 0.1 m) created 5 cm deep in each other, no gravity. erp / h times the
// depth beyond the slop would part them at 9.9 m/s; the cap parts them at 3 m/s at most, and the
// energy the push-out makes stays within the fault allowance (the run goes on).
TEST(PushOut, DeepOverlapPartsNoFasterThanTheCap) {
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
  double fastest = 0.0;
  for (int i = 0; i < 200; ++i) {
    world.step();
    const double parting =
        world.body(ib).linearVelocity().z() - world.body(ia).linearVelocity().z();
    fastest = std::max(fastest, parting);
  }
  EXPECT_LE(fastest, 3.0 * (1.0 + 1e-9));
  EXPECT_GT(fastest, 2.9);  // and pushed at the cap while deeper than it allows
  EXPECT_GT(world.body(ib).position().z() - world.body(ia).position().z(), 0.2);  // apart
}

}  // namespace
}  // namespace linx
