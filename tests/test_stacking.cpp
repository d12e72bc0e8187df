// Resting contact at scale: a 10-box stack and a 10-row pyramid must stand for 10 s of simulated
// time with every box within 1 cm of where it started, fall asleep and stay asleep; 1000 spheres
// poured into a box must settle with penetrations below the slop plus a stated tolerance. The
// truth here is statics: a stack at rest does not move, and resting contacts do not overlap
// deeper than the slop the contact law allows.
#include "support.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <vector>

namespace linx {
namespace {

constexpr double kSide = 0.2;  // box edge (m)

BodyDef groundPlane() {
  BodyDef g;
  g.name = "ground";
  g.is_static = true;
  g.shapes.push_back(ShapeDef{.type = ShapeType::Plane, .friction = 0.6});
  return g;
}

BodyDef cube(const std::string& name, const Vec3& position) {
  BodyDef d = test::boxBody(name, 1.0, Vec3::Constant(kSide), position);
  d.shapes[0].friction = 0.6;
  return d;
}

struct Pile {
  World world;
  std::vector<BodyId> boxes;
  std::vector<Vec3> start;
};

/// A pile on the ground: rows of cubes, row r holding counts[r] cubes centred on x = 0, each
/// resting exactly on the row below (a stack is rows of one, a pyramid rows of 10, 9, ..., 1).
Pile makePile(const WorldSettings& settings, const std::vector<int>& counts) {
  Pile pile{World(settings), {}, {}};
  pile.world.createBody(groundPlane());
  for (std::size_t row = 0; row < counts.size(); ++row) {
    for (int k = 0; k < counts[row]; ++k) {
      const Vec3 p((k - (counts[row] - 1) / 2.0) * kSide, 0, kSide / 2 + kSide * row);
      const std::string name = std::to_string(pile.boxes.size()).insert(0, "box");
      pile.boxes.push_back(pile.world.createBody(cube(name, p)));
      pile.start.push_back(p);
    }
  }
  return pile;
}

/// Runs for `seconds` and returns the largest displacement of any box from its start, checking
/// that once every box sleeps none wakes again.
double standFor(Pile& pile, double seconds, int& asleep_at, int& woke_after) {
  double worst = 0.0;
  asleep_at = -1;
  woke_after = 0;
  const int steps = static_cast<int>(std::lround(seconds / pile.world.settings().timestep));
  for (int i = 0; i < steps; ++i) {
    pile.world.step();
    bool all_asleep = true;
    for (std::size_t k = 0; k < pile.boxes.size(); ++k) {
      const Body& b = pile.world.body(pile.boxes[k]);
      worst = std::max(worst, (b.position() - pile.start[k]).norm());
      all_asleep = all_asleep && pile.world.isAsleep(pile.boxes[k]);
    }
    if (all_asleep && asleep_at < 0) asleep_at = i + 1;
    if (!all_asleep && asleep_at >= 0) ++woke_after;
  }
  return worst;
}

// 240 Hz. At 60 Hz the 10-box stack settles 1.6 cm off its start with the default 100 Gauss-Seidel
// sweeps before it sleeps (docs/contacts.md, "Limits"): standing at 60 Hz is issue 4's target.
WorldSettings stackSettings() {
  WorldSettings s;
  s.timestep = 1.0 / 240.0;
  return s;
}

// Ten cubes of 0.2 m, each resting exactly on the one below. The bound is the 1 cm; the
// stack must also fall asleep (its bodies at rest for 0.5 s) and then never wake by itself.
TEST(Stacking, TenBoxStackStandsAndSleeps) {
  Pile pile = makePile(stackSettings(), std::vector<int>(10, 1));
  int asleep_at = 0, woke = 0;
  const double worst = standFor(pile, 10.0, asleep_at, woke);
  std::printf("10-box stack: largest displacement %.3e m over 10 s, asleep at step %d, woke %d\n",
              worst, asleep_at, woke);
  EXPECT_LT(worst, 0.01);
  EXPECT_GT(asleep_at, 0);
  EXPECT_EQ(woke, 0);
}

// A pyramid of 10 rows (55 cubes), each row centred on the one below it.
TEST(Stacking, TenRowPyramidStandsAndSleeps) {
  Pile pile = makePile(stackSettings(), {10, 9, 8, 7, 6, 5, 4, 3, 2, 1});
  int asleep_at = 0, woke = 0;
  const double worst = standFor(pile, 10.0, asleep_at, woke);
  std::printf("10-row pyramid: largest displacement %.3e m over 10 s, asleep at step %d, woke %d\n",
              worst, asleep_at, woke);
  EXPECT_LT(worst, 0.01);
  EXPECT_GT(asleep_at, 0);
  EXPECT_EQ(woke, 0);
}

// A sleeping stack wakes when something hits it, and the whole island wakes with it.
TEST(Stacking, SleepingStackWakesWhenHit) {
  Pile pile = makePile(stackSettings(), {1, 1, 1});
  for (int i = 0; i < 480; ++i) pile.world.step();
  for (const BodyId b : pile.boxes) ASSERT_TRUE(pile.world.isAsleep(b));
  // A ball thrown at the top box.
  BodyDef ball;
  ball.name = "ball";
  ball.mass = 1.0;
  ball.inertia = Mat3::Identity() * 0.4 * 0.05 * 0.05;
  ball.position = Vec3(-0.5, 0, 0.5);
  ball.linear_velocity = Vec3(8.0, 0, 0);
  ball.shapes.push_back(ShapeDef{.type = ShapeType::Sphere, .radius = 0.05});
  pile.world.createBody(ball);
  bool all_woke = false;
  for (int i = 0; i < 120 && !all_woke; ++i) {
    pile.world.step();
    all_woke = true;
    for (const BodyId b : pile.boxes) all_woke = all_woke && !pile.world.isAsleep(b);
  }
  EXPECT_TRUE(all_woke);
  EXPECT_GT(pile.world.body(pile.boxes[2]).linearVelocity().x(), 0.1);  // the top box was hit
}

// 1000 spheres (r = 5 cm, 10 x 10 x 10, a little jitter) fall into an open box and settle. After
// 3 s the deepest overlap, sphere-sphere and sphere-wall, must stay below the slop (0.5 mm) plus
// 1 mm: erp removes a fifth of the excess per step, so what remains is what one step of gravity
// and the weight of the spheres above push in.
TEST(Stacking, ThousandSpheresSettleInABox) {
  WorldSettings s;
  s.timestep = 1.0 / 120.0;
  s.solver.iterations = 30;
  World world(s);
  BodyDef box;
  box.name = "container";
  box.is_static = true;
  const double half = 0.6, wall = 0.1, height = 2.0;
  box.shapes = {ShapeDef{.type = ShapeType::Box,
                         .size = Vec3(2 * half + 2 * wall, 2 * half + 2 * wall, wall),
                         .position = Vec3(0, 0, -wall / 2)},
                ShapeDef{.type = ShapeType::Box,
                         .size = Vec3(wall, 2 * half, height),
                         .position = Vec3(-half - wall / 2, 0, height / 2)},
                ShapeDef{.type = ShapeType::Box,
                         .size = Vec3(wall, 2 * half, height),
                         .position = Vec3(half + wall / 2, 0, height / 2)},
                ShapeDef{.type = ShapeType::Box,
                         .size = Vec3(2 * half + 2 * wall, wall, height),
                         .position = Vec3(0, -half - wall / 2, height / 2)},
                ShapeDef{.type = ShapeType::Box,
                         .size = Vec3(2 * half + 2 * wall, wall, height),
                         .position = Vec3(0, half + wall / 2, height / 2)}};
  world.createBody(box);
  const double r = 0.05;
  std::vector<BodyId> spheres;
  unsigned seed = 12345;
  auto jitter = [&] {
    seed = seed * 1103515245u + 12345u;
    return ((seed >> 8) % 1000) / 1000.0 * 0.01 - 0.005;
  };
  for (int i = 0; i < 1000; ++i) {
    BodyDef d;
    d.name = "sphere" + std::to_string(i);
    d.mass = 0.5;
    d.inertia = Mat3::Identity() * 0.4 * 0.5 * r * r;
    d.position = Vec3(-0.5 + 0.11 * (i % 10) + jitter(), -0.5 + 0.11 * ((i / 10) % 10) + jitter(),
                      0.2 + 0.11 * (i / 100));
    d.shapes.push_back(ShapeDef{.type = ShapeType::Sphere, .radius = r, .friction = 0.4});
    spheres.push_back(world.createBody(d));
  }
  for (int i = 0; i < 360; ++i) world.step();
  double deepest = 0.0;
  for (const Contact& c : world.contacts()) deepest = std::max(deepest, c.depth);
  double lowest = kInfinity;
  for (const BodyId b : spheres) lowest = std::min(lowest, world.body(b).position().z());
  const double slop = world.settings().contact.slop;
  std::printf(
      "1000 spheres: %zu contacts, deepest penetration %.3e m (slop %.1e), lowest centre "
      "%.4f m\n",
      world.contacts().size(), deepest, slop, lowest);
  EXPECT_LT(deepest, slop + 1e-3);
  EXPECT_GT(lowest, r - slop - 1e-3);  // nothing fell through the floor
}

// The exact solver chosen for a pile of boxes: its active set cannot settle friction on redundant
// contact points, so it hands most steps to Gauss-Seidel from the warm start. It is not the solver
// for piles (`auto` is): the stack drifts by centimetres. What it must never do is blow up: it once
// did, to impulses of 1e94 N s within 8 steps, from the active set's last iterate. The bound is
// on speed: a stack that stands or sways slowly stays far below 1 m/s; an exploding one does not.
TEST(Stacking, ExactSolverOnAPileNeverBlowsUp) {
  WorldSettings s;
  s.timestep = 1.0 / 60.0;
  s.solver.type = SolverType::Exact;
  Pile pile = makePile(s, std::vector<int>(10, 1));
  double fastest = 0.0;
  for (int i = 0; i < 120; ++i) {
    pile.world.step();
    for (const BodyId b : pile.boxes)
      fastest = std::max(fastest, pile.world.body(b).linearVelocity().norm());
  }
  std::printf("exact solver, 10-box stack at 60 Hz: fastest box %.3e m/s over 2 s\n", fastest);
  EXPECT_LT(fastest, 1.0);
}

// The same for a pyramid, whose contacts close loops (each box rests on two, which touch each
// other): its rows go to the sparse back-end, whose free solve on redundant points with friction
// once gave impulses that were not finite, and the active set took them for a solution (the
// 6-box pyramid stopped with non-finite positions at its 16th step, the 15-box one at its 3rd).
TEST(Stacking, ExactSolverOnAPyramidStaysFinite) {
  for (const std::vector<int>& rows :
       {std::vector<int>{3, 2, 1}, std::vector<int>{5, 4, 3, 2, 1}}) {
    WorldSettings s;
    s.timestep = 1.0 / 60.0;
    s.solver.type = SolverType::Exact;
    Pile pile = makePile(s, rows);
    double fastest = 0.0;
    for (int i = 0; i < 120; ++i) {
      ASSERT_NO_THROW(pile.world.step()) << rows.size() << " rows, step " << i + 1;
      for (const BodyId b : pile.boxes)
        fastest = std::max(fastest, pile.world.body(b).linearVelocity().norm());
    }
    std::printf("exact solver, %zu-row pyramid at 60 Hz: fastest box %.3e m/s over 2 s\n",
                rows.size(), fastest);
    EXPECT_LT(fastest, 1.0);
  }
}

// A box asleep on a static support must fall when the support is taken away: the program moves
// the support (setPose) and wakes it, which wakes what touched it.
TEST(Stacking, SleepingBoxFallsWhenItsSupportIsRemoved) {
  World world(stackSettings());
  BodyDef table;
  table.name = "table";
  table.is_static = true;
  table.position = Vec3(0, 0, -0.05);
  table.shapes.push_back(ShapeDef{.type = ShapeType::Box, .size = Vec3(1, 1, 0.1)});
  const BodyId support = world.createBody(table);
  const BodyId box = world.createBody(cube("box", Vec3(0, 0, kSide / 2)));
  for (int i = 0; i < 240; ++i) world.step();
  ASSERT_TRUE(world.isAsleep(box));
  world.body(support).setPose(Pose{Vec3(0, 0, -10), Quat::Identity()});
  world.wake(support);
  for (int i = 0; i < 120; ++i) world.step();  // 0.5 s of free fall: 1.2 m
  EXPECT_FALSE(world.isAsleep(box));
  EXPECT_LT(world.body(box).position().z(), -1.0);
}

}  // namespace
}  // namespace linx
