// The magnitudes a world holds in doubles (issue 43, linx/bounds.hpp): bodies and shapes beyond
// 1e8 m and timesteps below 1e-150 s are refused where they are made, and a state whose energy is
// not finite or that flew beyond 1e8 m stops the run as a fault naming the body. Each against its
// exact message. (What `linx check` refuses is in tests/bad_inputs/physics_*.json.)
#include "support.hpp"

#include <gtest/gtest.h>

#include <stdexcept>
#include <string>

namespace linx {
namespace {

BodyDef ball(const Vec3& position) {
  BodyDef d;
  d.name = "ball";
  d.mass = 1.0;
  d.inertia = Mat3::Identity() * 0.004;
  d.position = position;
  d.shapes.push_back(ShapeDef{.type = ShapeType::Sphere, .radius = 0.1});
  return d;
}

template <class E, class F>
std::string messageOf(F&& f) {
  try {
    f();
  } catch (const E& e) {
    return e.what();
  }
  return "(nothing thrown)";
}

TEST(Extent, BodyBeyondTheBoundIsRefused) {
  World world;
  EXPECT_EQ(messageOf<std::invalid_argument>([&] { world.createBody(ball(Vec3(0, 0, 1e308))); }),
            "position: 1e+308 m is beyond 1e+08 m: doubles there are 2.2e+292 m apart, too coarse "
            "to resolve a contact within the slop");
  world.createBody(ball(Vec3(0, 0, 1e8)));  // at the bound: accepted
}

TEST(Extent, ShapeBeyondTheBoundIsRefused) {
  World world;
  BodyDef d = ball(Vec3::Zero());
  d.shapes[0] = ShapeDef{.type = ShapeType::Capsule, .radius = 0.1, .length = 1e30};
  EXPECT_EQ(messageOf<std::invalid_argument>([&] { world.createBody(d); }),
            "shapes[0] (capsule): length: 1e+30 m is beyond 1e+08 m: doubles there are 2.2e+14 m "
            "apart, too coarse to resolve a contact within the slop");
}

TEST(Timestep, SubnormalStepIsRefused) {
  WorldSettings s;
  s.timestep = 5e-324;
  World world(s);
  world.createBody(ball(Vec3::Zero()));
  EXPECT_EQ(messageOf<std::invalid_argument>([&] { world.step(); }),
            "timestep: must be finite and at least 1e-150 s (the step forms h^2)");
}

// A ball moved (between steps) to z = 1e308 m has a finite state and an infinite potential
// energy: the step stops on it (its kinetic energy after one step of fall, (g h)^2 / 2), even
// with faults.stop false. With it true, the extent bound names it first, as it does a ball moved
// to 2e8 m.
TEST(Faults, InfiniteEnergyStopsTheRun) {
  WorldSettings s;
  s.faults.stop = false;  // faults kept, the world stepping on: but not with an infinite energy
  World world(s);
  const BodyId id = world.createBody(ball(Vec3::Zero()));
  world.body(id).setPose(Pose{Vec3(0, 0, 1e308), Quat::Identity()});
  EXPECT_EQ(
      messageOf<NonFiniteState>([&] { world.step(); }),
      "bodies[0] (ball): energy is not finite (kinetic 4.81181e-05 J, potential inf J at 1e+308 m "
      "from the origin) after step 1 (t = 0.001 s)");
}

TEST(Faults, BodyBeyondTheExtentStopsTheRun) {
  World world;
  const BodyId id = world.createBody(ball(Vec3::Zero()));
  world.body(id).setPose(Pose{Vec3(0, 0, 1e308), Quat::Identity()});
  EXPECT_EQ(messageOf<BoundExceeded>([&] { world.step(); }),
            "bodies[0] (ball): position 1e+308 m from the origin is beyond 1e+08 m, where doubles "
            "are too coarse to resolve a contact within the slop, after step 1 (t = 0.001 s)");
  world.body(id).setPose(Pose{Vec3(0, 0, 2e8), Quat::Identity()});
  const std::string message = messageOf<BoundExceeded>([&] { world.step(); });
  EXPECT_EQ(message.substr(0, message.find(" m from the origin")),
            "bodies[0] (ball): position 2e+08");
  EXPECT_NE(message.find("is beyond 1e+08 m, where doubles are too coarse to resolve a contact "
                         "within the slop, after step 2 (t = 0.002 s)"),
            std::string::npos)
      << message;
}

}  // namespace
}  // namespace linx
