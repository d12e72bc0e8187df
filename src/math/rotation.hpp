// Small rotation helpers over Eigen: skew matrices, quaternion integration, rotation vectors.
#pragma once

#include <linx/types.hpp>

namespace linx::math {

/// [v]x, so that skew(v) * u == v.cross(u).
Mat3 skew(const Vec3& v);

/// The rotation by the rotation vector `theta` (axis times angle, rad), exactly (exponential map).
Quat expMap(const Vec3& theta);

/// Rotation vector (axis times angle in (-pi, pi]) of a unit quaternion: the inverse of expMap.
Vec3 logMap(const Quat& q);

/// q advanced by a constant world-frame angular velocity w over h: exp(h w) * q, normalized.
Quat integrate(const Quat& q, const Vec3& w, double h);

/// Angle (rad, in (-pi, pi]) of the twist of q about the unit axis a (swing-twist decomposition).
double twistAngle(const Quat& q, const Vec3& a);

/// Two unit vectors that make (a, t1, t2) a right-handed orthonormal basis; a must be unit.
void orthonormalBasis(const Vec3& a, Vec3& t1, Vec3& t2);

}  // namespace linx::math
