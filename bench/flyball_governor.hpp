// IFToMM A05, the stiff flyball governor (examples/benchmarks/iftomm_a05_flyball_governor.json),
// and a reference solution of its own in reduced coordinates.
//
// The layout, as the library's data give it and MBS-BOS (Tagliapietra, Vivian, Ceseracciu,
// Reggiani: the benchmarks in OpenSim) builds it, z up: a shaft (1 x 0.01 x 0.01 m, density
// 3000) turns on a hinge about z at the origin and spans z in [0, 1]; a slider (0.1 m cube) runs
// along it, its centre at height s = 0.5 m; two rods (as the shaft) hinge about y at
// (+-0.05, 0, 1), hanging alpha = 30 degrees below the horizontal (60 degrees from the shaft),
// each with a 5 kg point mass at its far end; in place of coupler rods, a spring-damper (K = 8e5
// N/m, C = 4e4 N s/m, rest length 0.5 m) joins each rod's middle to the slider at (+-0.05, 0, s).
// The whole turns at 2 pi rad/s about z at the start, every other rate zero.
//
// The reference: the motion keeps the mirror symmetry of its start, the shaft's angle is cyclic
// (its angular momentum L about z is kept: nothing acts about z), and what is left is Lagrange's
// equations in the rods' angle theta from the downward vertical and the slider's height s, in
// closed form (each ball is welded to its rod: one rigid body, m = 5.3 kg):
//   T = 1/2 [M_theta theta'^2 + m_s s'^2 + I0(theta) w^2],   w = L / I0(theta),
//   M_theta theta'' = 1/2 I0'(theta) w^2 - dV/dtheta - 2 F dd/dtheta,
//   m_s s''         = -m_s g - 2 F dd/ds,
// with F = K (d - 0.5) + C d' each spring's tension and d its length (the same for both).
// It shares nothing with the engine but the geometry: no constraint rows, no multipliers.
#pragma once

#include <Eigen/Geometry>

#include <cmath>
#include <numbers>

namespace bench::flyball {

constexpr double kG = 9.81;
constexpr double kDensity = 3000.0;
constexpr double kBarMass = kDensity * 1.0 * 0.01 * 0.01;   // shaft and rods: 0.3 kg
constexpr double kSliderMass = kDensity * 0.1 * 0.1 * 0.1;  // 3 kg
constexpr double kBall = 5.0;                               // each point mass (kg)
constexpr double kStiffness = 8e5, kDamping = 4e4, kRest = 0.5;
constexpr double kOffset = 0.05;  // the rods' pivots and the springs' slider ends off the axis
constexpr double kStartAngle = std::numbers::pi / 3;  // rods from the downward vertical
constexpr double kStartHeight = 0.5;                  // s
constexpr double kStartRate = 2 * std::numbers::pi;   // rad/s about z

// A rod with its ball: one rigid body.
constexpr double kRodMass = kBarMass + kBall;
constexpr double kRodCentre = (kBarMass * 0.5 + kBall * 1.0) / kRodMass;  // from the pivot (m)
/// About the rod's axis (the bar's own: the ball lies on it) and across it.
constexpr double kRodAxial = kBarMass / 12.0 * (0.01 * 0.01 + 0.01 * 0.01);
constexpr double kRodTransverse = kBarMass / 12.0 * (1.0 + 0.01 * 0.01) +
                                  kBarMass * (0.5 - kRodCentre) * (0.5 - kRodCentre) +
                                  kBall * (1.0 - kRodCentre) * (1.0 - kRodCentre);
constexpr double kShaftAxial = kRodAxial;                                      // about z
constexpr double kSliderAxial = kSliderMass / 12.0 * (0.1 * 0.1 + 0.1 * 0.1);  // about z

/// Rod `side` (+1 along +x, -1 along -x) at angle theta, in the shaft's turning plane (x, z).
inline Eigen::Vector3d pivot(int side) {
  return {side * kOffset, 0.0, 1.0};
}
inline Eigen::Vector3d along(int side, double theta) {
  return {side * std::sin(theta), 0.0, -std::cos(theta)};
}
/// A spring's ends: the rod's middle and the slider's point.
inline Eigen::Vector3d rodEnd(int side, double theta) {
  return pivot(side) + 0.5 * along(side, theta);
}
inline Eigen::Vector3d sliderEnd(int side, double s) {
  return {side * kOffset, 0.0, s};
}

struct State {
  double theta = kStartAngle, theta_rate = 0.0;
  double s = kStartHeight, s_rate = 0.0;
  double dissipated = 0.0;  // by the two dampers since the start (J)
};

class Reference {
 public:
  /// The shaft's, the slider's and the rods' moment of inertia about z at theta.
  static double axialInertia(double theta) {
    const double x = kOffset + kRodCentre * std::sin(theta), c = std::cos(theta);
    return kShaftAxial + kSliderAxial +
           2.0 * (kRodMass * x * x + kRodTransverse * (1.0 - c * c) + kRodAxial * c * c);
  }
  /// The angular momentum about z (kept).
  double momentum() const { return momentum_; }
  /// The rate of the shaft at theta.
  double rate(double theta) const { return momentum_ / axialInertia(theta); }

  /// Kinetic, gravity's and the springs' energy (J; gravity's zero at z = 0).
  double energy(const State& x) const {
    const double m_theta = 2.0 * (kRodMass * kRodCentre * kRodCentre + kRodTransverse);
    const double w = rate(x.theta);
    const double kinetic =
        0.5 * (m_theta * x.theta_rate * x.theta_rate + kSliderMass * x.s_rate * x.s_rate +
               axialInertia(x.theta) * w * w);
    const double height = 2.0 * kRodMass * (1.0 - kRodCentre * std::cos(x.theta)) +
                          kSliderMass * x.s + kBarMass * 0.5;
    const double stretch = length(x.theta, x.s) - kRest;
    return kinetic + kG * height + 2.0 * 0.5 * kStiffness * stretch * stretch;
  }

  /// Advances x by dt in steps of at most `substep` (classical Runge-Kutta).
  void advance(State& x, double dt, double substep) const {
    const int n = static_cast<int>(std::ceil(dt / substep - 1e-9));
    const double h = dt / n;
    for (int i = 0; i < n; ++i) {
      const State k1 = rates(x), k2 = rates(plus(x, k1, h / 2)), k3 = rates(plus(x, k2, h / 2)),
                  k4 = rates(plus(x, k3, h));
      x.theta += h / 6 * (k1.theta + 2 * k2.theta + 2 * k3.theta + k4.theta);
      x.theta_rate +=
          h / 6 * (k1.theta_rate + 2 * k2.theta_rate + 2 * k3.theta_rate + k4.theta_rate);
      x.s += h / 6 * (k1.s + 2 * k2.s + 2 * k3.s + k4.s);
      x.s_rate += h / 6 * (k1.s_rate + 2 * k2.s_rate + 2 * k3.s_rate + k4.s_rate);
      x.dissipated +=
          h / 6 * (k1.dissipated + 2 * k2.dissipated + 2 * k3.dissipated + k4.dissipated);
    }
  }

 private:
  static double length(double theta, double s) {
    return (rodEnd(1, theta) - sliderEnd(1, s)).norm();
  }

  static State plus(const State& x, const State& k, double h) {
    return {x.theta + h * k.theta, x.theta_rate + h * k.theta_rate, x.s + h * k.s,
            x.s_rate + h * k.s_rate, 0.0};
  }

  /// The rates of (theta, theta', s, s', dissipated).
  State rates(const State& x) const {
    const double st = std::sin(x.theta), ct = std::cos(x.theta);
    // The spring's length d and its partial derivatives: d^2 = (st / 2)^2 + (1 - ct / 2 - s)^2.
    const double a = 0.5 * st, b = 1.0 - 0.5 * ct - x.s;
    const double d = std::hypot(a, b);
    const double d_theta = (a * 0.5 * ct + b * 0.5 * st) / d, d_s = -b / d;
    const double d_rate = d_theta * x.theta_rate + d_s * x.s_rate;
    const double tension = kStiffness * (d - kRest) + kDamping * d_rate;
    // I0'(theta), and gravity's dV/dtheta for the two rods.
    const double arm = kOffset + kRodCentre * st;
    const double inertia_rate = 2.0 * (2.0 * kRodMass * arm * kRodCentre * ct +
                                       2.0 * (kRodTransverse - kRodAxial) * st * ct);
    const double w = rate(x.theta);
    const double m_theta = 2.0 * (kRodMass * kRodCentre * kRodCentre + kRodTransverse);
    State r;
    r.theta = x.theta_rate;
    r.theta_rate = (0.5 * inertia_rate * w * w - 2.0 * kRodMass * kG * kRodCentre * st -
                    2.0 * tension * d_theta) /
                   m_theta;
    r.s = x.s_rate;
    r.s_rate = (-kSliderMass * kG - 2.0 * tension * d_s) / kSliderMass;
    r.dissipated = 2.0 * kDamping * d_rate * d_rate;
    return r;
  }

  double momentum_ = axialInertia(kStartAngle) * kStartRate;
};

}  // namespace bench::flyball
