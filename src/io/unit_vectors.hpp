// What a scene file's directions and quaternions become when read: a vector already of unit
// length to round-off (within 4 units in the last place of 1) is kept as written, any other is
// divided by its length. The writer (scene_writer.cpp) writes what reads back to the stored
// vector by the same rule: a unit vector as it is, so that one rotated by a model's frames (and
// so a few units in the last place off 1) still reads back to the bit.
#pragma once

#include <Eigen/Core>

#include <cmath>
#include <limits>

namespace linx::io {

template <int N>
Eigen::Matrix<double, N, 1> readNormalized(const Eigen::Matrix<double, N, 1>& v) {
  const double length = v.stableNorm();
  if (std::abs(length - 1.0) <= 4.0 * std::numeric_limits<double>::epsilon()) return v;
  Eigen::Matrix<double, N, 1> out;
  for (int i = 0; i < N; ++i) out[i] = v[i] / length;
  return out;
}

}  // namespace linx::io
