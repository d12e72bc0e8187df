// The IFToMM library of computational benchmark problems for multibody dynamics, as the example
// scenes of examples/benchmarks/ run them (accurate integrator, default settings): each scene's
// compared quantity against the library's published reference solution at its high-precision
// tolerance, 1e-3 (M. Gonzalez, D. Dopico, U. Lugris, J. Cuadrado, "A benchmarking system for MBS
// simulation software", Multibody System Dynamics 16:179-190, 2006; ../shared/reference/
// benchmarks.md), and the energy drift over the problem's whole duration (a shorter span under the
// sanitizers: test::runLength).
#include "support.hpp"

#include "flyball_governor.hpp"
#include "jacobi_sn.hpp"
#include "one_dof_reference.hpp"
#include "spatial_slider_crank.hpp"

#include <linx/scene.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>
#include <utility>
#include <vector>

namespace linx {
namespace {

constexpr double kHighPrecision = 1e-3;

World loadBenchmark(const std::string& name, Scene& scene) {
  scene = loadScene(std::string(LINX_EXAMPLES_DIR) + "/benchmarks/" + name);
  EXPECT_EQ(scene.settings.integrator.type, IntegratorType::Accurate);
  return buildWorld(scene);
}

using bench::jacobiSn;

struct Point {
  double t, x, y;
};

// A benchmark's published positions, met in time order: the largest distance to them.
class Published {
 public:
  /// The points up to `end` (s).
  Published(std::vector<Point> points, double end) : points_(std::move(points)) {
    std::erase_if(points_, [&](const Point& p) { return p.t > end + 1e-9; });
  }
  /// Compares the position p at time t, if t is the next published time.
  void compare(const char* name, double t, const Vec3& p) {
    if (next_ >= points_.size() || std::abs(t - points_[next_].t) > 1e-9) return;
    const double error = std::hypot(p.x() - points_[next_].x, p.y() - points_[next_].y);
    std::printf("%s t = %g s: (%.6f, %.6f), error %.3g m\n", name, t, p.x(), p.y(), error);
    worst_ = std::max(worst_, error);
    ++next_;
  }
  bool allMet() const { return next_ == points_.size(); }
  double worst() const { return worst_; }

 private:
  std::vector<Point> points_;
  std::size_t next_ = 0;
  double worst_ = 0.0;
};

// A01: a 1 kg lumped mass on a massless 1 m link released horizontal, 2000 s. Closed form:
// theta(t) = 2 asin(k sn(K - w0 t, k)), k = sin(45 deg), w0 = sqrt(g / L); x = -sin(theta),
// y = -cos(theta). Compared every 0.5 s over the whole run, and at the published points.
TEST(IftommBenchmarks, A01SimplePendulum) {
  Scene scene;
  World w = loadBenchmark("iftomm_a01_pendulum.json", scene);
  const BodyId mass = *w.findBody("mass");
  const double k = std::sin(std::numbers::pi / 4), w0 = std::sqrt(9.81);
  const double big_k = std::comp_ellint_1(k);
  const double duration = test::runLength(scene.duration, 200.0);
  Published published({{0.5, -3.91049E-01, -9.20370E-01},
                       {1.0, 9.86292E-01, -1.65011E-01},
                       {1.5, 8.84132E-01, -4.67237E-01},
                       {2.0, -7.93566E-01, -6.08484E-01},
                       {5.0, -9.42305E-01, -3.34754E-01},
                       {10.0, -2.75087E-01, -9.61419E-01},
                       {100.0, -1.81513E-01, -9.83388E-01}},
                      duration);
  const double e0 = w.energy().total(), exchanged = 9.81;  // m g L
  double worst = 0.0, drift = 0.0;
  const auto steps = static_cast<std::int64_t>(std::llround(duration / w.settings().timestep));
  const auto every = static_cast<std::int64_t>(std::llround(0.5 / w.settings().timestep));
  for (std::int64_t n = 1; n <= steps; ++n) {
    w.step();
    if (n % every != 0) continue;
    const Vec3 p = w.body(mass).position();
    const double theta = 2.0 * std::asin(k * jacobiSn(big_k - w0 * w.time(), k));
    worst = std::max(worst, std::hypot(p.x() + std::sin(theta), p.y() + std::cos(theta)));
    drift = std::max(drift, std::abs(w.energy().total() - e0));
    published.compare("A01", w.time(), p);
  }
  std::printf(
      "A01 over %g s: position error %.3g m (published points %.3g m), energy drift %.3g "
      "of %g J\n",
      w.time(), worst, published.worst(), drift, exchanged);
  EXPECT_TRUE(published.allMet());
  EXPECT_LT(worst, kHighPrecision);
  EXPECT_LT(published.worst(), kHighPrecision);
  EXPECT_LT(drift, 1e-6 * exchanged);
}

// A02: the N-four-bar mechanism (N = 40): 81 links, redundant constraints, singular positions
// whenever its links are horizontal. Point B0, the top of the first crank, against the published
// positions over 20 s.
TEST(IftommBenchmarks, A02FourBarThroughItsSingularPositions) {
  Scene scene;
  World w = loadBenchmark("iftomm_a02_four_bar.json", scene);
  const BodyId crank = *w.findBody("crank0");
  // Under the sanitizers: the first 2 s, through the first two singular positions.
  const double duration = test::runLength(scene.duration, 2.0);
  Published published({{0.05, 5.02096E-02, 9.98739E-01},
                       {0.5, 6.87926E-01, 7.25781E-01},
                       {1.0, -1.15357E-01, -9.93324E-01},
                       {2.0, 3.44663E-02, 9.99406E-01},
                       {5.0, -5.40191E-01, -8.41543E-01},
                       {10.0, 1.80513E-01, 9.83573E-01},
                       {20.0, 4.10902E-01, 9.11679E-01}},
                      duration);
  const double e0 = w.energy().total();
  double drift = 0.0, joints = 0.0, exchanged = 0.0;
  const auto steps = static_cast<std::int64_t>(std::llround(duration / w.settings().timestep));
  for (std::int64_t n = 1; n <= steps; ++n) {
    w.step();
    const Energy e = w.energy();
    drift = std::max(drift, std::abs(e.total() - e0));
    exchanged = std::max(exchanged, e.kinetic);
    if (n % 10 == 0)
      for (const JointId j : w.jointIds()) joints = std::max(joints, w.jointError(j));
    const Body& b = w.body(crank);
    published.compare("A02 B0", w.time(), b.position() + b.orientation() * Vec3(0, 0.5, 0));
  }
  std::printf(
      "A02 over %g s: B0 error %.3g m, energy drift %.3g of %.6g J exchanged, joints %.3g "
      "m\n",
      w.time(), published.worst(), drift, exchanged, joints);
  EXPECT_TRUE(published.allMet());
  EXPECT_LT(published.worst(), kHighPrecision);
  EXPECT_LT(drift, 1e-6 * exchanged);
  EXPECT_LT(joints, 1e-8);
}

// A02's mechanism with N = 1: two cranks and the coupler (3 bodies, four hinges: 20 rows of which
// 2 are redundant, at most 32: the accurate integrator's dense solves), released as A02 (crank up,
// turning at 1 rad/s), so that it turns over and over through the dead points where the cranks
// lie along the coupler. Reference: Lagrange's equation in the crank angle q (clockwise from up),
// the cranks turning about their pivots and the coupler translating on a circle.
TEST(IftommBenchmarks, SingleFourBarFollowsItsMinimalCoordinateSolution) {
  // examples/benchmarks/iftomm_a02_four_bar.json's first two cranks and first coupler.
  const Scene scene = parseScene(R"({
    "gravity": [0, -9.81, 0], "timestep": 0.01, "integrator": "accurate",
    "contact": {"enabled": false},
    "bodies": [
      {"name": "crank0", "mass": 1, "inertia": [0.08333333333333333, 0.0001, 0.08333333333333333],
       "position": [0, 0.5, 0], "linear_velocity": [0.5, 0, 0], "angular_velocity": [0, 0, -1]},
      {"name": "crank1", "mass": 1, "inertia": [0.08333333333333333, 0.0001, 0.08333333333333333],
       "position": [1, 0.5, 0], "linear_velocity": [0.5, 0, 0], "angular_velocity": [0, 0, -1]},
      {"name": "coupler0", "mass": 1, "inertia": [0.0001, 0.08333333333333333, 0.08333333333333333],
       "position": [0.5, 1, 0], "linear_velocity": [1, 0, 0]}],
    "joints": [
      {"name": "ground0", "type": "hinge", "body1": "crank0", "body2": "world", "anchor": [0, 0, 0], "axis": [0, 0, 1]},
      {"name": "ground1", "type": "hinge", "body1": "crank1", "body2": "world", "anchor": [1, 0, 0], "axis": [0, 0, 1]},
      {"name": "left0", "type": "hinge", "body1": "coupler0", "body2": "crank0", "anchor": [0, 1, 0], "axis": [0, 0, 1]},
      {"name": "right0", "type": "hinge", "body1": "coupler0", "body2": "crank1", "anchor": [1, 1, 0], "axis": [0, 0, 1]}]
  })",
                                 "single_four_bar.json");
  World w = buildWorld(scene);
  const BodyId crank = *w.findBody("crank0");
  const Vec3 crank_inertia(1.0 / 12, 1e-4, 1.0 / 12), coupler_inertia(1e-4, 1.0 / 12, 1.0 / 12);
  const auto turned = [](double q) {
    return Eigen::AngleAxisd(-q, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  };
  const auto up = [](double q) { return Eigen::Vector3d(std::sin(q), std::cos(q), 0.0); };
  const bench::OneDofReference reference(
      {{1.0, crank_inertia,
        [&](double q) {
          return std::pair{(0.5 * up(q)).eval(), turned(q)};
        }},
       {1.0, crank_inertia,
        [&](double q) {
          return std::pair{(Eigen::Vector3d(1, 0, 0) + 0.5 * up(q)).eval(), turned(q)};
        }},
       {1.0, coupler_inertia,
        [&](double q) {
          return std::pair{(Eigen::Vector3d(0.5, 0, 0) + up(q)).eval(),
                           Eigen::Matrix3d::Identity().eval()};
        }}},
      Vec3(0.0, -9.81, 0.0));
  double q = 0.0, rate = 1.0;
  const double h = w.settings().timestep, e0 = reference.energy(q, rate);
  EXPECT_NEAR(w.energy().total(), e0, 1e-12);
  const double duration = test::runLength(10.0, 2.0);
  double angle = 0.0, drift = 0.0, exchanged = 0.0, joints = 0.0;
  const auto steps = static_cast<std::int64_t>(std::llround(duration / h));
  for (std::int64_t n = 1; n <= steps; ++n) {
    w.step();
    reference.advance(q, rate, h, 2.5e-4);
    const Vec3 y = w.body(crank).orientation() * Vec3::UnitY();
    angle = std::max(angle,
                     std::abs(std::remainder(std::atan2(y.x(), y.y()) - q, 2 * std::numbers::pi)));
    const Energy e = w.energy();
    drift = std::max(drift, std::abs(e.total() - e0));
    exchanged = std::max(exchanged, e.kinetic);
    for (const JointId j : w.jointIds()) joints = std::max(joints, w.jointError(j));
  }
  std::printf(
      "single four-bar over %g s: %.2f turns, crank angle error %.3g rad, energy drift %.3g of "
      "%.6g J exchanged, joints %.3g m\n",
      w.time(), q / (2 * std::numbers::pi), angle, drift, exchanged, joints);
  EXPECT_GT(q, 2 * std::numbers::pi * (duration > 5.0 ? 4.0 : 1.0));  // through many dead points
  EXPECT_LT(angle, 1e-6);
  EXPECT_LT(drift, 1e-6 * exchanged);
  EXPECT_LT(joints, 1e-8);
}

// The spatial slider-crank (examples/benchmarks/spatial_slider_crank.json; its geometry in
// bench/spatial_slider_crank.hpp), the rod on a ball joint at the crank pin and a universal joint
// at the slider: one degree of freedom, no redundant constraint. Reference: Lagrange's equation in
// the crank angle with the closed-form kinematics, nothing of linx's full-coordinate machinery.
TEST(IftommBenchmarks, SpatialSliderCrankFollowsItsMinimalCoordinateSolution) {
  Scene scene;
  World w = loadBenchmark("spatial_slider_crank.json", scene);
  const BodyId crank = *w.findBody("crank"), rod = *w.findBody("rod"),
               slider = *w.findBody("slider");
  namespace sc = bench::slider_crank;
  double q = sc::kStart, rate = 0.0;
  // The scene is the reference's geometry at its start.
  EXPECT_LT((w.body(crank).position() - sc::pin(q) / 2).norm(), 1e-15);
  EXPECT_LT((w.body(slider).position() - sc::slider(q)).norm(), 1e-15);
  EXPECT_LT((w.body(rod).orientation().toRotationMatrix() - sc::rod(q)).norm(), 1e-15);
  const bench::OneDofReference reference = sc::reference(sc::RodEnd::Universal);
  const double h = w.settings().timestep, e0 = reference.energy(q, rate);
  EXPECT_NEAR(w.energy().total(), e0, 1e-14);
  const double duration = test::runLength(scene.duration, 2.0);
  double angle = 0.0, position = 0.0, drift = 0.0, exchanged = 0.0, joints = 0.0;
  double lowest = q;
  const auto steps = static_cast<std::int64_t>(std::llround(duration / h));
  for (std::int64_t n = 1; n <= steps; ++n) {
    w.step();
    reference.advance(q, rate, h, 2.5e-4);
    const Vec3 x = w.body(crank).orientation() * Vec3::UnitX();
    // The crank's angle, continued through the lower half-turn (it never reaches the top).
    double phi = std::atan2(x.y(), x.x());
    if (phi > std::numbers::pi / 2 + 0.1) phi -= 2 * std::numbers::pi;
    lowest = std::min(lowest, phi);
    angle = std::max(angle, std::abs(phi - q));
    position = std::max(position, std::abs(w.body(slider).position().x() - sc::slider(q).x()));
    const Energy e = w.energy();
    drift = std::max(drift, std::abs(e.total() - e0));
    exchanged = std::max(exchanged, e.kinetic);
    for (const JointId j : w.jointIds()) joints = std::max(joints, w.jointError(j));
  }
  std::printf(
      "spatial slider-crank over %g s: crank angle error %.3g rad (lowest %.6f rad), slider "
      "error %.3g m, energy drift %.3g of %.6g J exchanged, joints %.3g m\n",
      w.time(), angle, lowest, position, drift, exchanged, joints);
  EXPECT_LT(lowest, -std::numbers::pi);  // it swung through the lower half-turn
  EXPECT_LT(angle, 1e-6);
  EXPECT_LT(position, 1e-3 * 2 * sc::kCrank);  // high precision: 1e-3 of the stroke
  EXPECT_LT(drift, 1e-6 * exchanged);
  EXPECT_LT(joints, 1e-8);
}

// IFToMM A05, the stiff flyball governor (examples/benchmarks/iftomm_a05_flyball_governor.json; its
// layout and reference in bench/flyball_governor.hpp): four bodies on three hinges and a slider,
// the coupler rods spring-dampers stiff enough (a decay rate of some 7000 1/s) to set the step
// size. The library's own reference solution could not be reached from here; the reference is
// Lagrange's equations in the rods' angle and the slider's height with the shaft's angular
// momentum kept, in closed form (no constraint rows, no multipliers). Compared: the slider's
// height s (the library's quantity) and the rods' angle, every frame; the energy against the
// reference's (its dampers' dissipation included), and the angular momentum about the shaft,
// which nothing changes.
TEST(IftommBenchmarks, FlyballGovernorFollowsItsReducedCoordinateSolution) {
  Scene scene;
  World w = loadBenchmark("iftomm_a05_flyball_governor.json", scene);
  namespace fb = bench::flyball;
  const BodyId slider = *w.findBody("slider"), rod_a = *w.findBody("rod_a"),
               rod_b = *w.findBody("rod_b");
  const JointId pivot_a = *w.findJoint("pivot_a"), damper_a = *w.findJoint("damper_a"),
                damper_b = *w.findJoint("damper_b");
  const fb::Reference reference;
  fb::State x;
  // Spring energy from the dampers' lengths (linx's energy() is the bodies').
  const auto energy = [&] {
    double springs = 0.0;
    for (const JointId j : {damper_a, damper_b}) {
      const double stretch = w.jointCoordinates(j)[0] - fb::kRest;
      springs += 0.5 * fb::kStiffness * stretch * stretch;
    }
    return w.energy().total() + springs;
  };
  const auto momentum = [&] {  // about z through the origin
    double l = 0.0;
    for (const BodyId id : w.bodyIds()) {
      const Body& b = w.body(id);
      l += (b.inertiaWorld() * b.angularVelocity() +
            b.mass() * b.position().cross(b.linearVelocity()))
               .z();
    }
    return l;
  };
  // The scene is the reference's layout at its start.
  EXPECT_NEAR(energy(), reference.energy(x), 1e-9);
  EXPECT_NEAR(momentum(), reference.momentum(), 1e-12);
  const double h = w.settings().timestep, l0 = momentum();
  const double duration = test::runLength(scene.duration, 1.0);
  double height = 0.0, angle = 0.0, symmetry = 0.0, balance = 0.0, spin = 0.0, joints = 0.0;
  int steps = 0, rejected = 0;
  const auto frames = static_cast<std::int64_t>(std::llround(duration / h));
  for (std::int64_t n = 1; n <= frames; ++n) {
    w.step();
    reference.advance(x, h, 1e-5);
    steps += w.lastIntegratorReport().steps;
    rejected += w.lastIntegratorReport().rejected;
    height = std::max(height, std::abs(w.body(slider).position().z() - x.s));
    // The hinge's angle counts from the start, positive turning about +y: rod a falls outwards
    // towards the horizontal at negative angles.
    angle = std::max(angle, std::abs(fb::kStartAngle - w.jointCoordinates(pivot_a)[0] - x.theta));
    const Vec3 a = w.body(rod_a).position(), b = w.body(rod_b).position();
    symmetry = std::max(symmetry, std::abs(std::hypot(a.x(), a.y()) - std::hypot(b.x(), b.y())));
    balance = std::max(balance, std::abs(energy() - reference.energy(x)));
    spin = std::max(spin, std::abs(momentum() - l0));
    for (const JointId j : w.jointIds()) joints = std::max(joints, w.jointError(j));
  }
  std::printf(
      "flyball governor over %g s: s %.9f m (reference %.9f), error %.3g m; rods' angle error "
      "%.3g rad; mirror %.3g m; energy %.3g J off the reference's (%.6g J dissipated of %.6g J); "
      "angular momentum %.3g of %.6g N m s; joints %.3g m; %d steps, %d refused\n",
      w.time(), w.body(slider).position().z(), x.s, height, angle, symmetry, balance, x.dissipated,
      reference.energy(fb::State{}), spin, l0, joints, steps, rejected);
  EXPECT_GT(x.s - fb::kStartHeight, duration > 5 ? 0.1 : 1e-3);  // the governor opened
  EXPECT_LT(height, 1e-6);  // the library's high precision: kHighPrecision of s, 6e-4 m
  EXPECT_LT(angle, 1e-6);
  EXPECT_LT(symmetry, 1e-9);
  EXPECT_LT(balance, 1e-6 * x.dissipated + 1e-9);
  EXPECT_LT(spin, 1e-9 * l0);
  EXPECT_LT(joints, 1e-8);
}

}  // namespace
}  // namespace linx
