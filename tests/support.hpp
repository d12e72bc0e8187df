// Independent truths for the validation tests: closed forms, not the engine's own code.
#pragma once

#include <linx/linx.hpp>

#include <cmath>
#include <numbers>
#include <vector>

namespace linx::test {

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

/// Times at which a sampled signal crosses zero upwards, by linear interpolation.
inline std::vector<double> upwardCrossings(const std::vector<double>& t,
                                           const std::vector<double>& y) {
  std::vector<double> out;
  for (std::size_t i = 1; i < y.size(); ++i)
    if (y[i - 1] < 0.0 && y[i] >= 0.0)
      out.push_back(t[i - 1] + (t[i] - t[i - 1]) * (-y[i - 1]) / (y[i] - y[i - 1]));
  return out;
}

}  // namespace linx::test
