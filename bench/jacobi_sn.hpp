// Jacobi's elliptic function sn(u, k), for the pendulum's closed form: the benchmark's IFToMM A01
// scene (bench/scenes.cpp) and linx's own A01 test (tests/test_iftomm_benchmarks.cpp) use it.
#pragma once

#include <cmath>
#include <cstddef>
#include <vector>

namespace bench {

/// sn(u, k) by the arithmetic-geometric mean (Abramowitz and Stegun 16.4.3), 0 <= k < 1.
inline double jacobiSn(double u, double k) {
  std::vector<double> a{1.0}, c{k};
  double b = std::sqrt(1.0 - k * k);
  while (std::abs(c.back()) > 1e-16 && a.size() < 64) {
    const double next = 0.5 * (a.back() + b);
    c.push_back(0.5 * (a.back() - b));
    b = std::sqrt(a.back() * b);
    a.push_back(next);
  }
  double phi = std::ldexp(a.back(), static_cast<int>(a.size()) - 1) * u;
  for (std::size_t n = a.size() - 1; n > 0; --n)
    phi = 0.5 * (phi + std::asin(c[n] * std::sin(phi) / a[n]));
  return std::sin(phi);
}

}  // namespace bench
