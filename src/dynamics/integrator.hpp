// Time integration of single bodies: the velocity stage before the constraint solve and the
// position stage after it (DESIGN.md section 2, semi-implicit Euler).
#pragma once

#include <linx/body.hpp>

namespace linx::dynamics {

/// u* = u + h M^-1 f: gravity, applied forces and torques, and the gyroscopic term w x (I w);
/// then the body's damping, implicitly: u* / (1 + h c).
/// The gyroscopic term is integrated by the implicit midpoint rule in the body frame, solved by
/// Newton's method: it keeps 1/2 w.I w and |I w| of a torque-free body exactly (both are
/// quadratic invariants of Euler's equations) and stays stable for fast asymmetric spin.
void integrateVelocity(Body& body, const Vec3& gravity, double h);

/// x+ = x + h v+, q+ = exp(h w+) q (exact exponential map, normalized).
void integratePosition(Body& body, double h);

/// x += dx, q = exp(dtheta) q: a displacement without a velocity (post-stabilization).
void displace(Body& body, const Vec3& dx, const Vec3& dtheta);

/// The body-frame angular velocity after a torque-free implicit midpoint step of Euler's equations
/// I dw/dt = (I w) x w. Exposed for tests.
Vec3 gyroscopicStep(const Mat3& inertia, const Vec3& w_body, double h);

}  // namespace linx::dynamics
