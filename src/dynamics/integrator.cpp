#include "dynamics/integrator.hpp"

#include "math/rotation.hpp"

namespace linx::dynamics {

Vec3 gyroscopicStep(const Mat3& inertia, const Vec3& w0, double h) {
  // Solve F(w1) = I (w1 - w0) + h wm x (I wm) = 0, wm = (w0 + w1) / 2, by Newton from w1 = w0.
  // dF/dw1 = I + h/2 ([wm]x I - [I wm]x). Converges in a few iterations while h |w| is moderate.
  // An isotropic inertia (a sphere, a cube) has no gyroscopic torque: w1 = w0.
  if (inertia.isDiagonal(0.0) && inertia(0, 0) == inertia(1, 1) && inertia(1, 1) == inertia(2, 2))
    return w0;
  Vec3 w1 = w0;
  for (int it = 0; it < 8; ++it) {
    const Vec3 wm = 0.5 * (w0 + w1);
    const Vec3 lm = inertia * wm;
    const Vec3 f = inertia * (w1 - w0) + h * wm.cross(lm);
    const Mat3 jac = inertia + 0.5 * h * (math::skew(wm) * inertia - math::skew(lm));
    const Vec3 dw = jac.partialPivLu().solve(f);
    w1 -= dw;
    if (dw.squaredNorm() <= 1e-30 * (1.0 + w1.squaredNorm())) break;
  }
  return w1;
}

void integrateVelocity(Body& body, const Vec3& gravity, double h) {
  if (!body.isDynamic()) return;  // a kinematic body keeps its own velocity
  // Damping implicitly: v+ = (v + h a) / (1 + h c).
  body.setLinearVelocity(
      (body.linearVelocity() + h * (gravity + body.inverseMass() * body.force())) /
      (1.0 + h * body.linearDamping()));

  const Mat3 r = body.orientation().toRotationMatrix();
  Vec3 w_body = r.transpose() * body.angularVelocity();
  if (!w_body.isZero(0.0)) w_body = gyroscopicStep(body.inertiaBody(), w_body, h);
  const Vec3 torque_body = r.transpose() * body.torque();
  w_body += h * (body.inverseInertiaBody() * torque_body);
  body.setAngularVelocity(r * w_body / (1.0 + h * body.angularDamping()));
}

void integratePosition(Body& body, double h) {
  if (body.isStatic()) return;
  Pose pose = body.pose();
  pose.position += h * body.linearVelocity();
  pose.orientation = math::integrate(pose.orientation, body.angularVelocity(), h);
  body.setPose(pose);
}

void displace(Body& body, const Vec3& dx, const Vec3& dtheta) {
  if (!body.isDynamic()) return;
  Pose pose = body.pose();
  pose.position += dx;
  pose.orientation = math::integrate(pose.orientation, dtheta, 1.0);
  body.setPose(pose);
}

}  // namespace linx::dynamics
