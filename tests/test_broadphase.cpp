// Broadphase: world AABBs of the shapes (checked against sampled surface points) and sweep and
// prune (checked against the O(n^2) all-pairs reference on random, touching, identical,
// degenerate and moving boxes), plus its cost: 10,000 boxes at constant density must cost well
// under 100x what 1,000 do (n log n gives ~13x, n^2 would give 100x).
#include "support.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <new>
#include <random>
#include <vector>

#include "collision/aabb.hpp"
#include "collision/broadphase.hpp"

// Count heap allocations, to check that a repeated update allocates nothing. malloc and free
// sit behind functions GCC does not inline, or it would warn of a new/free mismatch.
namespace {
std::atomic<long> g_allocations{0};
[[gnu::noinline]] void* countedMalloc(std::size_t size) {
  g_allocations.fetch_add(1, std::memory_order_relaxed);
  return std::malloc(size == 0 ? 1 : size);
}
[[gnu::noinline]] void countedFree(void* p) {
  std::free(p);
}
}  // namespace
void* operator new(std::size_t size) {
  if (void* p = countedMalloc(size)) return p;
  throw std::bad_alloc();
}
void operator delete(void* p) noexcept {
  countedFree(p);
}
void operator delete(void* p, std::size_t) noexcept {
  countedFree(p);
}

namespace linx::collision {
namespace {

using test::kSanitized;

constexpr double kPi = 3.14159265358979323846;

Quat randomRotation(std::mt19937& rng) {
  std::normal_distribution<double> g(0.0, 1.0);
  return Quat(g(rng), g(rng), g(rng), g(rng)).normalized();
}

Vec3 randomVec(std::mt19937& rng, double lo, double hi) {
  std::uniform_real_distribution<double> u(lo, hi);
  return Vec3(u(rng), u(rng), u(rng));
}

/// Roughly uniform unit vectors (Fibonacci sphere).
std::vector<Vec3> sphereDirections(int n) {
  std::vector<Vec3> dirs;
  const double golden = kPi * (3.0 - std::sqrt(5.0));
  for (int k = 0; k < n; ++k) {
    const double z = 1.0 - (2.0 * k + 1.0) / n;
    const double r = std::sqrt(std::max(0.0, 1.0 - z * z));
    dirs.emplace_back(r * std::cos(golden * k), r * std::sin(golden * k), z);
  }
  dirs.emplace_back(1, 0, 0);
  dirs.emplace_back(-1, 0, 0);
  dirs.emplace_back(0, 1, 0);
  dirs.emplace_back(0, -1, 0);
  dirs.emplace_back(0, 0, 1);
  dirs.emplace_back(0, 0, -1);
  return dirs;
}

/// Points on the surface of the shape, in the shape frame (includes all the extreme features).
/// q is the shape-to-world rotation: the sphere also gets its six world-axis poles.
std::vector<Vec3> surfaceSamples(const ShapeDef& s, const Quat& q) {
  std::vector<Vec3> pts;
  switch (s.type) {
    case ShapeType::Sphere:
      for (const Vec3& d : sphereDirections(4000)) pts.push_back(s.radius * d);
      for (int i = 0; i < 3; ++i) {
        pts.push_back(s.radius * (q.conjugate() * Vec3::Unit(i)));
        pts.push_back(-s.radius * (q.conjugate() * Vec3::Unit(i)));
      }
      break;
    case ShapeType::Box:
      for (int corner = 0; corner < 8; ++corner) {
        const Vec3 sign((corner & 1) ? 1 : -1, (corner & 2) ? 1 : -1, (corner & 4) ? 1 : -1);
        pts.push_back(0.5 * s.size.cwiseProduct(sign));
      }
      break;
    case ShapeType::Capsule:
      for (const Vec3& d : sphereDirections(40000)) {
        const double end = d.z() >= 0.0 ? 0.5 * s.length : -0.5 * s.length;
        pts.push_back(Vec3(0, 0, end) + s.radius * d);
      }
      break;
    case ShapeType::Cylinder:
      for (int k = 0; k < 8192; ++k) {
        const double t = 2.0 * kPi * k / 8192;
        for (double z : {-0.5 * s.length, 0.0, 0.5 * s.length})
          pts.emplace_back(s.radius * std::cos(t), s.radius * std::sin(t), z);
        pts.emplace_back(0.5 * s.radius * std::cos(t), 0.5 * s.radius * std::sin(t),
                         0.5 * s.length);
      }
      break;
    default:  // planes, hulls and meshes are tested with their own AABBs
      break;
  }
  return pts;
}

void checkShapeAabb(const ShapeDef& shape, const Pose& pose, double tol) {
  const Aabb box = shapeAabb(shape, pose);
  const Quat q = pose.orientation * shape.orientation;
  Vec3 lo = Vec3::Constant(kInfinity), hi = Vec3::Constant(-kInfinity);
  for (const Vec3& p : surfaceSamples(shape, q)) {
    const Vec3 w = pose.toWorld(shape.position + shape.orientation * p);
    lo = lo.cwiseMin(w);
    hi = hi.cwiseMax(w);
  }
  const double slack = 1e-12 * (1.0 + pose.position.norm() + shape.position.norm());
  for (int i = 0; i < 3; ++i) {
    SCOPED_TRACE(::testing::Message() << shapeTypeName(shape.type) << " axis " << i);
    EXPECT_LE(box.min[i], lo[i] + slack);  // contains every sample
    EXPECT_GE(box.max[i], hi[i] - slack);
    EXPECT_NEAR(box.min[i], lo[i], tol + slack);  // and is tight
    EXPECT_NEAR(box.max[i], hi[i], tol + slack);
  }
}

TEST(ShapeAabb, MatchesSampledExtremesAtRandomRotations) {
  std::mt19937 rng(7);
  std::vector<Quat> rotations{Quat::Identity(), Quat(Eigen::AngleAxisd(kPi / 2, Vec3::UnitX())),
                              Quat(Eigen::AngleAxisd(kPi / 2, Vec3::UnitY())),
                              Quat(Eigen::AngleAxisd(kPi / 4, Vec3::UnitZ()))};
  for (int k = 0; k < 12; ++k) rotations.push_back(randomRotation(rng));
  for (const Quat& body_q : rotations) {
    const Pose pose{randomVec(rng, -5, 5), body_q};
    ShapeDef s;
    s.position = randomVec(rng, -0.5, 0.5);
    s.orientation = randomRotation(rng);
    s.radius = 0.3;
    s.length = 1.2;
    s.size = Vec3(0.4, 1.0, 2.2);
    s.type = ShapeType::Sphere;
    checkShapeAabb(s, pose, 1e-12);  // the world-axis poles are the exact extremes
    s.type = ShapeType::Box;
    checkShapeAabb(s, pose, 1e-12);  // corners are the exact extremes
    s.type = ShapeType::Capsule;
    checkShapeAabb(s, pose, 2e-3 * s.radius);  // sampling gap on the end spheres
    s.type = ShapeType::Cylinder;
    checkShapeAabb(s, pose, 1e-6 * s.radius);  // sampling gap on the rims
    // Axis-aligned shape orientation: the cylinder's sqrt(1 - R_iz^2) reaches 0 and 1.
    s.orientation = Quat::Identity();
    checkShapeAabb(s, Pose{pose.position, Quat::Identity()}, 1e-12);
  }
}

TEST(ShapeAabb, ExactValuesForSimpleCases) {
  ShapeDef cyl;
  cyl.type = ShapeType::Cylinder;
  cyl.radius = 0.5;
  cyl.length = 2.0;
  cyl.position = Vec3(1, 0, 0);
  const Pose pose{Vec3(0, 0, 3), Quat(Eigen::AngleAxisd(kPi / 2, Vec3::UnitY()))};
  const Aabb box = shapeAabb(cyl, pose);  // axis along world x, centre at (0, 0, 2)
  EXPECT_TRUE(box.min.isApprox(Vec3(-1.0, -0.5, 1.5), 1e-12)) << box.min.transpose();
  EXPECT_TRUE(box.max.isApprox(Vec3(1.0, 0.5, 2.5), 1e-12)) << box.max.transpose();

  const Aabb a{Vec3(0, 0, 0), Vec3(1, 1, 1)};
  const Aabb b{Vec3(1, 0.5, -1), Vec3(2, 2, 0)};  // touches a on x = 1 and z = 0
  EXPECT_TRUE(a.overlaps(b));
  EXPECT_TRUE(b.overlaps(a));
  EXPECT_FALSE(a.overlaps(Aabb{Vec3(1.0 + 1e-12, 0, 0), Vec3(2, 1, 1)}));
  const Aabb m = a.merged(b);
  EXPECT_EQ(m.min, Vec3(0, 0, -1));
  EXPECT_EQ(m.max, Vec3(2, 2, 1));
  Aabb e = a.expanded(0.25);
  EXPECT_EQ(e.min, Vec3::Constant(-0.25));
  EXPECT_EQ(e.max, Vec3::Constant(1.25));
  e.merge(Aabb{Vec3::Constant(5), Vec3::Constant(5)});
  EXPECT_EQ(e.max, Vec3::Constant(5));
}

using Pairs = std::vector<std::pair<int, int>>;

Pairs bruteForce(const std::vector<Aabb>& boxes) {
  Pairs out;
  const int n = static_cast<int>(boxes.size());
  for (int i = 0; i < n; ++i)
    for (int j = i + 1; j < n; ++j)
      if (boxes[i].overlaps(boxes[j])) out.emplace_back(i, j);
  return out;
}

/// n boxes, half sizes in [0.5, 1.5] * half, in a cube of edge chosen for ~overlaps per box.
std::vector<Aabb> randomBoxes(std::mt19937& rng, int n, double half = 0.1,
                              double overlaps_per_box = 3.0) {
  // Two boxes of mean half size h overlap when their centres are within ~2h on every axis.
  const double edge = 4.0 * half * std::cbrt(std::max(1, n) / overlaps_per_box);
  std::uniform_real_distribution<double> pos(0.0, edge), size(0.5 * half, 1.5 * half);
  std::vector<Aabb> boxes;
  for (int i = 0; i < n; ++i) {
    const Vec3 c(pos(rng), pos(rng), pos(rng));
    boxes.push_back(Aabb::fromCentre(c, Vec3(size(rng), size(rng), size(rng))));
  }
  return boxes;
}

void expectMatchesBruteForce(SweepAndPrune& sap, const std::vector<Aabb>& boxes) {
  sap.update(boxes);
  const Pairs expected = bruteForce(boxes);
  ASSERT_EQ(sap.pairs().size(), expected.size()) << "n = " << boxes.size();
  EXPECT_TRUE(sap.pairs() == expected) << "n = " << boxes.size();
}

TEST(SweepAndPrune, EmptyAndSingle) {
  SweepAndPrune sap;
  sap.update({});
  EXPECT_TRUE(sap.pairs().empty());
  std::vector<Aabb> one{Aabb{Vec3::Zero(), Vec3::Ones()}};
  sap.update(one);
  EXPECT_TRUE(sap.pairs().empty());
  std::vector<Aabb> two{one[0], one[0]};
  sap.update(two);
  ASSERT_EQ(sap.pairs().size(), 1u);
  EXPECT_EQ(sap.pairs()[0], std::make_pair(0, 1));
  sap.update({});
  EXPECT_TRUE(sap.pairs().empty());
}

TEST(SweepAndPrune, MatchesBruteForceOnRandomSets) {
  std::mt19937 rng(11);
  SweepAndPrune sap;  // one object across changing counts: exercises the re-sort fallback
  for (int n : {2, 3, 5, 10, 50, 200, 1000, 3000}) {
    for (double density : {0.3, 3.0, 30.0}) {
      SCOPED_TRACE(::testing::Message() << "n " << n << " density " << density);
      expectMatchesBruteForce(sap, randomBoxes(rng, n, 0.1, density));
      SweepAndPrune fresh;
      expectMatchesBruteForce(fresh, randomBoxes(rng, n, 0.1, density));
    }
  }
}

TEST(SweepAndPrune, TouchingIdenticalAndDegenerateBoxes) {
  std::mt19937 rng(3);
  std::vector<Aabb> boxes;
  // A 6 x 6 x 3 lattice of unit cubes sharing faces, edges and corners.
  for (int x = 0; x < 6; ++x)
    for (int y = 0; y < 6; ++y)
      for (int z = 0; z < 3; ++z) boxes.push_back(Aabb{Vec3(x, y, z), Vec3(x + 1, y + 1, z + 1)});
  // Identical boxes, several times over.
  for (int k = 0; k < 5; ++k) boxes.push_back(Aabb{Vec3(2.5, 2.5, 1.5), Vec3(3.5, 3.5, 2.5)});
  // Zero-size boxes: lattice points (on corners of many cubes), coincident points, points
  // inside and outside, and flat boxes.
  for (int k = 0; k < 20; ++k) {
    const Vec3 p(std::uniform_int_distribution<int>(0, 7)(rng),
                 std::uniform_int_distribution<int>(0, 7)(rng),
                 std::uniform_int_distribution<int>(0, 4)(rng));
    boxes.push_back(Aabb{p, p});
    boxes.push_back(Aabb{p, p});
  }
  for (int k = 0; k < 20; ++k) {
    const Vec3 p = randomVec(rng, -1, 7);
    boxes.push_back(Aabb{p, p});
  }
  boxes.push_back(Aabb{Vec3(-1, -1, 3), Vec3(7, 7, 3)});  // flat lid touching the top layer
  std::shuffle(boxes.begin(), boxes.end(), rng);
  SweepAndPrune sap;
  expectMatchesBruteForce(sap, boxes);
  EXPECT_GT(sap.pairs().size(), 500u);

  // All boxes on a line, in a plane, and all identical (zero variance on some or all axes).
  std::vector<Aabb> line, plane, same;
  for (int k = 0; k < 300; ++k) {
    const double t = 0.05 * k;
    line.push_back(Aabb::fromCentre(Vec3(t, 0, 0), Vec3(0.06, 0.1, 0.1)));
    plane.push_back(Aabb::fromCentre(Vec3(std::fmod(t, 1.0), 0, t), Vec3::Constant(0.03)));
    same.push_back(Aabb{Vec3::Zero(), Vec3::Zero()});
  }
  expectMatchesBruteForce(sap, line);
  expectMatchesBruteForce(sap, plane);
  expectMatchesBruteForce(sap, same);
  EXPECT_EQ(sap.pairs().size(), 300u * 299u / 2u);
}

TEST(SweepAndPrune, InfiniteAndNanBoxes) {
  std::mt19937 rng(5);
  std::vector<Aabb> boxes = randomBoxes(rng, 300);
  const double inf = kInfinity;
  boxes.push_back(Aabb{Vec3(-inf, -inf, -inf), Vec3(inf, inf, 0.1)});  // a ground half-space
  boxes.push_back(Aabb{Vec3(-inf, 0.2, 0.2), Vec3(inf, 0.3, 0.3)});    // an infinite rod
  const double nan = std::numeric_limits<double>::quiet_NaN();
  boxes.push_back(Aabb{Vec3(nan, 0, 0), Vec3(1, 1, 1)});  // overlaps nothing
  boxes.push_back(Aabb{Vec3(0, 0, 0), Vec3(1, nan, 1)});
  std::shuffle(boxes.begin(), boxes.end(), rng);
  SweepAndPrune sap;
  expectMatchesBruteForce(sap, boxes);
  expectMatchesBruteForce(sap, boxes);
}

TEST(SweepAndPrune, FewHugeBoxesAmongManySmall) {
  // Large boxes make the columns coarse (their copies are capped); results must not change.
  std::mt19937 rng(23);
  std::vector<Aabb> boxes = randomBoxes(rng, 3000);
  for (int k = 0; k < 40; ++k) boxes.push_back(Aabb{randomVec(rng, -1, 0), randomVec(rng, 3, 5)});
  for (int k = 0; k < 40; ++k) {  // rods along each axis
    Aabb rod = Aabb::fromCentre(randomVec(rng, 0, 3), Vec3::Constant(0.05));
    rod.min[k % 3] = -1.0;
    rod.max[k % 3] = 5.0;
    boxes.push_back(rod);
  }
  std::shuffle(boxes.begin(), boxes.end(), rng);
  SweepAndPrune sap;
  expectMatchesBruteForce(sap, boxes);

  // Points plus ten boxes around everything: the fine grid the points ask for would copy the
  // big boxes ~30,000 times, over the cap, so the grid is coarsened.
  std::vector<Aabb> points;
  for (int k = 0; k < 3000; ++k) {
    const Vec3 p = randomVec(rng, 0, 10);
    points.push_back(Aabb{p, p});
  }
  for (int k = 0; k < 10; ++k)
    points.push_back(Aabb{randomVec(rng, -2, 0), randomVec(rng, 10, 12)});
  std::shuffle(points.begin(), points.end(), rng);
  expectMatchesBruteForce(sap, points);
  EXPECT_EQ(sap.pairs().size(), 10u * 3000u + 45u);
  EXPECT_LE(sap.cellCounts()[0] * sap.cellCounts()[1], 2500);
}

TEST(SweepAndPrune, CoherentUpdatesStayExactAndIncremental) {
  std::mt19937 rng(17);
  std::vector<Aabb> boxes = randomBoxes(rng, 2000);
  std::vector<Vec3> velocity;
  for (std::size_t i = 0; i < boxes.size(); ++i) velocity.push_back(randomVec(rng, -1, 1));
  SweepAndPrune sap;
  expectMatchesBruteForce(sap, boxes);
  int incremental = 0;
  const int steps = 40;
  for (int step = 0; step < steps; ++step) {
    for (std::size_t i = 0; i < boxes.size(); ++i) {  // 1 m/s for 5 ms: a fraction of a box
      boxes[i].min += 0.005 * velocity[i];
      boxes[i].max += 0.005 * velocity[i];
    }
    expectMatchesBruteForce(sap, boxes);
    incremental += sap.lastUpdateIncremental() ? 1 : 0;
  }
  EXPECT_GE(incremental, steps - 2);  // an axis switch may force a full sort

  // A big jump (every box teleported): still exact, through the std::sort fallback.
  std::shuffle(boxes.begin(), boxes.end(), rng);
  expectMatchesBruteForce(sap, boxes);
  EXPECT_FALSE(sap.lastUpdateIncremental());

  // A repeated update at a constant count allocates nothing.
  sap.update(boxes);
  const long before = g_allocations.load();
  sap.update(boxes);
  for (auto& b : boxes) b = b.expanded(-1e-4);  // fewer pairs: no growth either
  sap.update(boxes);
  EXPECT_EQ(g_allocations.load() - before, 0);
}

double medianSeconds(std::vector<double> t) {
  std::sort(t.begin(), t.end());
  return t[t.size() / 2];
}

struct Timing {
  double fresh = 0.0;     // new SweepAndPrune: full std::sort (median, s)
  double coherent = 0.0;  // same object, boxes moved a little between calls (median, s)
  std::size_t pairs = 0;
  std::size_t tests = 0;  // overlap tests of one update: the work, independent of the machine
};

Timing timeUpdates(int n, int runs, std::vector<Aabb>* out_boxes = nullptr) {
  std::mt19937 rng(1234 + n);
  std::vector<Aabb> boxes = randomBoxes(rng, n);
  using Clock = std::chrono::steady_clock;
  Timing timing;
  std::vector<double> fresh, coherent;
  for (int r = 0; r < runs; ++r) {
    SweepAndPrune sap;
    const auto t0 = Clock::now();
    sap.update(boxes);
    fresh.push_back(std::chrono::duration<double>(Clock::now() - t0).count());
    timing.pairs = sap.pairs().size();
    timing.tests = sap.lastTests();
  }
  SweepAndPrune sap;
  sap.update(boxes);
  std::uniform_real_distribution<double> jitter(-0.002, 0.002);
  for (int r = 0; r < runs; ++r) {
    for (Aabb& b : boxes) {
      const Vec3 d(jitter(rng), jitter(rng), jitter(rng));
      b.min += d;
      b.max += d;
    }
    const auto t0 = Clock::now();
    sap.update(boxes);
    coherent.push_back(std::chrono::duration<double>(Clock::now() - t0).count());
  }
  timing.fresh = medianSeconds(fresh);
  timing.coherent = medianSeconds(coherent);
  if (out_boxes) *out_boxes = boxes;
  return timing;
}

TEST(SweepAndPrune, ScalesLikeNLogN) {
  // Same density at both sizes (~3 overlaps per box). Medians of several runs: the machine is
  // shared, so the bound is generous (n log n: ~13x, sweep without columns: ~46x, n^2: 100x).
  const int big = 10000, small = 1000;
  std::vector<Aabb> boxes;
  const Timing t_small = timeUpdates(small, kSanitized ? 15 : 31);
  const Timing t_big = timeUpdates(big, kSanitized ? 5 : 9, &boxes);
  std::printf("[ broadphase ] n = %5d: %6zu pairs, update fresh %8.3f ms, coherent %8.3f ms\n",
              small, t_small.pairs, 1e3 * t_small.fresh, 1e3 * t_small.coherent);
  std::printf("[ broadphase ] n = %5d: %6zu pairs, update fresh %8.3f ms, coherent %8.3f ms\n", big,
              t_big.pairs, 1e3 * t_big.fresh, 1e3 * t_big.coherent);
  std::printf("[ broadphase ] ratio 10000/1000: fresh %.1fx, coherent %.1fx\n",
              t_big.fresh / t_small.fresh, t_big.coherent / t_small.coherent);
  EXPECT_GT(t_big.pairs, static_cast<std::size_t>(big));  // "a few" overlaps per box
  EXPECT_LT(t_big.pairs, static_cast<std::size_t>(5 * big));
  // The bound is on the work, which the shared machine's load cannot change: the overlap tests grow
  // about as n (each box meets the few boxes of its column that follow it along the sweep), far
  // from a single sweep's n^(5/3) (46x) or all pairs' n^2 (100x). The times are printed above.
  std::printf("[ broadphase ] overlap tests: %zu at n = %d, %zu at n = %d: %.1fx\n", t_small.tests,
              small, t_big.tests, big,
              static_cast<double>(t_big.tests) / static_cast<double>(t_small.tests));
  EXPECT_LT(static_cast<double>(t_big.tests) / static_cast<double>(t_small.tests), 15.0);

  // The pair set at 10,000 boxes equals all-pairs (50M tests, once).
  SweepAndPrune sap;
  sap.update(boxes);
  std::printf("[ broadphase ] sweep axis %d, columns %d x %d\n", sap.sweepAxis(),
              sap.cellCounts()[0], sap.cellCounts()[1]);
  EXPECT_GT(sap.cellCounts()[0] * sap.cellCounts()[1], 1);  // a single sweep is ~n^(5/3) here
  const auto t0 = std::chrono::steady_clock::now();
  const Pairs expected = bruteForce(boxes);
  std::printf("[ broadphase ] brute force at n = %d: %.1f ms\n", big,
              1e3 * std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  EXPECT_TRUE(sap.pairs() == expected);
}

}  // namespace
}  // namespace linx::collision
