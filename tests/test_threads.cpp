// Threads: a step gives the same state to the bit for any thread count (docs/performance.md,
// "Threads"). The reference is the one-thread run. The pile is large enough that every parallel
// stage is in use: over 4096 bodies (the per-body stages), over 1024 broadphase pairs and contacts
// (narrowphase, rows, warm start), and an island of over 16384 rows (its gather and the coloured
// PGS sweep).
#include <linx/linx.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

namespace linx {
namespace {

constexpr double kRadius = 0.05;

/// 17 x 17 x 15 spheres in touching columns on a floor, each nudged sideways by a fixed pattern so
/// that the pile has to settle (a column of perfect spheres would just stand).
World pile(int threads) {
  WorldSettings s;
  s.timestep = 1.0 / 60.0;
  s.threads = threads;
  s.solver.iterations = 20;
  World world(s);
  BodyDef floor;
  floor.name = "floor";
  floor.is_static = true;
  floor.shapes.push_back(ShapeDef{.type = ShapeType::Plane, .friction = 0.5});
  world.createBody(floor);
  const int side = 17, layers = 15;
  for (int k = 0; k < layers; ++k)
    for (int j = 0; j < side; ++j)
      for (int i = 0; i < side; ++i) {
        const int n = (k * side + j) * side + i;
        BodyDef d;
        d.name = "ball" + std::to_string(n);
        d.mass = 0.1;
        d.inertia = Mat3::Identity() * 0.4 * 0.1 * kRadius * kRadius;
        const double nudge = 0.004 * std::sin(1.7 * n);
        d.position = Vec3(2 * kRadius * i + nudge, 2 * kRadius * j - nudge,
                          kRadius + 2 * kRadius * k - 0.001 * (k % 2));
        d.shapes.push_back(ShapeDef{.type = ShapeType::Sphere, .radius = kRadius, .friction = 0.5});
        world.createBody(d);
      }
  return world;
}

TEST(Threads, APileStepsToTheSameStateForAnyThreadCount) {
  constexpr int kSteps = 3;
  World reference = pile(1);
  for (int i = 0; i < kSteps; ++i) reference.step();
  ASSERT_GT(reference.bodyCount(), 4096);
  ASSERT_GT(reference.contacts().size(), 1024u);
  ASSERT_GT(reference.lastReport().rows, 16384);
  // The pile moved: a test of a world at rest would prove little.
  double speed = 0.0;
  for (int b = 1; b < reference.bodyCount(); ++b)
    speed = std::max(speed, reference.body(BodyId{b}).linearVelocity().norm());
  EXPECT_GT(speed, 0.05);

  for (const int threads : {2, 3}) {
    World world = pile(threads);
    for (int i = 0; i < kSteps; ++i) world.step();
    int differing = 0;
    for (int b = 0; b < world.bodyCount(); ++b) {
      const Body& x = world.body(BodyId{b});
      const Body& r = reference.body(BodyId{b});
      if (x.position() != r.position() || x.orientation().coeffs() != r.orientation().coeffs() ||
          x.linearVelocity() != r.linearVelocity() || x.angularVelocity() != r.angularVelocity())
        ++differing;
    }
    std::printf("%d threads: %d of %d bodies differ from one thread (%zu contacts, %d rows)\n",
                threads, differing, world.bodyCount(), world.contacts().size(),
                world.lastReport().rows);
    EXPECT_EQ(differing, 0);
    ASSERT_EQ(world.contacts().size(), reference.contacts().size());
    for (std::size_t c = 0; c < world.contacts().size(); ++c) {
      EXPECT_EQ(world.contacts()[c].normal_impulse, reference.contacts()[c].normal_impulse);
      EXPECT_EQ(world.contacts()[c].friction_impulse, reference.contacts()[c].friction_impulse);
    }
  }
}

}  // namespace
}  // namespace linx
