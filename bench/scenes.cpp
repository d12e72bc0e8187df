#include "scenes.hpp"

#include "flyball_governor.hpp"
#include "jacobi_sn.hpp"
#include "spatial_slider_crank.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace bench {
namespace {

constexpr double kPi = 3.14159265358979323846;

Vec3 boxInertia(double m, const Vec3& half) {
  const Vec3 e = 2.0 * half;
  return Vec3(e.y() * e.y() + e.z() * e.z(), e.x() * e.x() + e.z() * e.z(),
              e.x() * e.x() + e.y() * e.y()) *
         (m / 12.0);
}

// Solid capsule along z: cylinder of length 2a plus two hemispheres, uniform density.
Vec3 capsuleInertia(double m, double r, double a) {
  const double vc = kPi * r * r * 2.0 * a, vs = 4.0 / 3.0 * kPi * r * r * r;
  const double mc = m * vc / (vc + vs), ms = m - mc, L = 2.0 * a;
  const double ixy = mc * (L * L / 12.0 + r * r / 4.0) +
                     ms * (2.0 / 5.0 * r * r + L * L / 4.0 + 3.0 * L * r / 8.0);
  const double iz = mc * r * r / 2.0 + ms * 2.0 / 5.0 * r * r;
  return Vec3(ixy, ixy, iz);
}

// Deterministic jitter in [-1, 1] (splitmix64), the same on every machine.
double jitter(std::uint64_t i) {
  std::uint64_t z = i + 0x9e3779b97f4a7c15ull;
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
  z ^= z >> 31;
  return static_cast<double>(z >> 11) / static_cast<double>(1ull << 52) - 1.0;
}

Body staticBox(std::string name, const Vec3& centre, const Vec3& half) {
  Body b;
  b.name = std::move(name);
  b.is_static = true;
  b.position = centre;
  b.shape.kind = Shape::Kind::Box;
  b.shape.half_extents = half;
  return b;
}

int stepsOf(double duration, double h) {
  return static_cast<int>(std::llround(duration / h));
}

/// A point's known path from its position at every step n (time n h), computed once per scene
/// name and number of steps by `compute` (a reference solution integrated alongside).
KnownPath stepwisePath(const Scene& s, int body, const Vec3& point, std::string source,
                       const std::function<std::vector<Vec3>()>& compute) {
  static std::map<std::pair<std::string, std::int64_t>, std::shared_ptr<const std::vector<Vec3>>>
      computed;
  std::shared_ptr<const std::vector<Vec3>>& at = computed[{s.name, s.steps}];
  if (!at) at = std::make_shared<const std::vector<Vec3>>(compute());
  const double h = s.timestep;
  return KnownPath{
      body, point, std::move(source), [at = at, h](double time) -> std::optional<Vec3> {
        const auto n = static_cast<std::int64_t>(std::llround(time / h));
        if (n < 0 || n >= static_cast<std::int64_t>(at->size()) || std::abs(time - n * h) > 1e-9)
          return std::nullopt;
        return (*at)[static_cast<std::size_t>(n)];
      }};
}

}  // namespace

Scene hingeChain(int n, double last_mass) {
  constexpr double kLength = 0.1, kWidth = 0.02;
  Scene s;
  s.name = last_mass == 1.0 ? "chain" : "heavy chain";
  s.size = "N=" + std::to_string(n);
  s.timestep = 1.0 / 240.0;
  s.steps = 480;
  s.metric = Metric::JointSeparation;
  s.energy = true;  // released at rest, gravity only: the energy stays that of the start
  const Vec3 half(kLength / 2, kWidth / 2, kWidth / 2);
  for (int i = 0; i < n; ++i) {
    Body b;
    b.name = "link" + std::to_string(i);
    b.mass = i == n - 1 ? last_mass : 1.0;
    b.inertia = boxInertia(b.mass, half);
    b.position = Vec3((i + 0.5) * kLength, 0.0, 0.0);
    s.bodies.push_back(b);
    Joint j;
    j.kind = Joint::Kind::Hinge;
    j.body1 = i - 1;  // -1: link 0 hangs from the world
    j.body2 = i;
    j.anchor = Vec3(i * kLength, 0.0, 0.0);
    j.axis = Vec3::UnitY();
    s.joints.push_back(j);
  }
  return s;
}

Scene pyramid(int base) {
  constexpr double kHalf = 0.1, kPitch = 0.21;  // 1 cm gaps between the boxes of a row
  Scene s;
  s.name = "pyramid";
  s.size = "base " + std::to_string(base) + " (" + std::to_string(base * (base + 1) / 2) + ")";
  s.timestep = 1.0 / 60.0;
  s.steps = 600;
  s.friction = 0.6;
  s.ground_z = 0.0;
  s.metric = Metric::MaxDisplacement;
  const Vec3 half = Vec3::Constant(kHalf);
  for (int row = 0; row < base; ++row) {
    const int count = base - row;
    for (int k = 0; k < count; ++k) {
      Body b;
      b.name = "box" + std::to_string(row) + "_" + std::to_string(k);
      b.mass = 1.0;
      b.inertia = boxInertia(1.0, half);
      b.position = Vec3((k - 0.5 * (count - 1)) * kPitch, 0.0, kHalf + 2.0 * kHalf * row);
      b.shape.kind = Shape::Kind::Box;
      b.shape.half_extents = half;
      s.bodies.push_back(b);
    }
  }
  return s;
}

Scene pouredSpheres(int count) {
  constexpr double kRadius = 0.05, kMass = 0.1, kPitch = 2.5 * kRadius, kWall = 0.1;
  Scene s;
  s.name = "spheres";
  s.size = "N=" + std::to_string(count);
  s.timestep = 1.0 / 60.0;
  s.steps = 120;
  s.friction = 0.5;
  s.metric = Metric::MaxPenetration;
  const int side = std::max(1, static_cast<int>(std::ceil(std::cbrt(count) - 1e-9)));
  const int layers = (count + side * side - 1) / (side * side);
  // The open box: inner half-width 20 % wider than the lattice, walls as tall as the lattice.
  const double inner = 0.6 * side * kPitch + kRadius;
  const double height = layers * kPitch + 4.0 * kRadius;
  s.bodies.push_back(
      staticBox("floor", Vec3(0, 0, -kWall), Vec3(inner + 2 * kWall, inner + 2 * kWall, kWall)));
  for (int sign : {-1, 1}) {
    s.bodies.push_back(staticBox(sign < 0 ? "wall-x" : "wall+x",
                                 Vec3(sign * (inner + kWall), 0, height / 2),
                                 Vec3(kWall, inner + 2 * kWall, height / 2)));
    s.bodies.push_back(staticBox(sign < 0 ? "wall-y" : "wall+y",
                                 Vec3(0, sign * (inner + kWall), height / 2),
                                 Vec3(inner, kWall, height / 2)));
  }
  for (int i = 0; i < count; ++i) {
    const int layer = i / (side * side), cell = i % (side * side);
    const int ix = cell % side, iy = cell / side;
    Body b;
    b.name = "ball" + std::to_string(i);
    b.mass = kMass;
    b.inertia = Vec3::Constant(0.4 * kMass * kRadius * kRadius);
    const double a = 0.2 * kRadius;  // jitter, so the lattice does not stack in columns
    b.position = Vec3((ix - 0.5 * (side - 1)) * kPitch + a * jitter(3 * i),
                      (iy - 0.5 * (side - 1)) * kPitch + a * jitter(3 * i + 1),
                      kRadius + 0.02 + layer * kPitch + a * jitter(3 * i + 2));
    b.shape.kind = Shape::Kind::Sphere;
    b.shape.radius = kRadius;
    s.bodies.push_back(b);
  }
  return s;
}

Scene sliderCrank() {
  Scene s;
  s.name = "slider-crank";
  s.size = "3 bodies";
  s.timestep = 1e-3;
  s.steps = 2000;
  s.metric = Metric::PistonError;
  const auto body = [](std::string name, double m, const Vec3& pos, const Vec3& half) {
    Body b;
    b.name = std::move(name);
    b.mass = m;
    b.inertia = boxInertia(m, half);
    b.position = pos;
    return b;
  };
  s.bodies.push_back(body("crank", 1.0, Vec3(0.05, 0, 0), Vec3(0.05, 0.01, 0.01)));
  s.bodies.push_back(body("rod", 1.0, Vec3(0.25, 0, 0), Vec3(0.15, 0.01, 0.01)));
  s.bodies.push_back(body("piston", 0.5, Vec3(0.4, 0, 0), Vec3(0.025, 0.025, 0.025)));
  const auto joint = [](Joint::Kind kind, int b1, int b2, const Vec3& anchor, const Vec3& axis) {
    Joint j;
    j.kind = kind;
    j.body1 = b1;
    j.body2 = b2;
    j.anchor = anchor;
    j.axis = axis;
    return j;
  };
  Joint crank = joint(Joint::Kind::Hinge, -1, 0, Vec3::Zero(), Vec3::UnitZ());
  crank.motor = Joint::Motor{2.0 * kPi, 100.0};
  s.joints.push_back(crank);
  s.joints.push_back(joint(Joint::Kind::Hinge, 0, 1, Vec3(0.1, 0, 0), Vec3::UnitZ()));
  s.joints.push_back(joint(Joint::Kind::Hinge, 1, 2, Vec3(0.4, 0, 0), Vec3::UnitZ()));
  s.joints.push_back(joint(Joint::Kind::Slider, -1, 2, Vec3(0.4, 0, 0), Vec3::UnitX()));
  s.slider_crank_crank = 0;
  s.slider_crank_piston = 2;
  s.crank_radius = 0.1;
  s.rod_length = 0.3;
  s.crank_centre = Vec3::Zero();
  return s;
}

Scene ragdolls(int count) {
  Scene s;
  s.name = "ragdolls";
  s.size = std::to_string(count) + " x 11 bodies";
  s.timestep = 1.0 / 60.0;
  s.steps = 240;
  s.friction = 0.5;
  s.ground_z = 0.0;
  s.metric = Metric::JointSeparation;

  // One ragdoll standing at the origin, arms out (T pose). Capsules lie along their body's z.
  struct Part {
    const char* name;
    double mass, radius, half_length;
    Vec3 centre;
    Vec3 along;  // world direction of the capsule's axis
  };
  const Part parts[] = {
      {"pelvis", 10.0, 0.12, 0.05, Vec3(0, 0, 1.00), Vec3::UnitZ()},
      {"torso", 15.0, 0.13, 0.12, Vec3(0, 0, 1.43), Vec3::UnitZ()},
      {"head", 5.0, 0.10, 0.02, Vec3(0, 0, 1.81), Vec3::UnitZ()},
      {"upper_arm_l", 2.0, 0.05, 0.10, Vec3(0, 0.34, 1.58), Vec3::UnitY()},
      {"lower_arm_l", 1.5, 0.045, 0.10, Vec3(0, 0.645, 1.58), Vec3::UnitY()},
      {"upper_arm_r", 2.0, 0.05, 0.10, Vec3(0, -0.34, 1.58), Vec3::UnitY()},
      {"lower_arm_r", 1.5, 0.045, 0.10, Vec3(0, -0.645, 1.58), Vec3::UnitY()},
      {"thigh_l", 7.0, 0.07, 0.15, Vec3(0, 0.10, 0.60), Vec3::UnitZ()},
      {"shin_l", 4.0, 0.06, 0.15, Vec3(0, 0.10, 0.16), Vec3::UnitZ()},
      {"thigh_r", 7.0, 0.07, 0.15, Vec3(0, -0.10, 0.60), Vec3::UnitZ()},
      {"shin_r", 4.0, 0.06, 0.15, Vec3(0, -0.10, 0.16), Vec3::UnitZ()},
  };
  struct Link {
    int parent, child;
    Vec3 anchor, axis;
    double limit;  // symmetric (rad)
  };
  const Link links[] = {
      {0, 1, Vec3(0, 0, 1.175), Vec3::UnitY(), 0.5},      // spine
      {1, 2, Vec3(0, 0, 1.685), Vec3::UnitY(), 0.6},      // neck
      {1, 3, Vec3(0, 0.185, 1.58), Vec3::UnitX(), 1.2},   // shoulders
      {3, 4, Vec3(0, 0.4925, 1.58), Vec3::UnitZ(), 1.2},  // elbows
      {1, 5, Vec3(0, -0.185, 1.58), Vec3::UnitX(), 1.2},
      {5, 6, Vec3(0, -0.4925, 1.58), Vec3::UnitZ(), 1.2},
      {0, 7, Vec3(0, 0.10, 0.825), Vec3::UnitY(), 1.0},  // hips
      {7, 8, Vec3(0, 0.10, 0.38), Vec3::UnitY(), 1.0},   // knees
      {0, 9, Vec3(0, -0.10, 0.825), Vec3::UnitY(), 1.0},
      {9, 10, Vec3(0, -0.10, 0.38), Vec3::UnitY(), 1.0},
  };

  const int side = static_cast<int>(std::ceil(std::sqrt(static_cast<double>(count)) - 1e-9));
  for (int r = 0; r < count; ++r) {
    // Each ragdoll is tilted about its own horizontal axis and turned about z, so that it falls and
    // tumbles differently from its neighbours, then lifted to hang 0.2 to 0.5 m above the plane.
    const double yaw = 0.7 * r, tilt = 0.25 + 0.05 * (r % 6);
    const Quat q =
        Quat(Eigen::AngleAxisd(yaw, Vec3::UnitZ())) * Quat(Eigen::AngleAxisd(tilt, Vec3::UnitX()));
    double lowest = 1e9;
    for (const Part& p : parts) {
      for (double end : {-1.0, 1.0}) {
        lowest = std::min(lowest, (q * (p.centre + end * p.half_length * p.along)).z() - p.radius);
      }
    }
    const Vec3 offset((r % side - 0.5 * (side - 1)) * 2.5, (r / side - 0.5 * (side - 1)) * 2.5,
                      0.2 + 0.06 * (r % 5) - lowest);
    const int first = static_cast<int>(s.bodies.size());
    for (const Part& p : parts) {
      Body b;
      b.name = "ragdoll" + std::to_string(r) + "_" + p.name;
      b.mass = p.mass;
      b.inertia = capsuleInertia(p.mass, p.radius, p.half_length);
      b.position = q * p.centre + offset;
      b.orientation = q * Quat::FromTwoVectors(Vec3::UnitZ(), p.along);
      b.shape.kind = Shape::Kind::Capsule;
      b.shape.radius = p.radius;
      b.shape.half_length = p.half_length;
      s.bodies.push_back(b);
    }
    for (const Link& l : links) {
      Joint j;
      j.kind = Joint::Kind::Hinge;
      j.body1 = first + l.parent;
      j.body2 = first + l.child;
      j.anchor = q * l.anchor + offset;
      j.axis = q * l.axis;
      j.limits = Joint::Limits{-l.limit, l.limit};
      s.joints.push_back(j);
    }
  }
  return s;
}

Scene pendulumA01(double duration) {
  constexpr double kMass = 1.0, kInertia = 1e-4, kLength = 1.0, kG = 9.81;
  Scene s;
  s.name = "A01 pendulum";
  s.size = "1 body";
  s.timestep = 0.01;
  s.steps = stepsOf(duration, s.timestep);
  s.gravity = Vec3(0.0, -kG, 0.0);
  s.metric = Metric::PathError;
  s.energy = true;
  Body b;
  b.name = "mass";
  b.mass = kMass;
  b.inertia = Vec3::Constant(kInertia);
  b.position = Vec3(-kLength, 0.0, 0.0);
  s.bodies.push_back(b);
  Joint j;
  j.body1 = -1;
  j.body2 = 0;
  j.axis = Vec3::UnitZ();
  s.joints.push_back(j);
  // The physical pendulum released at 90 degrees: theta = 2 asin(k sn(K - w0 t, k)) from the
  // downward vertical, k = sin(45 degrees), w0^2 = m g L / (m L^2 + I).
  const double k = std::sin(kPi / 4);
  const double w0 = std::sqrt(kMass * kG * kLength / (kMass * kLength * kLength + kInertia));
  const double quarter = std::comp_ellint_1(k);
  s.path = KnownPath{0, Vec3::Zero(), "closed form", [=](double t) -> std::optional<Vec3> {
                       const double theta = 2.0 * std::asin(k * jacobiSn(quarter - w0 * t, k));
                       return Vec3(-kLength * std::sin(theta), -kLength * std::cos(theta), 0.0);
                     }};
  return s;
}

Scene fourBarA02(double duration) {
  constexpr int kBars = 40;
  Scene s;
  s.name = "A02 four-bar";
  s.size = "N=40 (81 bodies)";
  s.timestep = 0.01;
  s.steps = stepsOf(duration, s.timestep);
  s.gravity = Vec3(0.0, -9.81, 0.0);
  s.metric = Metric::PathError;
  s.energy = true;
  const double along = 1.0 / 12.0, thin = 1e-4;  // a 1 m, 1 kg rod about its centre
  for (int i = 0; i <= kBars; ++i) {             // the cranks, upright, turning at -1 rad/s
    Body b;
    b.name = "crank" + std::to_string(i);
    b.inertia = Vec3(along, thin, along);
    b.position = Vec3(i, 0.5, 0.0);
    b.velocity = Vec3(0.5, 0.0, 0.0);
    b.angular_velocity = Vec3(0.0, 0.0, -1.0);
    s.bodies.push_back(b);
  }
  for (int i = 0; i < kBars; ++i) {  // the couplers, level, moving at 1 m/s
    Body b;
    b.name = "coupler" + std::to_string(i);
    b.inertia = Vec3(thin, along, along);
    b.position = Vec3(i + 0.5, 1.0, 0.0);
    b.velocity = Vec3(1.0, 0.0, 0.0);
    s.bodies.push_back(b);
  }
  const auto hinge = [&](int b1, int b2, const Vec3& anchor) {
    Joint j;
    j.body1 = b1;
    j.body2 = b2;
    j.anchor = anchor;
    j.axis = Vec3::UnitZ();
    s.joints.push_back(j);
  };
  for (int i = 0; i <= kBars; ++i) hinge(-1, i, Vec3(i, 0.0, 0.0));
  for (int i = 0; i < kBars; ++i) {
    hinge(kBars + 1 + i, i, Vec3(i, 1.0, 0.0));
    hinge(kBars + 1 + i, i + 1, Vec3(i + 1, 1.0, 0.0));
  }
  struct Published {
    double t, x, y;
  };
  const std::vector<Published> published{
      {0.05, 5.02096E-02, 9.98739E-01},  {0.5, 6.87926E-01, 7.25781E-01},
      {1.0, -1.15357E-01, -9.93324E-01}, {2.0, 3.44663E-02, 9.99406E-01},
      {5.0, -5.40191E-01, -8.41543E-01}, {10.0, 1.80513E-01, 9.83573E-01},
      {20.0, 4.10902E-01, 9.11679E-01}};
  s.path = KnownPath{0, Vec3(0.0, 0.5, 0.0), "published reference solution",
                     [published](double t) -> std::optional<Vec3> {
                       for (const Published& p : published)
                         if (std::abs(t - p.t) < 1e-9) return Vec3(p.x, p.y, 0.0);
                       return std::nullopt;
                     }};
  return s;
}

Scene heavyTop(double duration) {
  constexpr double kMass = 1.0, kArm = 0.1, kTilt = 0.5, kPrecession = 1.5, kG = 9.81;
  constexpr double kAcross = 2e-3, kAlong = 3e-3;  // about the centre
  Scene s;
  s.name = "heavy top";
  s.size = "1 body";
  s.timestep = 1e-3;
  s.steps = stepsOf(duration, s.timestep);
  s.gravity = Vec3(0.0, 0.0, -kG);
  s.metric = Metric::PathError;
  s.energy = true;
  // Steady precession at W needs the spin w3 = (m g l + I1 W^2 cos(theta)) / (I3 W), I1 about
  // the tip; the angular velocity is W z + (w3 - W cos(theta)) along the axis.
  const double about_tip = kAcross + kMass * kArm * kArm;
  const double spin =
      (kMass * kG * kArm + about_tip * kPrecession * kPrecession * std::cos(kTilt)) /
      (kAlong * kPrecession);
  const Vec3 axis(std::sin(kTilt), 0.0, std::cos(kTilt));
  Body b;
  b.name = "top";
  b.mass = kMass;
  b.inertia = Vec3(kAcross, kAcross, kAlong);
  b.orientation = Quat::FromTwoVectors(Vec3::UnitZ(), axis);
  b.position = kArm * axis;
  b.angular_velocity = kPrecession * Vec3::UnitZ() + (spin - kPrecession * std::cos(kTilt)) * axis;
  b.velocity = b.angular_velocity.cross(b.position);
  s.bodies.push_back(b);
  Joint tip;
  tip.kind = Joint::Kind::Ball;
  tip.body1 = -1;
  tip.body2 = 0;
  s.joints.push_back(tip);
  s.path = KnownPath{0, Vec3::Zero(), "closed form", [=](double t) -> std::optional<Vec3> {
                       const double azimuth = kPrecession * t;
                       return kArm * Vec3(std::sin(kTilt) * std::cos(azimuth),
                                          std::sin(kTilt) * std::sin(azimuth), std::cos(kTilt));
                     }};
  return s;
}

Scene swingingChain(double duration) {
  Scene s = hingeChain(5);
  s.timestep = 1e-3;
  s.steps = stepsOf(duration, s.timestep);
  return s;
}

Scene spatialSliderCrank(double duration) {
  namespace sc = slider_crank;
  Scene s;
  s.name = "spatial slider-crank";
  s.size = "3 bodies";
  s.timestep = 0.01;
  s.steps = stepsOf(duration, s.timestep);
  s.gravity = Vec3(0.0, -sc::kGravity, 0.0);
  s.metric = Metric::PathError;
  s.energy = true;
  const double q0 = sc::kStart;
  const double t = sc::kThickness, c = sc::kSliderSize;
  s.bodies = {Body{.name = "crank",
                   .mass = sc::kCrankMass,
                   .inertia = sc::boxInertia(sc::kCrankMass, sc::kCrank, t, t),
                   .position = sc::pin(q0) / 2,
                   .orientation = Quat(Eigen::AngleAxisd(q0, Vec3::UnitZ()))},
              Body{.name = "rod",
                   .mass = sc::kRodMass,
                   .inertia = sc::boxInertia(sc::kRodMass, sc::kRod, t, t),
                   .position = (sc::pin(q0) + sc::slider(q0)) / 2,
                   .orientation = Quat(sc::rod(q0))},
              Body{.name = "slider",
                   .mass = sc::kSliderMass,
                   .inertia = sc::boxInertia(sc::kSliderMass, c, c, c),
                   .position = sc::slider(q0)}};
  const auto joint = [&](Joint::Kind kind, int b1, int b2, const Vec3& anchor, const Vec3& axis) {
    s.joints.push_back(
        Joint{.kind = kind, .body1 = b1, .body2 = b2, .anchor = anchor, .axis = axis});
  };
  joint(Joint::Kind::Hinge, -1, 0, Vec3::Zero(), Vec3::UnitZ());     // the crank's bearing
  joint(Joint::Kind::Slider, -1, 2, sc::slider(q0), Vec3::UnitX());  // the guide
  joint(Joint::Kind::Ball, 1, 0, sc::pin(q0), Vec3::UnitZ());        // the crank pin
  joint(Joint::Kind::Ball, 1, 2, sc::slider(q0), Vec3::UnitZ());     // the slider pin
  // The crank pin at every step from Lagrange's equation in the crank angle (balls at both ends
  // of the rod), by fourth-order Runge-Kutta at 0.25 ms.
  s.path = stepwisePath(s, 0, Vec3(sc::kCrank / 2, 0.0, 0.0), "minimal-coordinate solution", [&] {
    const OneDofReference reference = sc::reference(sc::RodEnd::Ball);
    double q = q0, rate = 0.0;
    std::vector<Vec3> pins{sc::pin(q)};
    for (std::int64_t n = 1; n <= s.steps; ++n) {
      reference.advance(q, rate, s.timestep, 2.5e-4);
      pins.push_back(sc::pin(q));
    }
    return pins;
  });
  return s;
}

Scene flyballGovernorA05(double duration) {
  namespace fb = flyball;
  Scene s;
  s.name = "IFToMM A05 flyball governor";
  s.size = "4 bodies";
  s.timestep = 0.01;
  s.steps = stepsOf(duration, s.timestep);
  s.gravity = Vec3(0.0, 0.0, -fb::kG);
  s.metric = Metric::PathError;
  const Vec3 spin(0.0, 0.0, fb::kStartRate);
  const auto turning = [&](Body b) {
    b.angular_velocity = spin;
    b.velocity = spin.cross(b.position);
    return b;
  };
  s.bodies.push_back(
      turning(Body{.name = "shaft",
                   .mass = fb::kBarMass,
                   .inertia = Vec3(fb::kBarMass / 12.0 * (1.0 + 1e-4),
                                   fb::kBarMass / 12.0 * (1.0 + 1e-4), fb::kShaftAxial),
                   .position = Vec3(0.0, 0.0, 0.5)}));
  s.bodies.push_back(turning(Body{.name = "slider",
                                  .mass = fb::kSliderMass,
                                  .inertia = Vec3::Constant(fb::kSliderAxial),
                                  .position = Vec3(0.0, 0.0, fb::kStartHeight)}));
  for (const int side : {1, -1}) {  // each rod with its ball: its body z along the rod
    const Vec3 u = fb::along(side, fb::kStartAngle);
    s.bodies.push_back(
        turning(Body{.name = side > 0 ? "rod_a" : "rod_b",
                     .mass = fb::kRodMass,
                     .inertia = Vec3(fb::kRodTransverse, fb::kRodTransverse, fb::kRodAxial),
                     .position = fb::pivot(side) + fb::kRodCentre * u,
                     .orientation = Quat::FromTwoVectors(Vec3::UnitZ(), u)}));
  }
  s.joints.push_back(Joint{.kind = Joint::Kind::Hinge,
                           .body1 = -1,
                           .body2 = 0,
                           .anchor = Vec3::Zero(),
                           .axis = Vec3::UnitZ()});
  s.joints.push_back(Joint{.kind = Joint::Kind::Slider,
                           .body1 = 0,
                           .body2 = 1,
                           .anchor = Vec3(0.0, 0.0, fb::kStartHeight),
                           .axis = Vec3::UnitZ()});
  for (const int side : {1, -1}) {
    const int rod = side > 0 ? 2 : 3;
    s.joints.push_back(Joint{.kind = Joint::Kind::Hinge,
                             .body1 = 0,
                             .body2 = rod,
                             .anchor = fb::pivot(side),
                             .axis = Vec3::UnitY()});
    s.springs.push_back(Spring{.body1 = rod,
                               .body2 = 1,
                               .anchor1 = fb::rodEnd(side, fb::kStartAngle),
                               .anchor2 = fb::sliderEnd(side, fb::kStartHeight),
                               .stiffness = fb::kStiffness,
                               .damping = fb::kDamping,
                               .rest = fb::kRest});
  }
  // The slider's centre at every step from the reduced-coordinate solution (RK4 at 1e-5 s).
  s.path = stepwisePath(s, 1, Vec3::Zero(), "reduced-coordinate solution", [&] {
    const fb::Reference reference;
    fb::State x;
    std::vector<Vec3> centres{Vec3(0.0, 0.0, x.s)};
    for (std::int64_t n = 1; n <= s.steps; ++n) {
      reference.advance(x, s.timestep, 1e-5);
      centres.emplace_back(0.0, 0.0, x.s);
    }
    return centres;
  });
  return s;
}

}  // namespace bench
