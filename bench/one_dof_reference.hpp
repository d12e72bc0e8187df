// A reference solution for a mechanism of one degree of freedom, in its own minimal coordinate:
// Lagrange's equation for a coordinate q whose closed-form kinematics place every body,
//
//     m(q) q'' + 1/2 m'(q) q'^2 + V'(q) = 0,   m(q) = sum_i m_i |dp_i/dq|^2 + w_i^T I_i w_i,
//                                               V(q) = -sum_i m_i g . p_i,
//
// (w_i: body i's angular velocity per unit q'), integrated by the classical Runge-Kutta method at
// a step far below the one it is compared against. It shares nothing with the engine but the
// geometry: no constraint rows, no multipliers, no projection. The spatial slider-crank's test
// (tests/test_iftomm_benchmarks.cpp) compares linx's full-coordinate motion with it.
#pragma once

#include <Eigen/Geometry>

#include <cmath>
#include <functional>
#include <utility>
#include <vector>

namespace bench {

/// d f / dq by central differences, Richardson-extrapolated (error ~ h^4 f^(5), h = 1e-3).
template <typename F>
auto derivative(const F& f, double q) {
  constexpr double h = 1e-3;
  const auto central = [&](double step) {
    return ((f(q + step) - f(q - step)) / (2 * step)).eval();
  };
  return ((4.0 * central(0.5 * h) - central(h)) / 3.0).eval();
}

/// One rigid body of the mechanism: its mass, its principal inertia about its centre of mass (in
/// its own frame), and where the coordinate puts it.
struct OneDofBody {
  double mass;
  Eigen::Vector3d inertia;
  /// q -> (centre of mass, orientation), both in the world frame.
  std::function<std::pair<Eigen::Vector3d, Eigen::Matrix3d>(double)> pose;
};

class OneDofReference {
 public:
  OneDofReference(std::vector<OneDofBody> bodies, Eigen::Vector3d gravity)
      : bodies_(std::move(bodies)), gravity_(std::move(gravity)) {}

  /// The generalized mass m(q).
  double mass(double q) const {
    double m = 0.0;
    for (const OneDofBody& b : bodies_) {
      const Eigen::Vector3d v = derivative([&](double x) { return b.pose(x).first; }, q);
      const Eigen::Vector3d w = angularRate(b, q);
      const Eigen::Matrix3d r = b.pose(q).second;
      m += b.mass * v.squaredNorm() + w.dot(r * b.inertia.asDiagonal() * r.transpose() * w);
    }
    return m;
  }

  /// The potential energy V(q) of gravity (J, zero at the world's origin).
  double potential(double q) const {
    double v = 0.0;
    for (const OneDofBody& b : bodies_) v -= b.mass * gravity_.dot(b.pose(q).first);
    return v;
  }

  /// The total energy at (q, q').
  double energy(double q, double rate) const { return 0.5 * mass(q) * rate * rate + potential(q); }

  /// q'' at (q, q').
  double acceleration(double q, double rate) const {
    const auto m = [&](double x) { return Eigen::Matrix<double, 1, 1>(mass(x)); };
    const auto v = [&](double x) { return Eigen::Matrix<double, 1, 1>(potential(x)); };
    return -(0.5 * derivative(m, q)(0) * rate * rate + derivative(v, q)(0)) / mass(q);
  }

  /// Advances (q, q') by `duration` in steps of at most `step` (classical fourth-order RK).
  void advance(double& q, double& rate, double duration, double step) const {
    const int n = std::max(1, static_cast<int>(std::ceil(duration / step - 1e-9)));
    const double h = duration / n;
    for (int i = 0; i < n; ++i) {
      const double k1q = rate, k1r = acceleration(q, rate);
      const double k2q = rate + 0.5 * h * k1r, k2r = acceleration(q + 0.5 * h * k1q, k2q);
      const double k3q = rate + 0.5 * h * k2r, k3r = acceleration(q + 0.5 * h * k2q, k3q);
      const double k4q = rate + h * k3r, k4r = acceleration(q + h * k3q, k4q);
      q += h / 6.0 * (k1q + 2.0 * k2q + 2.0 * k3q + k4q);
      rate += h / 6.0 * (k1r + 2.0 * k2r + 2.0 * k3r + k4r);
    }
  }

 private:
  // Body b's angular velocity per unit q': the axis-angle of R(q + e) R(q - e)^T over 2 e,
  // Richardson-extrapolated as derivative() is.
  static Eigen::Vector3d angularRate(const OneDofBody& b, double q) {
    const auto central = [&](double step) {
      const Eigen::AngleAxisd turn(b.pose(q + step).second * b.pose(q - step).second.transpose());
      return (turn.angle() / (2 * step) * turn.axis()).eval();
    };
    constexpr double h = 1e-3;
    return (4.0 * central(0.5 * h) - central(h)) / 3.0;
  }

  std::vector<OneDofBody> bodies_;
  Eigen::Vector3d gravity_;
};

}  // namespace bench
