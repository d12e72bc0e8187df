#include "math/rotation.hpp"

#include <cmath>

namespace linx::math {

Mat3 skew(const Vec3& v) {
  Mat3 s;
  s << 0.0, -v.z(), v.y(), v.z(), 0.0, -v.x(), -v.y(), v.x(), 0.0;
  return s;
}

Quat expMap(const Vec3& theta) {
  const double angle = theta.norm();
  const double half = 0.5 * angle;
  // sin(half)/angle, with its series near zero so that tiny rotations stay exact to round-off.
  const double k = angle < 1e-8 ? 0.5 - angle * angle / 48.0 : std::sin(half) / angle;
  return Quat(std::cos(half), k * theta.x(), k * theta.y(), k * theta.z());
}

Vec3 logMap(const Quat& q_in) {
  Quat q = q_in;
  if (q.w() < 0.0) q.coeffs() = -q.coeffs();  // the shorter way round
  const Vec3 v = q.vec();
  const double s = v.norm();
  if (s < 1e-12) return 2.0 * v;  // angle ~ 2 s
  const double angle = 2.0 * std::atan2(s, q.w());
  return v * (angle / s);
}

Quat integrate(const Quat& q, const Vec3& w, double h) {
  return (expMap(h * w) * q).normalized();
}

double twistAngle(const Quat& q, const Vec3& a) {
  // Twist about a: the quaternion (w, (v.a) a) normalized; its angle is 2 atan2(v.a, w).
  double angle = 2.0 * std::atan2(q.vec().dot(a), q.w());
  if (angle > M_PI) angle -= 2.0 * M_PI;
  if (angle <= -M_PI) angle += 2.0 * M_PI;
  return angle;
}

void orthonormalBasis(const Vec3& a, Vec3& t1, Vec3& t2) {
  // Pick the world axis least aligned with a, then Gram-Schmidt.
  const Vec3 helper = std::abs(a.x()) < 0.57735   ? Vec3::UnitX()
                      : std::abs(a.y()) < 0.57735 ? Vec3::UnitY()
                                                  : Vec3::UnitZ();
  t1 = (helper - a * a.dot(helper)).normalized();
  t2 = a.cross(t1);
}

}  // namespace linx::math
