// Basic math types used across the public API. Units are SI; quaternions are (w, x, y, z).
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <limits>

namespace linx {

using Vec3 = Eigen::Vector3d;
using Mat3 = Eigen::Matrix3d;
using Quat = Eigen::Quaterniond;
/// A 6-vector (linear part, angular part): a body velocity or one body's block of a Jacobian row.
using Vec6 = Eigen::Matrix<double, 6, 1>;
/// A joint's two bodies' coordinates against each other (body 1 linear, angular, body 2 ...).
using Mat12 = Eigen::Matrix<double, 12, 12>;

inline constexpr double kInfinity = std::numeric_limits<double>::infinity();

/// A rigid transform: position of the centre of mass (m) and orientation, world frame.
struct Pose {
  Vec3 position = Vec3::Zero();
  Quat orientation = Quat::Identity();

  Vec3 toWorld(const Vec3& local) const { return position + orientation * local; }
  Vec3 toLocal(const Vec3& world) const { return orientation.conjugate() * (world - position); }
};

}  // namespace linx
