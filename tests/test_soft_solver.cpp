// The soft step's row solver (solver/soft_solver.hpp). Its wide sweep solves kLanes blocks of a
// colour side by side; it must give each block exactly what the scalar sweep, one block at a
// time, gives: checked to the bit on random contact manifolds between random bodies (heavy and
// light, spinning, static ends, speculative gaps and penetrations, points fewer than the lanes
// hold), with more manifolds than 64 colours so that some are solved in the overflow set.
// And a physical check of the rows themselves: a box resting on the ground on four points takes
// its weight, and friction holds it on a slope below atan(mu) and lets it slide above.
#include "solver/soft_solver.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <numbers>
#include <random>
#include <vector>

namespace linx::solver {
namespace {

struct Contacts {
  std::vector<Row> rows;
  std::vector<int> manifold;
  std::vector<SolverBody> bodies;
  std::vector<double> lambda;
};

/// One contact point between bodies a and b (b may be -1: the world), at `ra` and `rb` from
/// their centres, along `normal`: a unilateral row and two friction rows.
void addPoint(Contacts& c, int a, int b, const Vec3& ra, const Vec3& rb, const Vec3& normal,
              double phi, double mu, int manifold) {
  const Vec3 t1 = normal.unitOrthogonal(), t2 = normal.cross(t1);
  const int first = static_cast<int>(c.rows.size());
  for (int k = 0; k < 3; ++k) {
    const Vec3 d = k == 0 ? normal : k == 1 ? t1 : t2;
    Row r;
    r.Ja << -d, -ra.cross(d);
    if (b >= 0) r.Jb << d, rb.cross(d);
    r.body_a = a;
    r.body_b = b;
    if (k == 0) {
      r.kind = RowKind::Unilateral;
      r.lo = 0.0;
      r.phi = phi;
    } else {
      r.kind = RowKind::Friction;
      r.normal = first;
      r.mu = mu;
    }
    c.rows.push_back(r);
    c.manifold.push_back(k == 0 ? manifold : -1);
    c.lambda.push_back(0.0);
  }
}

Contacts randomContacts(std::uint32_t seed, int count_bodies, int count_manifolds) {
  std::mt19937 random(seed);
  std::uniform_real_distribution<double> unit(-1.0, 1.0), positive(0.1, 10.0);
  std::uniform_int_distribution<int> body(0, count_bodies - 1), points(1, 4);
  Contacts c;
  for (int i = 0; i < count_bodies; ++i) {
    SolverBody s;
    if (i % 7 != 3) {  // every seventh body static
      s.inv_mass = 1.0 / positive(random);
      const Vec3 d(positive(random), positive(random), positive(random));
      s.inv_inertia = d.cwiseInverse().asDiagonal();
    }
    s.v = Vec3(unit(random), unit(random), unit(random));
    s.w = Vec3(unit(random), unit(random), unit(random));
    c.bodies.push_back(s);
  }
  for (int m = 0; m < count_manifolds; ++m) {
    const int a = body(random);
    int b = body(random);
    if (b == a || m % 5 == 0) b = -1;  // against the world
    const Vec3 normal = Vec3(unit(random), unit(random), unit(random)).normalized();
    const double mu = m % 9 == 0 ? 0.0 : 0.5 * (1.0 + unit(random));
    for (int p = 0, n = points(random); p < n; ++p) {
      const Vec3 ra(unit(random), unit(random), unit(random));
      const Vec3 rb(unit(random), unit(random), unit(random));
      addPoint(c, a, b, ra, rb, normal, 0.01 * unit(random), mu, m);
      c.lambda.end()[-3] = std::max(0.0, unit(random));  // warm start
    }
  }
  // One body in more manifolds than there are colours: some go to the overflow set.
  for (int m = 0; m < 80; ++m)
    addPoint(c, 0, 1 + m % (count_bodies - 1), Vec3(0.1, 0, 0), Vec3(0, 0.1, 0), Vec3::UnitZ(),
             -0.001, 0.4, count_manifolds + m);
  return c;
}

/// Four substeps of the soft step's solver, as step/step.cpp drives it (without gravity).
SoftSolver run(const Contacts& c, bool wide, int threads) {
  SoftSolver solver;
  SoftSolver::Settings s;
  s.h = 1.0 / 240.0;
  s.substeps = 4;
  s.contact = Softness::of(30.0, 10.0, s.h);
  s.threads = threads;
  s.wide = wide;
  const std::vector<std::uint8_t> active(c.rows.size(), 1);
  solver.prepare(c.rows, c.lambda, active, c.manifold, c.bodies, s);
  for (int k = 0; k < s.substeps; ++k) {
    solver.warmStart();
    solver.solve();
    solver.push();
    solver.move(s.h);
    solver.relax();
    solver.accumulate();
  }
  return solver;
}

TEST(SoftSolver, WideSweepIsTheScalarSweepToTheBit) {
  for (const std::uint32_t seed : {1u, 2u, 3u}) {
    const Contacts c = randomContacts(seed, 300, 2000);
    SoftSolver scalar = run(c, false, 1);
    for (const int threads : {1, 2}) {
      SoftSolver wide = run(c, true, threads);
      ASSERT_EQ(wide.lambda().size(), c.rows.size());
      for (std::size_t k = 0; k < c.rows.size(); ++k) {
        ASSERT_EQ(wide.lambda()[k], scalar.lambda()[k]) << "row " << k << ", seed " << seed;
        ASSERT_EQ(wide.total()[k], scalar.total()[k]) << "row " << k << ", seed " << seed;
      }
      for (std::size_t i = 0; i < c.bodies.size(); ++i) {
        const SoftSolver::Body& w = wide.bodies()[i];
        const SoftSolver::Body& s = scalar.bodies()[i];
        for (int d = 0; d < 3; ++d) {
          ASSERT_EQ(w.v[d], s.v[d]) << "body " << i << ", seed " << seed;
          ASSERT_EQ(w.w[d], s.w[d]) << "body " << i << ", seed " << seed;
          ASSERT_EQ(w.dp[d], s.dp[d]) << "body " << i << ", seed " << seed;
        }
      }
    }
  }
}

/// A 1 kg box of half-size 0.1 m on the ground, its four bottom corners in contact, on a slope
/// of `angle` (the ground's normal tilted about x), at rest: the substeps with gravity.
struct Box {
  SoftSolver solver;
  Vec3 v;
  double normal_total = 0.0;
};

Box restingBox(double angle, double mu) {
  const double m = 1.0, a = 0.1, g = 9.81, h = 1.0 / 240.0;
  const Vec3 normal(0.0, -std::sin(angle), std::cos(angle));
  const Vec3 t = Vec3(0.0, std::cos(angle), std::sin(angle));
  Contacts c;
  SolverBody body;
  body.inv_mass = 1.0 / m;
  const double inertia = m * (2.0 * a) * (2.0 * a) / 6.0;
  body.inv_inertia = Mat3::Identity() / inertia;
  c.bodies.push_back(body);
  for (const double x : {-a, a})
    for (const double y : {-a, a}) {
      const Vec3 r = Vec3(x, 0.0, 0.0) + y * t - a * normal;  // a corner, from the centre
      addPoint(c, 0, -1, r, Vec3::Zero(), -normal, 0.0, mu, 0);
      // addPoint's normal row pushes b along +normal and a against it: a is the box, the
      // world is b, so the row's direction is the ground's normal reversed.
    }
  Box box;
  SoftSolver::Settings s;
  s.h = h;
  s.substeps = 4;
  s.contact = Softness::of(30.0, 10.0, h);
  const std::vector<std::uint8_t> active(c.rows.size(), 1);
  std::vector<double> lambda = c.lambda;
  std::vector<SolverBody> bodies = c.bodies;
  for (int step = 0; step < 240; ++step) {  // 4 s
    box.solver.prepare(c.rows, lambda, active, c.manifold, bodies, s);
    for (int k = 0; k < s.substeps; ++k) {
      box.solver.bodies()[0].v += h * Vec3(0.0, 0.0, -g);
      box.solver.warmStart();
      box.solver.solve();
      box.solver.push();
      box.solver.move(h);
      box.solver.relax();
      box.solver.accumulate();
    }
    lambda.assign(box.solver.lambda().begin(), box.solver.lambda().end());
    bodies[0].v = box.solver.bodies()[0].v;
    bodies[0].w = box.solver.bodies()[0].w;
  }
  box.v = bodies[0].v;
  for (std::size_t k = 0; k < c.rows.size(); k += 3) box.normal_total += box.solver.total()[k];
  return box;
}

TEST(SoftSolver, BoxOnTheGroundTakesItsWeightAndFrictionHoldsItBelowTheFrictionAngle) {
  const double g = 9.81, dt = 4.0 / 240.0;
  // Flat: the four points carry the weight over the step, m g dt, and the box stays at rest.
  const Box flat = restingBox(0.0, 0.5);
  EXPECT_NEAR(flat.normal_total, g * dt, 1e-3 * g * dt);
  EXPECT_LT(flat.v.norm(), 2e-3);  // sliding would reach metres per second
  // Below the friction angle (tan 0.3 rad = 0.31 < mu 0.5) it sticks; above it (mu 0.2) it slides
  // down with acceleration g (sin - mu cos): to 5 %, since the two friction rows each take
  // mu times the manifold's mean normal impulse (a pyramid, not a cone).
  const double angle = 0.3;
  const Box sticks = restingBox(angle, 0.5);
  EXPECT_LT(sticks.v.norm(), 2e-3);
  EXPECT_NEAR(sticks.normal_total, g * std::cos(angle) * dt, 1e-3 * g * dt);
  const Box slides = restingBox(angle, 0.2);
  const double speed = g * (std::sin(angle) - 0.2 * std::cos(angle)) * 4.0;
  EXPECT_NEAR(slides.v.norm(), speed, 0.05 * speed);
}

}  // namespace
}  // namespace linx::solver
