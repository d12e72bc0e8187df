// The spatial slider-crank of examples/benchmarks/spatial_slider_crank.json and of the integrator
// table (linx-bench --integrators): its geometry in closed form and its reference solution in the
// crank angle (one_dof_reference.hpp). A crank of r = 0.08 m turns on a hinge about z at the
// origin; a connecting rod of l = 0.3 m joins its pin to a slider running along x on the line
// y = 0.1 m, z = 0.12 m, out of the crank's plane, so that every joint works in three dimensions.
// Gravity is 9.81 m/s^2 along -y; the mechanism starts at rest with the crank 30 degrees up and
// swings through the lower half-turn and back. Shared by tests/test_iftomm_benchmarks.cpp and
// bench/scenes.cpp.
#pragma once

#include "one_dof_reference.hpp"

#include <cmath>
#include <numbers>
#include <utility>

namespace bench::slider_crank {

inline constexpr double kCrank = 0.08, kRod = 0.3;    // r, l (m)
inline constexpr double kLineY = 0.1, kLineZ = 0.12;  // the slider's line (m)
inline constexpr double kThickness = 0.01;   // the crank's and the rod's square section (m)
inline constexpr double kSliderSize = 0.05;  // the slider's cube (m)
inline constexpr double kCrankMass = 0.5, kRodMass = 0.5, kSliderMass = 1.0;  // (kg)
inline constexpr double kStart = std::numbers::pi / 6;  // the crank angle at rest at t = 0 (rad)
inline constexpr double kGravity = 9.81;

/// The crank pin at crank angle q.
inline Eigen::Vector3d pin(double q) {
  return {kCrank * std::cos(q), kCrank * std::sin(q), 0.0};
}

/// The slider's centre (and the rod's far end) at crank angle q.
inline Eigen::Vector3d slider(double q) {
  const Eigen::Vector3d p = pin(q);
  const double dy = kLineY - p.y();
  return {p.x() + std::sqrt(kRod * kRod - dy * dy - kLineZ * kLineZ), kLineY, kLineZ};
}

/// The rod's frame at crank angle q when a universal joint holds it at the slider, its cross
/// along x in the slider: x along the rod (slider to pin), y = x_world x (rod direction), the
/// cross's arm in the rod.
inline Eigen::Matrix3d rod(double q) {
  const Eigen::Vector3d d = (pin(q) - slider(q)) / kRod;
  const Eigen::Vector3d y = Eigen::Vector3d::UnitX().cross(d).normalized();
  Eigen::Matrix3d m;
  m << d, y, d.cross(y);
  return m;
}

/// Principal moments of a uniform box of mass m and edges x, y, z.
inline Eigen::Vector3d boxInertia(double m, double x, double y, double z) {
  return {m * (y * y + z * z) / 12, m * (x * x + z * z) / 12, m * (x * x + y * y) / 12};
}

/// How the rod is held at the slider.
enum class RodEnd {
  Universal,  ///< it turns with the cross: rod() is its frame, its spin about itself counts
  Ball,       ///< balls at both ends: the symmetric rod never spins about itself (no torque can
              ///< reach that axis), so its moment about its own axis takes no part
};

/// Lagrange's equation in the crank angle for the mechanism with the rod held as `end` says.
inline OneDofReference reference(RodEnd end) {
  using Pose = std::pair<Eigen::Vector3d, Eigen::Matrix3d>;
  Eigen::Vector3d rod_inertia = boxInertia(kRodMass, kRod, kThickness, kThickness);
  if (end == RodEnd::Ball) rod_inertia.x() = 0.0;
  return OneDofReference(
      {{kCrankMass, boxInertia(kCrankMass, kCrank, kThickness, kThickness),
        [](double q) {
          return Pose(pin(q) / 2, Eigen::AngleAxisd(q, Eigen::Vector3d::UnitZ()).matrix());
        }},
       {kRodMass, rod_inertia, [](double q) { return Pose((pin(q) + slider(q)) / 2, rod(q)); }},
       {kSliderMass, boxInertia(kSliderMass, kSliderSize, kSliderSize, kSliderSize),
        [](double q) { return Pose(slider(q), Eigen::Matrix3d::Identity()); }}},
      Eigen::Vector3d(0, -kGravity, 0));
}

}  // namespace bench::slider_crank
