// Values given in time: constants, or tables interpolated linearly (drive targets, prescribed
// motion, applied loads).
#pragma once

#include <linx/types.hpp>

#include <array>
#include <utility>
#include <vector>

namespace linx {

/// A value in time: a constant, or a table of points (times strictly increasing) interpolated
/// linearly between them and held at the first and last values outside them.
struct Signal {
  Signal(double constant = 0.0) : values{constant} {}  // NOLINT: a number is a constant signal
  Signal(std::vector<double> times_, std::vector<double> values_)
      : times(std::move(times_)), values(std::move(values_)) {}
  std::vector<double> times;   ///< (s), empty for a constant
  std::vector<double> values;  ///< one per time; the constant alone when `times` is empty

  double at(double t) const;
  /// d/dt of at(t): the slope of the segment t is in (right-hand at a point), 0 outside.
  double rate(double t) const;
  bool operator==(const Signal&) const = default;
};

/// A vector in time: one Signal per component (a constant force, or a table of forces).
struct VectorSignal {
  VectorSignal(const Vec3& constant = Vec3::Zero())  // NOLINT: a vector is a constant signal
      : components{constant.x(), constant.y(), constant.z()} {}
  explicit VectorSignal(std::array<Signal, 3> components_) : components(std::move(components_)) {}
  std::array<Signal, 3> components;

  Vec3 at(double t) const {
    return {components[0].at(t), components[1].at(t), components[2].at(t)};
  }
  /// Whether it is zero at all times.
  bool isZero() const;
  bool operator==(const VectorSignal&) const = default;
};

}  // namespace linx
