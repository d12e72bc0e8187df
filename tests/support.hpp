// Independent truths for the validation tests: closed forms, not the engine's own code.
#pragma once

#include <linx/linx.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <string>
#include <vector>

namespace linx::test {

/// Whether the tests run under AddressSanitizer, ten to fifteen times slower: the longest runs
/// (the accurate integrator's) check a shorter span there and their whole span in the plain build.
#if defined(__SANITIZE_ADDRESS__)
inline constexpr bool kSanitized = true;
#else
inline constexpr bool kSanitized = false;
#endif

/// A run's length: `full` in the plain build, `sanitized` under the sanitizers.
inline double runLength(double full, double sanitized) {
  return kSanitized ? sanitized : full;
}

/// Distance from rest under a constant acceleration `a` after n steps of h: symplectic Euler's,
/// a h^2 n (n + 1) / 2, with the step; the motion's own, a (n h)^2 / 2, with the accurate
/// integrator (which "auto", the default, gives an island of joints alone).
inline double distanceFromRest(IntegratorType type, double a, double h, int n) {
  const double t = n * h;
  return type == IntegratorType::Step ? 0.5 * a * h * t * (n + 1.0) : 0.5 * a * t * t;
}

/// Complete elliptic integral of the first kind K(k), k the modulus, by the arithmetic-geometric
/// mean: K(k) = pi / (2 AGM(1, sqrt(1 - k^2))).
inline double ellipticK(double k) {
  double a = 1.0, b = std::sqrt(1.0 - k * k);
  for (int i = 0; i < 40 && std::abs(a - b) > 1e-16 * a; ++i) {
    const double an = 0.5 * (a + b);
    b = std::sqrt(a * b);
    a = an;
  }
  return std::numbers::pi / (2.0 * a);
}

/// Exact period of a physical pendulum of amplitude theta0: 4 sqrt(I_p / (m g d)) K(sin(theta0/2)),
/// with I_p the moment of inertia about the pivot and d the pivot-to-centre-of-mass distance.
inline double pendulumPeriod(double inertia_pivot, double mass, double g, double d, double theta0) {
  return 4.0 * std::sqrt(inertia_pivot / (mass * g * d)) * ellipticK(std::sin(0.5 * theta0));
}

/// Solid box of full edge lengths (lx, ly, lz).
inline Mat3 boxInertia(double m, double lx, double ly, double lz) {
  return Vec3(m / 12.0 * (ly * ly + lz * lz), m / 12.0 * (lx * lx + lz * lz),
              m / 12.0 * (lx * lx + ly * ly))
      .asDiagonal();
}

inline BodyDef boxBody(const std::string& name, double m, const Vec3& size, const Vec3& position) {
  BodyDef d;
  d.name = name;
  d.mass = m;
  d.inertia = boxInertia(m, size.x(), size.y(), size.z());
  d.position = position;
  d.shapes.push_back(ShapeDef{.type = ShapeType::Box, .size = size});
  return d;
}

/// A static body "ground" whose one shape is the plane z = 0.
inline BodyDef groundPlane() {
  BodyDef ground;
  ground.name = "ground";
  ground.is_static = true;
  ShapeDef plane;
  plane.type = ShapeType::Plane;
  plane.normal = Vec3::UnitZ();
  ground.shapes.push_back(plane);
  return ground;
}

/// Times at which a sampled signal crosses zero upwards, by linear interpolation.
inline std::vector<double> upwardCrossings(const std::vector<double>& t,
                                           const std::vector<double>& y) {
  std::vector<double> out;
  for (std::size_t i = 1; i < y.size(); ++i)
    if (y[i - 1] < 0.0 && y[i] >= 0.0)
      out.push_back(t[i - 1] + (t[i] - t[i - 1]) * (-y[i - 1]) / (y[i] - y[i - 1]));
  return out;
}

/// A solver's name, for messages and the names of tests run with each solver.
inline const char* solverName(SolverType type) {
  return solverTypeName(type).data();
}

/// The settings of a test run with each solver: h = 1 ms, that solver, and no sleeping (the test
/// watches the motion to its end).
inline WorldSettings solverSettings(SolverType type) {
  WorldSettings s;
  s.timestep = 1e-3;
  s.solver.type = type;
  s.sleep.enabled = false;
  return s;
}

/// An oscillation sampled at times t: its amplitude (half its range) and its mean period, from
/// the upward crossings of its middle (zero periods when it crossed fewer than twice).
struct Oscillation {
  double amplitude = 0.0;
  double period = 0.0;
  std::size_t crossings = 0;
};
inline Oscillation oscillation(const std::vector<double>& t, std::vector<double> y) {
  const auto [lo, hi] = std::minmax_element(y.begin(), y.end());
  const double middle = 0.5 * (*lo + *hi), amplitude = 0.5 * (*hi - *lo);
  for (double& v : y) v -= middle;
  const std::vector<double> up = upwardCrossings(t, y);
  const double period =
      up.size() < 2 ? 0.0 : (up.back() - up.front()) / static_cast<double>(up.size() - 1);
  return {amplitude, period, up.size()};
}

/// A rigid body of mass m and inertia `inertia` (about its centre `com`, world axes) on a hinge
/// about the unit `axis` through `pivot`, released from rest under gravity g: its amplitude, the
/// angle between its centre's arm and the part of g across the axis (rad), and its exact period
/// (s), from pendulumPeriod with the moment about the axis and that part of g.
struct PendulumOnAxis {
  double amplitude = 0.0;
  double period = 0.0;
};
inline PendulumOnAxis pendulumOnAxis(const Vec3& pivot, const Vec3& axis, const Vec3& com,
                                     const Mat3& inertia, double m, const Vec3& g) {
  const Vec3 r = com - pivot;
  const Vec3 arm = r - r.dot(axis) * axis;
  const Vec3 g_across = g - g.dot(axis) * axis;
  const double d = arm.norm();
  const double theta0 = std::acos(arm.normalized().dot(g_across.normalized()));
  return {theta0,
          pendulumPeriod(axis.dot(inertia * axis) + m * d * d, m, g_across.norm(), d, theta0)};
}

/// The oscillation of a joint's first coordinate over `steps` steps of `world`.
inline Oscillation jointOscillation(World& world, JointId joint, int steps) {
  std::vector<double> t, q;
  for (int i = 0; i < steps; ++i) {
    world.step();
    t.push_back(world.time());
    q.push_back(world.jointCoordinates(joint)[0]);
  }
  return oscillation(t, std::move(q));
}

/// jointOscillation of a pendulum's joint, printed beside its closed form `truth`.
inline Oscillation swingAgainst(World& world, JointId joint, int steps,
                                const PendulumOnAxis& truth) {
  const Oscillation swing = jointOscillation(world, joint, steps);
  std::printf(
      "pendulum: amplitude %.6f rad (closed form %.6f), period %.9f s (closed form %.9f "
      "s, relative error %.2e)\n",
      swing.amplitude, truth.amplitude, swing.period, truth.period,
      swing.period / truth.period - 1.0);
  return swing;
}

/// A fresh folder under the system's temporary folder, removed with its files at the end.
class TempFolder {
 public:
  explicit TempFolder(const std::string& name)
      : path_(std::filesystem::temp_directory_path() / name) {
    std::filesystem::remove_all(path_);
    std::filesystem::create_directories(path_);
  }
  ~TempFolder() { std::filesystem::remove_all(path_); }
  TempFolder(const TempFolder&) = delete;
  TempFolder& operator=(const TempFolder&) = delete;

  const std::filesystem::path& path() const { return path_; }
  /// Writes `text` to the file `name` in it (making its folders); its path.
  std::filesystem::path write(const std::string& name, const std::string& text) const {
    const std::filesystem::path file = path_ / name;
    std::filesystem::create_directories(file.parent_path());
    std::ofstream(file) << text;
    return file;
  }

 private:
  std::filesystem::path path_;
};

}  // namespace linx::test
