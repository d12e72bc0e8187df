// Threads: a step gives the same state to the bit for any thread count (docs/performance.md,
// "Threads"). The reference is the one-thread run. The pile is large enough that every parallel
// stage is in use: over 4096 bodies (the per-body stages), over 1024 broadphase pairs and contacts
// (narrowphase, rows, warm start), and an island of over 16384 rows (its gather and the coloured
// PGS sweep). A second scene has many small islands, which threads solve side by side.
#include <linx/linx.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

namespace linx {
namespace {

/// A static floor, the plane z = 0, of the given friction.
void addFloor(World& world, double friction) {
  BodyDef floor;
  floor.name = "floor";
  floor.is_static = true;
  floor.shapes.push_back(ShapeDef{.type = ShapeType::Plane, .friction = friction});
  world.createBody(floor);
}

constexpr double kRadius = 0.05;
constexpr int kRagdolls = 6;

/// 17 x 17 x 15 spheres in touching columns on a floor, each nudged sideways by a fixed pattern so
/// that the pile has to settle (a column of perfect spheres would just stand).
World pile(int threads) {
  WorldSettings s;
  s.timestep = 1.0 / 60.0;
  s.threads = threads;
  s.solver.iterations = 20;
  World world(s);
  addFloor(world, 0.5);
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

/// Bodies whose pose or velocity is not the same to the bit in both worlds.
int differingBodies(const World& world, const World& reference) {
  int differing = 0;
  for (int b = 0; b < world.bodyCount(); ++b) {
    const Body& x = world.body(BodyId{b});
    const Body& r = reference.body(BodyId{b});
    if (x.position() != r.position() || x.orientation().coeffs() != r.orientation().coeffs() ||
        x.linearVelocity() != r.linearVelocity() || x.angularVelocity() != r.angularVelocity())
      ++differing;
  }
  return differing;
}

/// The same contacts, with the same impulses to the bit.
void expectSameContacts(const World& world, const World& reference) {
  ASSERT_EQ(world.contacts().size(), reference.contacts().size());
  for (std::size_t c = 0; c < world.contacts().size(); ++c) {
    EXPECT_EQ(world.contacts()[c].normal_impulse, reference.contacts()[c].normal_impulse);
    EXPECT_EQ(world.contacts()[c].friction_impulse, reference.contacts()[c].friction_impulse);
  }
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
    const int differing = differingBodies(world, reference);
    std::printf("%d threads: %d of %d bodies differ from one thread (%zu contacts, %d rows)\n",
                threads, differing, world.bodyCount(), world.contacts().size(),
                world.lastReport().rows);
    EXPECT_EQ(differing, 0);
    expectSameContacts(world, reference);
  }
}

/// 24 separate islands of each kind: three-link hinge pendulums released horizontal (joints
/// only: the exact solver) and boxes dropped tilted onto a floor (contacts with friction: PGS).
World islands(int threads) {
  WorldSettings s;
  s.timestep = 1.0 / 120.0;
  s.threads = threads;
  World world(s);
  addFloor(world, 0.6);
  for (int p = 0; p < 24; ++p) {
    const double y = 0.5 * p;
    BodyId previous = kWorldBody;
    for (int link = 0; link < 3; ++link) {
      BodyDef d;
      d.name = "link" + std::to_string(p) + "_" + std::to_string(link);
      d.mass = 1.0 + 0.1 * link;
      d.inertia = Mat3::Identity() * 0.01;
      d.position = Vec3(0.1 + 0.2 * link, y, 2.0);
      const BodyId body = world.createBody(d);
      JointDef j;
      j.name = "hinge" + std::to_string(p) + "_" + std::to_string(link);
      j.body1 = body;
      j.body2 = previous;
      j.anchor = Vec3(0.2 * link, y, 2.0);
      j.axis = Vec3::UnitY();
      world.createJoint("hinge", j);
      previous = body;
    }
    BodyDef box;
    box.name = "box" + std::to_string(p);
    box.mass = 1.0;
    box.inertia = Mat3::Identity() * (1.0 / 6.0) * 0.04;
    box.position = Vec3(3.0, y, 0.15 + 0.01 * (p % 5));
    box.orientation = Quat(Eigen::AngleAxisd(0.2 + 0.01 * p, Vec3(1, 1, 0).normalized()));
    box.shapes.push_back(
        ShapeDef{.type = ShapeType::Box, .size = Vec3::Constant(0.2), .friction = 0.6});
    world.createBody(box);
  }
  return world;
}

TEST(Threads, ManySmallIslandsStepToTheSameStateForAnyThreadCount) {
  constexpr int kSteps = 90;
  World reference = islands(1);
  std::vector<double> lowest_tip(24, 1e9);
  for (int i = 0; i < kSteps; ++i) {
    reference.step();
    for (int p = 0; p < 24; ++p) {
      const BodyId tip = *reference.findBody("link" + std::to_string(p) + "_2");
      lowest_tip[static_cast<std::size_t>(p)] =
          std::min(lowest_tip[static_cast<std::size_t>(p)], reference.body(tip).position().z());
    }
  }
  // Every box came to touch the floor (its lowest corner at the floor, to the contact slop), and
  // every pendulum swung down: the islands did work.
  for (int p = 0; p < 24; ++p) {
    const Body& b = reference.body(*reference.findBody("box" + std::to_string(p)));
    double lowest = 1e9;
    for (int c = 0; c < 8; ++c) {
      const Vec3 corner(c & 1 ? 0.1 : -0.1, c & 2 ? 0.1 : -0.1, c & 4 ? 0.1 : -0.1);
      lowest = std::min(lowest, (b.position() + b.orientation() * corner).z());
    }
    EXPECT_NEAR(lowest, 0.0, 2e-3) << "box " << p;
    EXPECT_LT(lowest_tip[static_cast<std::size_t>(p)], 1.6) << "pendulum " << p;
  }
  for (const int threads : {2, 3}) {
    World world = islands(threads);
    for (int i = 0; i < kSteps; ++i) world.step();
    const int differing = differingBodies(world, reference);
    EXPECT_EQ(differing, 0) << threads << " threads";
    const SolverReport& x = world.lastReport();
    const SolverReport& r = reference.lastReport();
    EXPECT_EQ(x.rows, r.rows);
    EXPECT_EQ(x.iterations, r.iterations);
    EXPECT_EQ(x.residual, r.residual);
    EXPECT_EQ(x.converged, r.converged);
    expectSameContacts(world, reference);
  }
}

/// A free hinge chain of 3,400 links in zero gravity, each link given its own velocity: one island
/// of 16,995 equality rows, over the 16,384 from which PGS sweeps colour by colour, with each
/// joint's five rows relaxed as one block.
World freeChain(int threads) {
  WorldSettings s;
  s.timestep = 1.0 / 60.0;
  s.threads = threads;
  s.gravity = Vec3::Zero();
  s.solver.type = SolverType::Pgs;
  s.solver.iterations = 10;
  World world(s);
  constexpr int kLinks = 3400;
  for (int i = 0; i < kLinks; ++i) {
    BodyDef d;
    d.name = "link" + std::to_string(i);
    d.mass = 1.0 + 0.5 * std::sin(0.3 * i);
    d.inertia = Vec3(0.01, 0.02, 0.02).asDiagonal();
    d.position = Vec3(0.2 * i, 0.0, 0.0);
    d.linear_velocity = Vec3(0.1 * std::sin(1.3 * i), 0.1 * std::cos(0.7 * i), 0.05);
    d.angular_velocity = Vec3(0.0, 0.0, 0.2 * std::sin(0.9 * i));
    const BodyId id = world.createBody(d);
    std::string joint = "joint";  // not "j" + ...: GCC 12's -Wrestrict misfires on it
    joint += std::to_string(i);
    if (i > 0)
      world.createJoint("hinge", JointDef{.name = joint,
                                          .body1 = id,
                                          .body2 = BodyId{i - 1},
                                          .anchor = Vec3(0.2 * i - 0.1, 0.0, 0.0),
                                          .axis = Vec3::UnitZ()});
  }
  return world;
}

Vec3 linearMomentum(const World& world) {
  Vec3 p = Vec3::Zero();
  for (int b = 0; b < world.bodyCount(); ++b)
    p += world.body(BodyId{b}).mass() * world.body(BodyId{b}).linearVelocity();
  return p;
}

TEST(Threads, JointBlocksInAColouredSweepStepToTheSameStateForAnyThreadCount) {
  constexpr int kSteps = 5;
  World reference = freeChain(1);
  const Vec3 p0 = linearMomentum(reference);
  double scale = 0.0;  // sum of |m v|: the size of the momenta that cancel
  for (int b = 0; b < reference.bodyCount(); ++b)
    scale += reference.body(BodyId{b}).mass() * reference.body(BodyId{b}).linearVelocity().norm();
  for (int i = 0; i < kSteps; ++i) reference.step();
  ASSERT_GE(reference.lastReport().rows, 16384);
  // Joint impulses are internal: equal and opposite on the two links, so the chain's linear
  // momentum is kept to round-off however far the sweeps are from converged.
  EXPECT_LT((linearMomentum(reference) - p0).norm(), 1e-12 * scale);
  for (const int threads : {2, 3}) {
    World world = freeChain(threads);
    for (int i = 0; i < kSteps; ++i) world.step();
    EXPECT_EQ(differingBodies(world, reference), 0) << threads << " threads";
    EXPECT_EQ(world.lastReport().residual, reference.lastReport().residual);
  }
}

/// Ragdolls of 11 capsules joined by 10 limited hinges (the benchmark's scene), dropped tilted in
/// a row onto a floor with friction: one island each, moved by the accurate integrator while they
/// fall (the default integrator "auto": islands of joints alone), then by the step with contacts
/// (PGS), small islands solved side by side on several threads.
World ragdolls(int threads) {
  WorldSettings s;
  s.timestep = 1.0 / 60.0;
  s.threads = threads;
  World world(s);
  addFloor(world, 0.5);
  struct Part {
    double mass, radius, half_length;
    Vec3 centre, along;
  };
  const Part parts[] = {
      {10.0, 0.12, 0.05, Vec3(0, 0, 1.00), Vec3::UnitZ()},      // pelvis
      {15.0, 0.13, 0.12, Vec3(0, 0, 1.43), Vec3::UnitZ()},      // torso
      {5.0, 0.10, 0.02, Vec3(0, 0, 1.81), Vec3::UnitZ()},       // head
      {2.0, 0.05, 0.10, Vec3(0, 0.34, 1.58), Vec3::UnitY()},    // upper arms
      {1.5, 0.045, 0.10, Vec3(0, 0.645, 1.58), Vec3::UnitY()},  // lower arms
      {2.0, 0.05, 0.10, Vec3(0, -0.34, 1.58), Vec3::UnitY()},
      {1.5, 0.045, 0.10, Vec3(0, -0.645, 1.58), Vec3::UnitY()},
      {7.0, 0.07, 0.15, Vec3(0, 0.10, 0.60), Vec3::UnitZ()},  // thighs and shins
      {4.0, 0.06, 0.15, Vec3(0, 0.10, 0.16), Vec3::UnitZ()},
      {7.0, 0.07, 0.15, Vec3(0, -0.10, 0.60), Vec3::UnitZ()},
      {4.0, 0.06, 0.15, Vec3(0, -0.10, 0.16), Vec3::UnitZ()},
  };
  struct Link {
    int parent, child;
    Vec3 anchor, axis;
    double limit;
  };
  const Link links[] = {
      {0, 1, Vec3(0, 0, 1.175), Vec3::UnitY(), 0.5},
      {1, 2, Vec3(0, 0, 1.685), Vec3::UnitY(), 0.6},
      {1, 3, Vec3(0, 0.185, 1.58), Vec3::UnitX(), 1.2},
      {3, 4, Vec3(0, 0.4925, 1.58), Vec3::UnitZ(), 1.2},
      {1, 5, Vec3(0, -0.185, 1.58), Vec3::UnitX(), 1.2},
      {5, 6, Vec3(0, -0.4925, 1.58), Vec3::UnitZ(), 1.2},
      {0, 7, Vec3(0, 0.10, 0.825), Vec3::UnitY(), 1.0},
      {7, 8, Vec3(0, 0.10, 0.38), Vec3::UnitY(), 1.0},
      {0, 9, Vec3(0, -0.10, 0.825), Vec3::UnitY(), 1.0},
      {9, 10, Vec3(0, -0.10, 0.38), Vec3::UnitY(), 1.0},
  };
  for (int r = 0; r < kRagdolls; ++r) {
    const Quat q = Quat(Eigen::AngleAxisd(0.7 * r, Vec3::UnitZ())) *
                   Quat(Eigen::AngleAxisd(0.25 + 0.05 * r, Vec3::UnitX()));
    const Vec3 offset(2.5 * r, 0.0, 0.3 + 0.06 * r);
    std::vector<BodyId> ids;
    for (std::size_t k = 0; k < std::size(parts); ++k) {
      const Part& p = parts[k];
      BodyDef d;
      d.name = "doll" + std::to_string(r) + "_" + std::to_string(k);
      d.mass = p.mass;
      const double i_axis = 0.4 * p.mass * p.radius * p.radius;
      const double i_across = p.mass * (p.radius * p.radius / 4.0 + p.half_length * p.half_length);
      d.inertia = Vec3(i_across, i_across, i_axis).asDiagonal();
      d.position = q * p.centre + offset;
      d.orientation = q * Quat::FromTwoVectors(Vec3::UnitZ(), p.along);
      d.shapes.push_back(ShapeDef{.type = ShapeType::Capsule,
                                  .radius = p.radius,
                                  .length = 2.0 * p.half_length,
                                  .friction = 0.5});
      ids.push_back(world.createBody(d));
    }
    for (const Link& l : links) {
      JointDef j;
      j.name = "doll" + std::to_string(r) + "_hinge" + std::to_string(l.child);
      j.body1 = ids[static_cast<std::size_t>(l.parent)];
      j.body2 = ids[static_cast<std::size_t>(l.child)];
      j.anchor = q * l.anchor + offset;
      j.axis = q * l.axis;
      j.coordinates[0].limits = JointLimits{-l.limit, l.limit};
      world.createJoint("hinge", j);
    }
  }
  return world;
}

TEST(Threads, RagdollsStepToTheSameStateForAnyThreadCount) {
  constexpr int kSteps = 60;
  std::vector<World> worlds;
  for (const int threads : {1, 2, 3, 4}) worlds.push_back(ragdolls(threads));
  int accurate_steps = 0;  // steps on which the accurate integrator moved a falling ragdoll
  bool touched = false;    // some ragdoll reached the floor: contacts with friction were solved
  for (int i = 0; i < kSteps; ++i) {
    for (World& world : worlds) world.step();
    const World& reference = worlds.front();
    for (std::size_t w = 1; w < worlds.size(); ++w) {
      ASSERT_EQ(differingBodies(worlds[w], reference), 0)
          << "step " << i + 1 << ", " << w + 1 << " threads";
      expectSameContacts(worlds[w], reference);
      EXPECT_EQ(worlds[w].lastReport().iterations, reference.lastReport().iterations);
      EXPECT_EQ(worlds[w].lastReport().residual, reference.lastReport().residual);
      EXPECT_EQ(worlds[w].lastIntegratorReport().bodies, reference.lastIntegratorReport().bodies);
    }
    if (reference.lastIntegratorReport().bodies > 0) ++accurate_steps;
    for (const Contact& c : reference.contacts())
      touched = touched || c.body1 == BodyId{0} || c.body2 == BodyId{0};
  }
  EXPECT_GT(accurate_steps, 0);
  EXPECT_TRUE(touched);
}

}  // namespace
}  // namespace linx
