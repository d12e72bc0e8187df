// The benchmark's own pieces: its accuracy figures against hand-made poses with known answers,
// its scenes against their stated sizes, and linx through the benchmark's adapter against closed
// forms (so the table's linx rows measure the engine the tests measure).
#include "engine.hpp"
#include "metrics.hpp"
#include "report.hpp"
#include "runner.hpp"
#include "scenes.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <string>
#include <string_view>
#include <thread>
#include <vector>

namespace bench {
namespace {

// An engine that does not move: poses come from the test.
class FixedPoses final : public Engine {
 public:
  explicit FixedPoses(const Scene& s) {
    for (const Body& b : s.bodies) poses.push_back({b.position, b.orientation});
  }
  void step() override {}
  Pose pose(int i) const override { return poses[static_cast<std::size_t>(i)]; }
  std::vector<Pose> poses;
};

TEST(BenchMetrics, JointSeparationIsTheAnchorGap) {
  const Scene s = hingeChain(3);
  FixedPoses e(s);
  Accuracy a(s);
  a.sample(e);
  EXPECT_EQ(a.value(), 0.0);
  e.poses[2].position += Vec3(0.0, 0.003, 0.004);  // joint 2's anchors part by 5 mm
  a.sample(e);
  EXPECT_NEAR(a.value(), 0.005, 1e-15);
  // Turning link 0 about its hinge (the world anchor at the origin) by 90 degrees moves its far
  // end, which joint 1 shares with link 1, from (0.1, 0, 0) to (0, 0, -0.1).
  Accuracy b(s);
  FixedPoses f(s);
  f.poses[0].orientation = Quat(Eigen::AngleAxisd(M_PI / 2, Vec3::UnitY()));
  f.poses[0].position = Vec3(0.0, 0.0, -0.05);
  b.sample(f);
  EXPECT_NEAR(b.value(), std::sqrt(2.0) * 0.1, 1e-12);
}

TEST(BenchMetrics, ABlownUpEngineReadsNaNForEver) {
  const Scene s = hingeChain(3);
  FixedPoses e(s);
  Accuracy a(s);
  e.poses[1].position.x() = NAN;
  a.sample(e);
  EXPECT_TRUE(std::isnan(a.value()));
  e.poses[1].position.x() = 0.15;  // back to where it was: the run still blew up
  a.sample(e);
  EXPECT_TRUE(std::isnan(a.value()));
}

TEST(BenchMetrics, PenetrationOfSpheresWallsAndDisplacement) {
  Scene s = pouredSpheres(8);
  FixedPoses e(s);
  Accuracy a(s);
  a.sample(e);
  EXPECT_EQ(a.value(), 0.0) << "the lattice starts apart and above the floor";
  // Lift the lattice out of the way, then put sphere 0 (body 5, after the five walls) 3 mm into
  // the floor, and sphere 1 2 mm into sphere 0.
  for (std::size_t i = 5; i < e.poses.size(); ++i) e.poses[i].position.z() += 1.0;
  const double r = s.bodies[5].shape.radius;
  e.poses[5].position = Vec3(0.0, 0.0, r - 0.003);
  e.poses[6].position = e.poses[5].position + Vec3(2.0 * r - 0.002, 0.0, 0.0);
  a.sample(e);
  EXPECT_NEAR(a.value(), 0.003, 1e-12);

  Scene p = pyramid(3);
  FixedPoses q(p);
  Accuracy d(p);
  q.poses[4].position += Vec3(0.0, 0.0, -0.02);
  d.sample(q);
  EXPECT_NEAR(d.value(), 0.02, 1e-15);
}

TEST(BenchMetrics, PistonErrorIsZeroOnTheClosedForm) {
  const Scene s = sliderCrank();
  FixedPoses e(s);
  Accuracy a(s);
  const double r = 0.1, l = 0.3, phi = 0.7;
  e.poses[0].orientation = Quat(Eigen::AngleAxisd(phi, Vec3::UnitZ()));
  e.poses[0].position = e.poses[0].orientation * Vec3(0.05, 0.0, 0.0);
  e.poses[2].position =
      Vec3(r * std::cos(phi) + std::sqrt(l * l - std::pow(r * std::sin(phi), 2)), 0, 0);
  a.sample(e);
  EXPECT_NEAR(a.value(), 0.0, 1e-15);
  e.poses[2].position.x() += 0.001;
  a.sample(e);
  EXPECT_NEAR(a.value(), 0.001, 1e-12);
}

// An engine whose poses and velocities come from the test.
class FixedStates final : public Engine {
 public:
  explicit FixedStates(const Scene& s) {
    for (const Body& b : s.bodies) {
      poses.push_back({b.position, b.orientation});
      twists.push_back({b.velocity, b.angular_velocity});
    }
  }
  void step() override {}
  Pose pose(int i) const override { return poses[static_cast<std::size_t>(i)]; }
  Twist velocity(int i) const override { return twists[static_cast<std::size_t>(i)]; }
  std::vector<Pose> poses;
  std::vector<Twist> twists;
};

// One link of the chain, hanging straight down from its hinge at the origin and turning about y:
// released at rest level with the hinge, it has lost m g r of potential energy (r = 0.05 m, its
// centre's drop), which is all kinetic at w^2 = 2 m g r / (m r^2 + I_yy).
TEST(BenchMetrics, EnergyIsKineticPlusPotentialAgainstTheStart) {
  const Scene s = hingeChain(1);
  ASSERT_TRUE(s.energy);
  const Body& b = s.bodies[0];
  const double g = 9.81, r = 0.05;
  const double w = std::sqrt(2.0 * b.mass * g * r / (b.mass * r * r + b.inertia.y()));
  FixedStates e(s);
  Energy a(s);
  a.sample(e);
  EXPECT_EQ(a.rise(), 0.0);
  EXPECT_EQ(a.end(), 0.0);
  e.poses[0].position = Vec3(0.0, 0.0, -r);
  e.poses[0].orientation = Quat(Eigen::AngleAxisd(M_PI / 2, Vec3::UnitY()));
  e.twists[0].angular = Vec3(0.0, w, 0.0);
  e.twists[0].linear = e.twists[0].angular.cross(e.poses[0].position);
  a.sample(e);
  EXPECT_NEAR(a.rise(), 0.0, 1e-12);
  EXPECT_NEAR(a.end(), 0.0, 1e-12);
  // 2 % more kinetic energy: a rise of 0.02 / 1.02 of the largest kinetic energy.
  e.twists[0].angular *= std::sqrt(1.02);
  e.twists[0].linear *= std::sqrt(1.02);
  a.sample(e);
  EXPECT_NEAR(a.rise(), 100.0 * 0.02 / 1.02, 1e-9);
  // Back at the start, at rest: the end change is zero, the rise stays.
  e.poses[0] = {b.position, b.orientation};
  e.twists[0] = {};
  a.sample(e);
  EXPECT_NEAR(a.rise(), 100.0 * 0.02 / 1.02, 1e-9);
  EXPECT_NEAR(a.end(), 0.0, 1e-12);
  EXPECT_NEAR(a.drift(), 100.0 * 0.02 / 1.02, 1e-9);
  // 3 % of it lost: the drift is the larger change either way.
  e.poses[0].position.z() -= 0.03 * (1.02 * b.mass * r * g) / (b.mass * g);
  a.sample(e);
  EXPECT_NEAR(a.end(), -100.0 * 0.03, 1e-9);
  EXPECT_NEAR(a.drift(), 100.0 * 0.03, 1e-9);
  // An engine without velocities (the default) reads NaN, for good.
  FixedPoses f(s);
  a.sample(f);
  EXPECT_TRUE(std::isnan(a.rise()));
  a.sample(e);
  EXPECT_TRUE(std::isnan(a.end()));
}

TEST(BenchScenes, SizesAreAsStated) {
  EXPECT_EQ(pyramid(100).bodies.size(), 5050u);
  EXPECT_EQ(pouredSpheres(1000).bodies.size(), 1005u);  // five static walls
  EXPECT_EQ(ragdolls(100).bodies.size(), 1100u);
  EXPECT_EQ(ragdolls(100).joints.size(), 1000u);
  EXPECT_EQ(hingeChain(1000).joints.size(), 1000u);
  EXPECT_EQ(hingeChain(10, 1000.0).bodies.back().mass, 1000.0);
}

// The integrator table's mechanisms: each known path starts where its point is, A02's published
// positions are met only at their instants, and the sizes are the benchmark's.
TEST(BenchScenes, MechanismPathsStartAtTheirPoints) {
  for (const Scene& s :
       {pendulumA01(1.0), fourBarA02(1.0), heavyTop(1.0), spatialSliderCrank(1.0)}) {
    ASSERT_EQ(s.metric, Metric::PathError) << s.name;
    ASSERT_TRUE(s.path.has_value()) << s.name;
    ASSERT_TRUE(s.energy) << s.name;
    const Body& b = s.bodies[static_cast<std::size_t>(s.path->body)];
    const Vec3 point = b.position + b.orientation * s.path->point;
    if (s.name == "A02 four-bar") {
      EXPECT_FALSE(s.path->at(0.0).has_value());
      ASSERT_TRUE(s.path->at(0.05).has_value());
      // B0 at 0.05 s: the crank turned by about 0.05 rad from upright, clockwise.
      EXPECT_NEAR((*s.path->at(0.05) - Eigen::AngleAxisd(-0.05, Vec3::UnitZ()) * point).norm(), 0.0,
                  1e-3);
    } else {
      ASSERT_TRUE(s.path->at(0.0).has_value());
      EXPECT_NEAR((*s.path->at(0.0) - point).norm(), 0.0, 1e-12) << s.name;
    }
  }
  EXPECT_EQ(fourBarA02(1.0).bodies.size(), 81u);
  EXPECT_EQ(fourBarA02(1.0).joints.size(), 121u);
  EXPECT_EQ(pendulumA01(100.0).steps, 10000);
  EXPECT_EQ(swingingChain(10.0).steps, 10000);
  EXPECT_EQ(spatialSliderCrank(1.0).joints.size(), 4u);
}

// linx's accurate integrator through the adapter's integrator rows: the pendulum and the top on
// their closed forms, the slider-crank on its minimal-coordinate solution, the energy kept, the
// joints closed.
TEST(BenchLinx, AccurateRowsFollowTheClosedForms) {
  for (Scene s : {pendulumA01(2.0), heavyTop(1.0), spatialSliderCrank(2.0)}) {
    const std::vector<Variant> variants = linxIntegrators(s);
    const auto it = std::find_if(variants.begin(), variants.end(),
                                 [](const Variant& v) { return v.reference; });
    ASSERT_NE(it, variants.end());
    const Result r = run(s, *it, 60.0);
    ASSERT_TRUE(r.ran) << r.note;
    std::printf("%s, %s: path error %.2e m, energy drift %.2e %%, joints %.2e m\n", s.name.c_str(),
                it->settings.c_str(), r.accuracy, r.energy_drift, r.joints);
    EXPECT_EQ(r.path_points, s.steps);
    EXPECT_LT(r.accuracy, 1e-8);
    EXPECT_LT(r.energy_drift, 1e-6);  // percent
    EXPECT_LT(r.joints, 1e-9);
  }
}

// The speed target's rule: the fastest RK4 row at least as accurate as linx decides; when none
// is, linx must beat the finest, unless RK4's error stopped falling with its step.
TEST(BenchReport, IntegratorTargetTakesTheRowsAsAccurate) {
  const auto row = [](const char* engine, const char* knob, double error, double ms) {
    Result r;
    r.scene = std::string("mechanism");
    r.engine = std::string(engine);
    r.knob = std::string(knob);
    r.reference = std::string_view(engine) == "linx";
    r.ran = true;
    r.steps = r.steps_planned = 1000;
    r.accuracy = error;
    r.path_points = 1000;
    r.mean_ms = ms;
    return r;
  };
  const auto verdict = [](const std::vector<Result>& rows) {
    const std::vector<Target> t = integratorTargets(rows);
    EXPECT_EQ(t.size(), 2u);  // MuJoCo's RK4, and Simbody (no rows: not measured)
    EXPECT_FALSE(t.back().measured);
    return t.front().met;
  };
  const Result linx = row("linx", "accurate", 1e-9, 1.0);
  EXPECT_TRUE(
      verdict({linx, row("MuJoCo", "RK4", 1e-6, 0.1), row("MuJoCo", "RK4, h / 4", 1e-9, 2.0)}));
  EXPECT_FALSE(
      verdict({linx, row("MuJoCo", "RK4", 1e-6, 0.1), row("MuJoCo", "RK4, h / 4", 1e-10, 0.5)}));
  // None as accurate: the finest (2e-9) still falling and cheaper than linx: not met.
  EXPECT_FALSE(
      verdict({linx, row("MuJoCo", "RK4", 1e-6, 0.1), row("MuJoCo", "RK4, h / 4", 2e-9, 0.5)}));
  // ... stalled at 1e-6 (soft constraints): met.
  EXPECT_TRUE(
      verdict({linx, row("MuJoCo", "RK4", 1.1e-6, 0.1), row("MuJoCo", "RK4, h / 4", 1e-6, 0.5)}));
}

// linx through the adapter: the slider-crank's piston against its closed form, and a pyramid
// that stands.
TEST(BenchLinx, SliderCrankPistonFollowsTheClosedForm) {
  Scene s = sliderCrank();
  s.steps = 500;
  const std::vector<Variant> variants = linxVariants(s);
  ASSERT_FALSE(variants.empty());
  for (const Variant& v : variants) {
    const Result r = run(s, v, 60.0);
    ASSERT_TRUE(r.ran) << r.note;
    EXPECT_EQ(r.steps, 500);
    std::printf("%s: piston error %.2e m\n", v.settings.c_str(), r.accuracy);
    EXPECT_LT(r.accuracy, 1e-4) << v.settings;
  }
}

// The chains' energy figure through linx's adapter: present, finite, and no rise of a percent in
// a quarter of a second of the 10-link chain.
TEST(BenchLinx, ChainEnergyIsMeasured) {
  Scene s = hingeChain(10);
  s.steps = 60;
  const Result r = run(s, linxVariants(s).front(), 60.0);
  ASSERT_TRUE(r.ran) << r.note;
  ASSERT_TRUE(r.has_energy);
  std::printf("10-link chain after 0.25 s: energy rise %.3g %%, end %.3g %%\n", r.energy_rise,
              r.energy_end);
  EXPECT_TRUE(std::isfinite(r.energy_rise) && std::isfinite(r.energy_end));
  EXPECT_LT(r.energy_rise, 1.0);
  Scene p = pyramid(2);
  p.steps = 5;
  EXPECT_FALSE(run(p, linxVariants(p).front(), 60.0).has_energy) << "contacts: no energy figure";
}

TEST(BenchLinx, SmallPyramidStandsForOneSecond) {
  Scene s = pyramid(4);
  s.steps = 60;
  const Result r = run(s, linxVariants(s).front(), 60.0);
  ASSERT_TRUE(r.ran) << r.note;
  std::printf("pyramid of 10 boxes after 1 s: largest displacement %.2e m\n", r.accuracy);
  EXPECT_LT(r.accuracy, 0.01);
}

// The threads target compares the poses of the one- and two-thread rows step by step: a report
// that called differing runs identical would hide a race. Runs of the 1000-sphere pile on one and
// on two threads, 12 steps each, must agree to the bit; a doctored fingerprint must be caught at
// its step.
TEST(BenchReport, ThreadRowsAreComparedStepByStep) {
  Scene s = pouredSpheres(1000);
  s.steps = 12;
  std::vector<Result> results;
  for (const Variant& v : linxVariants(s)) results.push_back(run(s, v, 60.0));
  if (results.size() < 2) GTEST_SKIP() << "a single hardware thread: no threads row";
  ASSERT_EQ(results[1].threads, static_cast<int>(std::thread::hardware_concurrency()));
  ASSERT_EQ(results[0].fingerprints.size(), 12u);
  EXPECT_EQ(results[0].fingerprints, results[1].fingerprints);
  auto line = [](const std::vector<Result>& r) {
    for (const Target& t : targets(r))
      if (t.text.find("threads") != std::string::npos) return t;
    return Target{false, false, "none"};
  };
  const Target same = line(results);
  std::printf("%s\n", same.text.c_str());
  EXPECT_TRUE(same.met);
  EXPECT_NE(same.text.find("identical poses over all 12 steps"), std::string::npos);
  results[1].fingerprints[7] ^= 1;
  const Target differ = line(results);
  EXPECT_FALSE(differ.met);
  EXPECT_NE(differ.text.find("poses differ from step 8"), std::string::npos);
}

// The threads row is the reference row on more threads, nothing else: ragdolls, whose islands
// of joints alone the default integrator "auto" moves with the accurate integrator while they
// fall, ran identical on two threads only with the same integrator (the threads row once took the
// step, and its poses differed from step 1). Over their fall and landing (they hang 0.2 to 0.5 m
// above the floor: a third of a second), both rows' engines agree to the bit on every body's pose
// and velocity after every step, and the target is met.
TEST(BenchReport, RagdollThreadRowIsTheReferenceRowOnMoreThreads) {
  Scene s = ragdolls(4);
  s.steps = 60;
  const std::vector<Variant> variants = linxVariants(s);
  if (variants.size() < 2 || variants[1].threads <= 1)
    GTEST_SKIP() << "a single hardware thread: no threads row";
  ASSERT_TRUE(variants[0].reference);
  ASSERT_EQ(variants[0].threads, 1);
  EXPECT_EQ(variants[1].settings,
            variants[0].settings + ", " + std::to_string(variants[1].threads) + " threads");
  const std::unique_ptr<Engine> one = variants[0].make(s), many = variants[1].make(s);
  bool landed = false;
  for (int step = 1; step <= s.steps; ++step) {
    one->step();
    many->step();
    landed = landed || one->contactCount() > 0;
    for (int b = 0; b < static_cast<int>(s.bodies.size()); ++b) {
      const Pose p1 = one->pose(b), p2 = many->pose(b);
      const Twist t1 = one->velocity(b), t2 = many->velocity(b);
      ASSERT_TRUE(p1.position == p2.position &&
                  p1.orientation.coeffs() == p2.orientation.coeffs() && t1.linear == t2.linear &&
                  t1.angular == t2.angular)
          << s.bodies[static_cast<std::size_t>(b)].name << " differs after step " << step;
    }
  }
  EXPECT_TRUE(landed) << "the ragdolls reached the floor";
  std::vector<Result> results;
  for (std::size_t v = 0; v < 2; ++v) results.push_back(run(s, variants[v], 60.0));
  bool checked = false;
  for (const Target& t : targets(results)) {
    if (t.text.find("threads") == std::string::npos) continue;
    std::printf("%s\n", t.text.c_str());
    EXPECT_TRUE(t.met) << t.text;
    checked = true;
  }
  EXPECT_TRUE(checked) << "no threads target";
}

}  // namespace
}  // namespace bench
