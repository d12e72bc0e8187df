// Islands (union-find over a step's links), solving island by island against the monolithic
// solve, and sleeping.
#include "solver/problem.hpp"
#include "step/island_solver.hpp"
#include "step/islands.hpp"
#include "step/sleep.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <cstdlib>
#include <new>
#include <queue>
#include <random>

// Counting allocator: the modules must not allocate once warmed up at a constant size. The
// operators are kept out of line so that GCC does not see malloc/free meet new/delete.
namespace {
std::atomic<long> g_allocations{0};
}
__attribute__((noinline)) void* operator new(std::size_t n) {
  ++g_allocations;
  if (void* p = std::malloc(n == 0 ? 1 : n)) return p;
  throw std::bad_alloc();
}
__attribute__((noinline)) void operator delete(void* p) noexcept {
  std::free(p);
}
__attribute__((noinline)) void operator delete(void* p, std::size_t) noexcept {
  std::free(p);
}

namespace linx {
namespace {

using step::Islands;
using Links = std::vector<std::pair<int, int>>;
using Flags = std::vector<std::uint8_t>;

std::vector<int> list(std::span<const int> s) {
  return {s.begin(), s.end()};
}

// --- Islands -----------------------------------------------------------------------------------

TEST(Islands, ChainsFormOneIslandEachAndLoneBodiesTheirOwn) {
  Islands isl;
  const Flags movable(7, 1);
  const Links links{{0, 1}, {4, 5}, {1, 2}, {5, 4}, {2, 2}};
  isl.build(7, movable, links);
  ASSERT_EQ(isl.count(), 4);
  EXPECT_EQ(list(isl.bodies(0)), (std::vector<int>{0, 1, 2}));
  EXPECT_EQ(list(isl.bodies(1)), (std::vector<int>{3}));
  EXPECT_EQ(list(isl.bodies(2)), (std::vector<int>{4, 5}));
  EXPECT_EQ(list(isl.bodies(3)), (std::vector<int>{6}));
  EXPECT_EQ(list(isl.links(0)), (std::vector<int>{0, 2, 4}));
  EXPECT_TRUE(isl.links(1).empty());
  EXPECT_EQ(list(isl.links(2)), (std::vector<int>{1, 3}));
  EXPECT_TRUE(isl.links(3).empty());
  for (int b = 0; b < 7; ++b)
    EXPECT_EQ(isl.islandOf(b), b <= 2 ? 0 : b == 3 ? 1 : b <= 5 ? 2 : 3) << b;
  EXPECT_EQ(isl.islandOfLink(3), 2);
}

TEST(Islands, StaticGroundSharedByTwoStacksGivesTwoIslands) {
  // Body 0 the ground, stacks 1-2-3 and 4-5 standing on it; 6 another static body.
  Islands isl;
  const Flags movable{0, 1, 1, 1, 1, 1, 0};
  const Links links{{0, 1}, {1, 2}, {4, 0}, {2, 3}, {4, 5}, {0, 6}, {-1, 0}};
  isl.build(7, movable, links);
  ASSERT_EQ(isl.count(), 2);
  EXPECT_EQ(list(isl.bodies(0)), (std::vector<int>{1, 2, 3}));
  EXPECT_EQ(list(isl.bodies(1)), (std::vector<int>{4, 5}));
  EXPECT_EQ(isl.islandOf(0), -1);
  EXPECT_EQ(isl.islandOf(6), -1);
  EXPECT_EQ(list(isl.links(0)), (std::vector<int>{0, 1, 3}));
  EXPECT_EQ(list(isl.links(1)), (std::vector<int>{2, 4}));
  EXPECT_EQ(isl.islandOfLink(5), -1);  // static to static: no island
  EXPECT_EQ(isl.islandOfLink(6), -1);  // world to static
}

TEST(Islands, LinksToTheWorldDoNotConnect) {
  Islands isl;
  const Flags movable(4, 1);
  const Links links{{-1, 2}, {3, -1}, {-1, -1}, {0, -1}, {1, -1}};
  isl.build(4, movable, links);
  ASSERT_EQ(isl.count(), 4);
  for (int b = 0; b < 4; ++b) EXPECT_EQ(isl.islandOf(b), b);
  EXPECT_EQ(list(isl.links(2)), (std::vector<int>{0}));
  EXPECT_EQ(list(isl.links(3)), (std::vector<int>{1}));
  EXPECT_EQ(list(isl.links(0)), (std::vector<int>{3}));
  EXPECT_EQ(isl.islandOfLink(2), -1);
}

TEST(Islands, EmptyAndInvalidInput) {
  Islands isl;
  isl.build(0, {}, {});
  EXPECT_EQ(isl.count(), 0);
  const Flags movable(3, 1);
  EXPECT_THROW(isl.build(4, movable, {}), std::invalid_argument);
  const Links bad{{0, 3}};
  EXPECT_THROW(isl.build(3, movable, bad), std::invalid_argument);
  const Links bad2{{-2, 0}};
  EXPECT_THROW(isl.build(3, movable, bad2), std::invalid_argument);
}

// Reference labelling by breadth-first search, numbered by smallest body.
std::vector<int> bfsIslands(int n, const Flags& movable, const Links& links) {
  std::vector<std::vector<int>> adj(static_cast<std::size_t>(n));
  auto moves = [&](int b) { return b >= 0 && movable[static_cast<std::size_t>(b)] != 0; };
  for (const auto& [a, b] : links)
    if (moves(a) && moves(b)) {
      adj[static_cast<std::size_t>(a)].push_back(b);
      adj[static_cast<std::size_t>(b)].push_back(a);
    }
  std::vector<int> label(static_cast<std::size_t>(n), -1);
  int count = 0;
  for (int s = 0; s < n; ++s) {
    if (!moves(s) || label[static_cast<std::size_t>(s)] >= 0) continue;
    std::queue<int> q;
    q.push(s);
    label[static_cast<std::size_t>(s)] = count;
    while (!q.empty()) {
      const int u = q.front();
      q.pop();
      for (const int v : adj[static_cast<std::size_t>(u)])
        if (label[static_cast<std::size_t>(v)] < 0) {
          label[static_cast<std::size_t>(v)] = count;
          q.push(v);
        }
    }
    ++count;
  }
  return label;
}

TEST(Islands, NumberingIsDeterministicAndIndependentOfLinkOrder) {
  std::mt19937 rng(7);
  for (int trial = 0; trial < 50; ++trial) {
    const int n = 1 + static_cast<int>(rng() % 60);
    Flags movable(static_cast<std::size_t>(n));
    for (auto& m : movable) m = rng() % 5 != 0 ? 1 : 0;
    Links links(rng() % 80);
    for (auto& [a, b] : links) {
      a = static_cast<int>(rng() % static_cast<unsigned>(n + 1)) - 1;
      b = static_cast<int>(rng() % static_cast<unsigned>(n + 1)) - 1;
    }
    Islands ref;
    ref.build(n, movable, links);
    const std::vector<int> expected = bfsIslands(n, movable, links);
    for (int b = 0; b < n; ++b) ASSERT_EQ(ref.islandOf(b), expected[static_cast<std::size_t>(b)]);
    // Islands ordered by smallest body; bodies and links ascending; every link in its island.
    for (int i = 0; i < ref.count(); ++i) {
      const auto bodies = ref.bodies(i);
      ASSERT_FALSE(bodies.empty());
      EXPECT_TRUE(std::is_sorted(bodies.begin(), bodies.end()));
      if (i > 0) {
        EXPECT_LT(ref.bodies(i - 1)[0], bodies[0]);
      }
      const auto ls = ref.links(i);
      EXPECT_TRUE(std::is_sorted(ls.begin(), ls.end()));
      for (const int k : ls) {
        const auto [a, b] = links[static_cast<std::size_t>(k)];
        EXPECT_TRUE((a >= 0 && ref.islandOf(a) == i) || (b >= 0 && ref.islandOf(b) == i));
      }
    }
    // The same links shuffled and reversed give the same bodies per island.
    Links shuffled = links;
    std::vector<int> perm(links.size());
    for (std::size_t k = 0; k < perm.size(); ++k) perm[k] = static_cast<int>(k);
    std::shuffle(perm.begin(), perm.end(), rng);
    for (std::size_t k = 0; k < perm.size(); ++k) {
      const auto [a, b] = links[static_cast<std::size_t>(perm[k])];
      shuffled[k] = {b, a};
    }
    Islands other;
    other.build(n, movable, shuffled);
    ASSERT_EQ(other.count(), ref.count());
    for (int i = 0; i < ref.count(); ++i) {
      EXPECT_EQ(list(other.bodies(i)), list(ref.bodies(i)));
      std::vector<int> mapped;
      for (const int k : other.links(i)) mapped.push_back(perm[static_cast<std::size_t>(k)]);
      std::sort(mapped.begin(), mapped.end());
      EXPECT_EQ(mapped, list(ref.links(i)));
    }
  }
}

TEST(Islands, NoAllocationOnceWarm) {
  const int n = 200;
  Flags movable(n, 1);
  movable[0] = 0;
  Links a, b;
  for (int i = 1; i < n; ++i) a.emplace_back(i % 3 == 0 ? 0 : i - 1, i);
  for (int i = 1; i < n; ++i) b.emplace_back(i, (i * 7) % n);
  Islands isl;
  isl.build(n, movable, a);
  isl.build(n, movable, b);
  const long before = g_allocations.load();
  for (int k = 0; k < 10; ++k) isl.build(n, movable, k % 2 ? a : b);
  EXPECT_EQ(g_allocations.load(), before);
}

// --- Island solver -----------------------------------------------------------------------------

// Row k (0, 1, 2) of a ball joint between a point at arm ra on body a and arm rb on body b (or the
// world), with position error phi.
Row pointRow(int a, const Vec3& ra, int b, const Vec3& rb, int axis, double phi) {
  Row r;
  const Vec3 e = Vec3::Unit(axis);
  r.Ja << e, ra.cross(e);
  if (b >= 0) r.Jb << -e, -rb.cross(e);
  r.body_a = a;
  r.body_b = b;
  r.phi = phi;
  r.cfm = 1e-10;
  return r;
}

// A contact of body a at arm r with a surface of normal z (body b, or the world): a unilateral
// normal row and two friction rows.
void contactRows(int a, const Vec3& r, int b, double phi, double mu, std::vector<Row>& rows) {
  const int normal = static_cast<int>(rows.size());
  Row n;
  n.Ja << Vec3::UnitZ(), r.cross(Vec3::UnitZ());
  n.body_a = a;
  n.body_b = b;
  if (b >= 0) n.Jb = -n.Ja;
  n.phi = phi;
  n.lo = 0.0;
  n.kind = RowKind::Unilateral;
  n.cfm = 1e-10;
  rows.push_back(n);
  for (const int axis : {0, 1}) {
    const Vec3 t = Vec3::Unit(axis);
    Row f;
    f.Ja << t, r.cross(t);
    if (b >= 0) f.Jb = -f.Ja;
    f.body_a = a;
    f.body_b = b;
    f.kind = RowKind::Friction;
    f.normal = normal;
    f.mu = mu;
    f.cfm = 1e-10;
    rows.push_back(f);
  }
}

// Two double pendulums A (bodies 0, 3) and B (bodies 2, 4), each lower link touching a static
// ground (body 1, non-movable) with sliding friction, and a free body 5; their rows interleaved.
struct TwoPendulums {
  std::vector<Row> rows;
  std::vector<solver::SolverBody> bodies;
  std::vector<double> lambda;
  Flags movable{1, 0, 1, 1, 1, 1};
  Islands islands;
  Links links;
  int frictionA = -1;  // a friction row of A's contact

  TwoPendulums() {
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    auto vec = [&] { return Vec3(u(rng), u(rng), u(rng)); };
    for (int i = 0; i < 6; ++i) {
      solver::SolverBody b;
      if (movable[static_cast<std::size_t>(i)]) {
        b.inv_mass = 1.0 / (1.0 + 0.5 * i);
        const Mat3 q = Quat(1.0, 0.2 * i, -0.1, 0.3).normalized().toRotationMatrix();
        b.inv_inertia = q * Vec3(8.0 + i, 11.0, 5.0 + 0.5 * i).asDiagonal() * q.transpose();
        b.v = vec();
        b.w = vec();
      }
      bodies.push_back(b);
    }
    bodies[1].v = Vec3(0.1, 0.0, 0.0);   // a moving (conveyor) ground: read by B's contact
    bodies[3].v = Vec3(3.0, 1.0, -1.0);  // sliding into the ground
    bodies[4].v = Vec3(-2.0, 0.5, -0.7);
    const Vec3 left(-0.5, 0, 0), right(0.5, 0, 0);
    for (int k = 0; k < 3; ++k) rows.push_back(pointRow(0, left, -1, Vec3::Zero(), k, 1e-3 * k));
    for (int k = 0; k < 3; ++k) rows.push_back(pointRow(2, left, -1, Vec3::Zero(), k, -2e-3));
    for (int k = 0; k < 3; ++k) rows.push_back(pointRow(3, left, 0, right, k, 5e-4));
    contactRows(4, Vec3(0.4, 0, -0.05), 1, -1e-3, 0.5, rows);  // B on the ground body
    for (int k = 0; k < 3; ++k) rows.push_back(pointRow(4, left, 2, right, k, 1e-4 * k));
    frictionA = static_cast<int>(rows.size()) + 1;
    contactRows(3, Vec3(0.5, 0, -0.05), -1, -2e-3, 0.3, rows);  // A on the world
    lambda.assign(rows.size(), 0.0);
    step::rowLinks(rows, links);
    islands.build(6, movable, links);
  }
};

struct Solved {
  std::vector<double> lambda;
  std::vector<solver::SolverBody> bodies;
  SolverReport report;
};

Solved monolithic(const TwoPendulums& s, const SolverSettings& settings) {
  Solved out{s.lambda, s.bodies, {}};
  solver::Problem p{s.rows, out.bodies, out.lambda, 1e-3};
  out.report = solver::makeSolver(settings.type)->solve(p, settings);
  return out;
}

SolverSettings settingsFor(SolverType type) {
  SolverSettings s;
  s.type = type;
  if (type == SolverType::Pgs) {  // a fixed number of sweeps: the same in both solves
    s.iterations = 40;
    s.tolerance = -1.0;
  }
  return s;
}

TEST(IslandSolver, TwoPendulumsMatchTheMonolithicSolve) {
  for (const SolverType type : {SolverType::Exact, SolverType::Pgs}) {
    SCOPED_TRACE(std::string(solverTypeName(type)));
    TwoPendulums s;
    ASSERT_EQ(s.islands.count(), 3);
    EXPECT_EQ(list(s.islands.bodies(0)), (std::vector<int>{0, 3}));
    EXPECT_EQ(list(s.islands.bodies(1)), (std::vector<int>{2, 4}));
    EXPECT_EQ(list(s.islands.bodies(2)), (std::vector<int>{5}));
    const SolverSettings settings = settingsFor(type);
    const Solved ref = monolithic(s, settings);

    auto solver = solver::makeSolver(type);
    step::IslandWorkspace work;
    const SolverReport report = step::solveIslands(s.islands, {}, s.rows, s.bodies, s.lambda, 1e-3,
                                                   *solver, settings, work);
    double dl = 0.0, du = 0.0;
    for (std::size_t k = 0; k < s.rows.size(); ++k)
      dl = std::max(dl, std::abs(s.lambda[k] - ref.lambda[k]));
    for (std::size_t i = 0; i < s.bodies.size(); ++i)
      du = std::max({du, (s.bodies[i].v - ref.bodies[i].v).lpNorm<Eigen::Infinity>(),
                     (s.bodies[i].w - ref.bodies[i].w).lpNorm<Eigen::Infinity>()});
    std::printf("%s: island vs monolithic, impulses %.2e, velocities %.2e\n",
                std::string(solverTypeName(type)).c_str(), dl, du);
    EXPECT_LT(dl, 1e-12);
    EXPECT_LT(du, 1e-12);
    // The static ground was read, not written; the free body has no rows.
    EXPECT_EQ(s.bodies[1].v, Vec3(0.1, 0.0, 0.0));
    EXPECT_EQ(s.bodies[5].v, ref.bodies[5].v);
    // A's friction slides: it sits at mu times its normal impulse (so the remapped `normal` of
    // the friction rows mattered).
    const auto fa = static_cast<std::size_t>(s.frictionA);
    const double bound = 0.3 * s.lambda[static_cast<std::size_t>(s.rows[fa].normal)];
    EXPECT_GT(bound, 0.0);
    EXPECT_NEAR(std::abs(s.lambda[fa]), bound, 1e-9);
    // The merged report.
    EXPECT_EQ(report.rows, static_cast<int>(s.rows.size()));
    EXPECT_EQ(report.converged, ref.report.converged);
    EXPECT_LE(report.residual, std::max(ref.report.residual, 1e-12) * 10.0);
    if (type == SolverType::Pgs) {
      EXPECT_EQ(report.iterations, 40);
    }
  }
}

TEST(IslandSolver, SleepingIslandKeepsItsImpulsesAndBodies) {
  for (const SolverType type : {SolverType::Exact, SolverType::Pgs}) {
    SCOPED_TRACE(std::string(solverTypeName(type)));
    TwoPendulums s;
    std::fill(s.lambda.begin(), s.lambda.end(), 0.25);  // a warm start everywhere
    const SolverSettings settings = settingsFor(type);
    const Solved mono = monolithic(s, settings);
    auto solver = solver::makeSolver(type);
    step::IslandWorkspace work;
    // Reference: every island awake.
    TwoPendulums all = s;
    step::solveIslands(all.islands, {}, all.rows, all.bodies, all.lambda, 1e-3, *solver, settings,
                       work);
    const auto before = s.bodies;
    const Flags awake{1, 0, 1};  // B asleep
    const SolverReport report = step::solveIslands(s.islands, awake, s.rows, s.bodies, s.lambda,
                                                   1e-3, *solver, settings, work);
    int solved = 0;
    for (std::size_t k = 0; k < s.rows.size(); ++k) {
      const Row& r = s.rows[k];
      if (r.body_a == 2 || r.body_a == 4) {  // B's rows: the impulses it rests on, kept
        EXPECT_EQ(s.lambda[k], 0.25) << k;
      } else {
        ++solved;
        // A is solved exactly as when B is awake (the same local problem), and as in the
        // monolithic solve up to the exact solver's own tolerance: it settles the friction bounds
        // (mu lambda_n) by a fixed point to 1e-12 relative, which a different set of rows in the
        // same solve stops at a different iterate.
        EXPECT_EQ(s.lambda[k], all.lambda[k]) << k;
        EXPECT_NEAR(s.lambda[k], mono.lambda[k], 1e-10) << k;
      }
    }
    for (const std::size_t b : {2u, 4u}) {  // asleep: untouched
      EXPECT_EQ(s.bodies[b].v, before[b].v);
      EXPECT_EQ(s.bodies[b].w, before[b].w);
    }
    for (const std::size_t b : {0u, 3u}) {
      EXPECT_EQ(s.bodies[b].v, all.bodies[b].v);
      EXPECT_EQ(s.bodies[b].w, all.bodies[b].w);
      EXPECT_LT((s.bodies[b].v - mono.bodies[b].v).norm(), 1e-10);
      EXPECT_LT((s.bodies[b].w - mono.bodies[b].w).norm(), 1e-10);
    }
    EXPECT_EQ(report.rows, solved);
  }
}

TEST(IslandSolver, ThreadsSolveIslandsSideBySideWithTheGivenSolver) {
  // On several threads the islands are solved side by side, each task with another() of the
  // given solver: the same impulses and velocities to the bit as on one thread, even when the
  // settings name another solver type than the one given (here Auto, which would pick PGS for
  // the island with friction).
  for (const SolverType type : {SolverType::Exact, SolverType::Pgs}) {
    SCOPED_TRACE(std::string(solverTypeName(type)));
    SolverSettings settings = settingsFor(type);
    settings.type = SolverType::Auto;
    TwoPendulums one;
    auto solver = solver::makeSolver(type);
    step::IslandWorkspace work;
    const SolverReport r1 = step::solveIslands(one.islands, {}, one.rows, one.bodies, one.lambda,
                                               1e-3, *solver, settings, work, 1);
    for (const int threads : {2, 3}) {
      TwoPendulums s;
      step::IslandWorkspace many;
      const SolverReport r = step::solveIslands(s.islands, {}, s.rows, s.bodies, s.lambda, 1e-3,
                                                *solver, settings, many, threads);
      EXPECT_EQ(s.lambda, one.lambda) << threads << " threads";
      for (std::size_t i = 0; i < s.bodies.size(); ++i) {
        EXPECT_EQ(s.bodies[i].v, one.bodies[i].v) << "body " << i;
        EXPECT_EQ(s.bodies[i].w, one.bodies[i].w) << "body " << i;
      }
      EXPECT_EQ(r.rows, r1.rows);
      EXPECT_EQ(r.iterations, r1.iterations);
      EXPECT_EQ(r.residual, r1.residual);
      EXPECT_EQ(r.converged, r1.converged);
      EXPECT_EQ(r.redundant_rows, r1.redundant_rows);
    }
  }
}

TEST(IslandSolver, RowsTouchingNothingMovableAreNotSolved) {
  TwoPendulums s;
  Row stray = pointRow(-1, Vec3::Zero(), 1, Vec3::Zero(), 0, 0.1);  // world to static ground
  stray.Ja.setZero();
  stray.body_a = 1;
  stray.body_b = -1;
  s.rows.push_back(stray);
  s.lambda.assign(s.rows.size(), 0.5);
  step::rowLinks(s.rows, s.links);
  s.islands.build(6, s.movable, s.links);
  auto solver = solver::makeSolver(SolverType::Exact);
  step::IslandWorkspace work;
  const SolverReport report = step::solveIslands(s.islands, {}, s.rows, s.bodies, s.lambda, 1e-3,
                                                 *solver, SolverSettings{}, work);
  EXPECT_EQ(s.lambda.back(), 0.0);
  EXPECT_EQ(report.rows, static_cast<int>(s.rows.size()) - 1);
}

TEST(IslandSolver, RejectsInconsistentInput) {
  TwoPendulums s;
  auto solver = solver::makeSolver(SolverType::Exact);
  step::IslandWorkspace work;
  // Islands built without the joint 3-0: a row then joins two islands.
  Links partial = s.links;
  for (auto& l : partial)
    if (l.first == 3 && l.second == 0) l = {3, -1};
  Islands wrong;
  wrong.build(6, s.movable, partial);
  EXPECT_THROW(step::solveIslands(wrong, {}, s.rows, s.bodies, s.lambda, 1e-3, *solver,
                                  SolverSettings{}, work),
               std::invalid_argument);
  const Flags too_few{1};
  EXPECT_THROW(step::solveIslands(s.islands, too_few, s.rows, s.bodies, s.lambda, 1e-3, *solver,
                                  SolverSettings{}, work),
               std::invalid_argument);
  std::vector<double> short_lambda(3, 0.0);
  EXPECT_THROW(step::solveIslands(s.islands, {}, s.rows, s.bodies, short_lambda, 1e-3, *solver,
                                  SolverSettings{}, work),
               std::invalid_argument);
}

TEST(IslandSolver, NoAllocationOnceWarmWithPgs) {
  TwoPendulums s;
  const auto bodies0 = s.bodies;
  auto solver = solver::makeSolver(SolverType::Pgs);
  step::IslandWorkspace work;
  const SolverSettings settings = settingsFor(SolverType::Pgs);
  const Flags all{1, 1, 1}, some{0, 1, 1};
  for (int k = 0; k < 2; ++k)
    step::solveIslands(s.islands, all, s.rows, s.bodies, s.lambda, 1e-3, *solver, settings, work);
  const long before = g_allocations.load();
  for (int k = 0; k < 6; ++k) {
    s.bodies = bodies0;  // same size: no allocation
    step::solveIslands(s.islands, k % 2 ? all : some, s.rows, s.bodies, s.lambda, 1e-3, *solver,
                       settings, work);
  }
  EXPECT_EQ(g_allocations.load(), before);
}

// --- Sleeping ----------------------------------------------------------------------------------

std::vector<Body> makeBodies(int n, std::vector<int> statics = {}) {
  std::vector<Body> out;
  for (int i = 0; i < n; ++i) {
    BodyDef d;
    d.name = std::to_string(i);
    d.mass = 1.0;
    d.inertia = Mat3::Identity();
    d.is_static = std::find(statics.begin(), statics.end(), i) != statics.end();
    out.emplace_back(d);
  }
  return out;
}

Flags movableOf(const std::vector<Body>& bodies) {
  Flags m;
  for (const Body& b : bodies) m.push_back(b.isStatic() ? 0 : 1);
  return m;
}

// One step of the protocol, without dynamics: build, wake, update. Returns the awake flags.
Flags protocolStep(Islands& isl, step::SleepTracker& tracker, const std::vector<Body>& bodies,
                   const Links& links, double h, const SleepSettings& settings) {
  isl.build(static_cast<int>(bodies.size()), movableOf(bodies), links);
  const auto awake = tracker.wakeIslands(isl);
  Flags out(awake.begin(), awake.end());
  tracker.update(isl, bodies, h, settings);
  return out;
}

// Steps until the body falls asleep; -1 if it does not within `limit` steps.
int stepsToSleep(double h, double time, int limit = 1000) {
  auto bodies = makeBodies(1);
  bodies[0].setLinearVelocity(Vec3(0.04, 0, 0));   // below 0.05 m/s
  bodies[0].setAngularVelocity(Vec3(0, 0.09, 0));  // below 0.1 rad/s
  Islands isl;
  step::SleepTracker tracker;
  tracker.resize(1);
  SleepSettings settings;
  settings.time = time;
  for (int n = 1; n <= limit; ++n) {
    protocolStep(isl, tracker, bodies, {}, h, settings);
    if (tracker.asleep(0)) return n;
  }
  return -1;
}

TEST(Sleep, FallsAsleepAfterExactlyTheTimeAtRest) {
  EXPECT_EQ(stepsToSleep(0.01, 0.5), 50);
  EXPECT_EQ(stepsToSleep(1.0 / 60.0, 0.5), 30);
  EXPECT_EQ(stepsToSleep(0.1, 0.3), 3);
  EXPECT_EQ(stepsToSleep(1e-3, 0.5), 500);
  EXPECT_EQ(stepsToSleep(0.1, 0.25), 3);  // ceil(time / h)
  EXPECT_EQ(stepsToSleep(0.01, 0.0), 1);
}

TEST(Sleep, MotionRestartsTheTimer) {
  auto bodies = makeBodies(1);
  Islands isl;
  step::SleepTracker tracker;
  tracker.resize(1);
  const SleepSettings settings;
  for (int n = 0; n < 40; ++n) protocolStep(isl, tracker, bodies, {}, 0.01, settings);
  EXPECT_NEAR(tracker.restTime(0), 0.4, 1e-12);
  bodies[0].setLinearVelocity(Vec3(0, 0, 0.05));  // at the threshold: moving
  protocolStep(isl, tracker, bodies, {}, 0.01, settings);
  EXPECT_EQ(tracker.restTime(0), 0.0);
  bodies[0].setLinearVelocity(Vec3::Zero());
  bodies[0].setAngularVelocity(Vec3(0.2, 0, 0));  // turning
  protocolStep(isl, tracker, bodies, {}, 0.01, settings);
  EXPECT_EQ(tracker.restTime(0), 0.0);
  bodies[0].setAngularVelocity(Vec3::Zero());
  int n = 0;
  while (!tracker.asleep(0) && n < 1000) {
    protocolStep(isl, tracker, bodies, {}, 0.01, settings);
    ++n;
  }
  EXPECT_EQ(n, 50);
}

TEST(Sleep, AFastBodyKeepsItsIslandAwake) {
  // Island {0, 1, 2} (a chain on static ground 4) with body 2 spinning; body 3 alone at rest.
  auto bodies = makeBodies(5, {4});
  bodies[2].setAngularVelocity(Vec3(0, 0, 1.0));
  const Links links{{0, 1}, {1, 2}, {4, 0}, {3, 4}};
  Islands isl;
  step::SleepTracker tracker;
  tracker.resize(5);
  const SleepSettings settings;
  for (int n = 1; n <= 200; ++n) {
    protocolStep(isl, tracker, bodies, links, 0.01, settings);
    EXPECT_EQ(tracker.asleep(3), n >= 50) << n;
    for (const int b : {0, 1, 2}) ASSERT_FALSE(tracker.asleep(b)) << n;
    EXPECT_FALSE(tracker.asleep(4));  // static: never
  }
  EXPECT_NEAR(tracker.restTime(0), 2.0, 1e-9);  // bodies 0 and 1 rest all along...
  EXPECT_EQ(tracker.restTime(2), 0.0);          // ...but body 2 does not
  bodies[2].setAngularVelocity(Vec3::Zero());
  int n = 0;
  while (!tracker.asleep(0) && n < 1000) {
    protocolStep(isl, tracker, bodies, links, 0.01, settings);
    ++n;
  }
  EXPECT_EQ(n, 50);  // the island waits for its last body's timer
  for (const int b : {0, 1, 2}) EXPECT_TRUE(tracker.asleep(b));
  // Sleeping islands report not awake.
  const Flags awake = protocolStep(isl, tracker, bodies, links, 0.01, settings);
  EXPECT_EQ(awake, (Flags{0, 0}));
}

TEST(Sleep, WakingPropagatesThroughAnIsland) {
  // Islands {0, 1} and {2, 3}, then body 4 moving on its own.
  auto bodies = makeBodies(5);
  bodies[4].setLinearVelocity(Vec3(1, 0, 0));
  Links links{{0, 1}, {2, 3}};
  Islands isl;
  step::SleepTracker tracker;
  tracker.resize(5);
  const SleepSettings settings;
  for (int n = 0; n < 50; ++n) protocolStep(isl, tracker, bodies, links, 0.01, settings);
  for (const int b : {0, 1, 2, 3}) ASSERT_TRUE(tracker.asleep(b));
  ASSERT_FALSE(tracker.asleep(4));

  // Two sleeping islands touching stay asleep together.
  links.emplace_back(1, 2);
  Flags awake = protocolStep(isl, tracker, bodies, links, 0.01, settings);
  EXPECT_EQ(awake, (Flags{0, 1}));
  for (const int b : {0, 1, 2, 3}) EXPECT_TRUE(tracker.asleep(b));

  // The moving body touches body 3: the whole island 0-1-2-3 wakes, timers from 0.
  links.back() = {4, 3};
  awake = protocolStep(isl, tracker, bodies, links, 0.01, settings);
  ASSERT_EQ(isl.count(), 2);
  EXPECT_EQ(list(isl.bodies(1)), (std::vector<int>{2, 3, 4}));
  EXPECT_EQ(awake, (Flags{0, 1}));
  for (const int b : {0, 1}) EXPECT_TRUE(tracker.asleep(b));
  for (const int b : {2, 3}) {
    EXPECT_FALSE(tracker.asleep(b));
    EXPECT_NEAR(tracker.restTime(b), 0.01, 1e-15);  // reset on waking, then one step at rest
  }

  // wake() on one body of a sleeping island wakes the island at the next step.
  tracker.wake(1);
  EXPECT_FALSE(tracker.asleep(1));
  EXPECT_TRUE(tracker.asleep(0));
  Islands again;
  again.build(5, movableOf(bodies), links);
  const auto flags = tracker.wakeIslands(again);
  EXPECT_EQ(Flags(flags.begin(), flags.end()), (Flags{1, 1}));
  EXPECT_EQ(Flags(tracker.islandAwake().begin(), tracker.islandAwake().end()), (Flags{1, 1}));
  for (int b = 0; b < 5; ++b) {
    EXPECT_FALSE(tracker.asleep(b));
    if (b <= 1) {
      EXPECT_EQ(tracker.restTime(b), 0.0);
    }
  }
}

TEST(Sleep, DisabledNothingSleepsAndSleepersWake) {
  auto bodies = makeBodies(2);
  Islands isl;
  step::SleepTracker tracker;
  tracker.resize(2);
  SleepSettings settings;
  for (int n = 0; n < 50; ++n) protocolStep(isl, tracker, bodies, {}, 0.01, settings);
  ASSERT_TRUE(tracker.asleep(0));
  settings.enabled = false;
  for (int n = 0; n < 100; ++n) {
    protocolStep(isl, tracker, bodies, {}, 0.01, settings);
    ASSERT_FALSE(tracker.asleep(0));
    ASSERT_FALSE(tracker.asleep(1));
  }
}

TEST(Sleep, ResizeKeepsStateAndChecksSizes) {
  auto bodies = makeBodies(2);
  Islands isl;
  step::SleepTracker tracker;
  tracker.resize(2);
  const SleepSettings settings;
  for (int n = 0; n < 50; ++n) protocolStep(isl, tracker, bodies, {}, 0.01, settings);
  tracker.resize(3);
  EXPECT_TRUE(tracker.asleep(0));
  EXPECT_FALSE(tracker.asleep(2));
  EXPECT_EQ(tracker.restTime(2), 0.0);
  EXPECT_THROW(tracker.wakeIslands(isl), std::invalid_argument);  // islands of 2 bodies
}

TEST(Sleep, NoAllocationOnceWarm) {
  auto bodies = makeBodies(50, {0});
  Links links;
  for (int i = 1; i < 50; ++i) links.emplace_back(i % 5 == 1 ? 0 : i - 1, i);
  const Flags movable = movableOf(bodies);
  Islands isl;
  step::SleepTracker tracker;
  tracker.resize(50);
  const SleepSettings settings;
  isl.build(50, movable, links);
  tracker.wakeIslands(isl);
  tracker.update(isl, bodies, 0.01, settings);
  const long before = g_allocations.load();
  for (int n = 0; n < 100; ++n) {
    isl.build(50, movable, links);
    tracker.wakeIslands(isl);
    tracker.update(isl, bodies, 0.01, settings);
  }
  EXPECT_EQ(g_allocations.load(), before);
  EXPECT_TRUE(tracker.asleep(1));
}

}  // namespace
}  // namespace linx
