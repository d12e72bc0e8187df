// The contact joint: three rows at one contact point between bodies a and b (DESIGN.md section 4).
//
// With n the unit normal from a towards b, r_a and r_b the lever arms from each centre of mass to
// the contact point, and t1, t2 unit tangents making (n, t1, t2) right-handed:
//   normal     C = signed distance along n (a gap > 0, a penetration < 0)
//              J = [ -n, -(r_a x n) | n, r_b x n ]     unilateral: 0 <= lambda_n, J u+ >= target
//   friction   J = [ -t, -(r_a x t) | t, r_b x t ]     |lambda_t| <= mu lambda_n, for t = t1, t2
// so the normal impulse pushes b along +n and a along -n, and J u is the velocity of b's point
// relative to a's.
//
// The normal row's target:
// - a gap g > 0 (a speculative contact) allows an approach of at most g / h: erp 1, phi = g, so the
//   bodies meet at the surface at the end of the step instead of stopping short or sinking in;
// - a penetration d deeper than the slop s is removed at the rate erp (d - s) / h; within the slop
//   nothing is corrected (phi = 0), so resting contacts do not jitter;
// - restitution: when the approach speed v = -J u exceeds the threshold and the gap closes within
//   the step, the target is e v (the bounce), unless the penetration correction asks for more.
// The friction rows have no target (static friction holds the points together). t1 follows the
// sliding velocity when there is one, so that the box-shaped friction bound of two rows acts as the
// isotropic Coulomb cone for sliding; at rest (no sliding) the tangents are a fixed basis of n.
#pragma once

#include <linx/joint.hpp>
#include <linx/row.hpp>

#include <limits>
#include <span>

#include "collision/narrowphase.hpp"

namespace linx::joints {

/// The material and numerical parameters of one contact (already combined for the pair).
struct ContactLaw {
  double friction = 0.5;               ///< mu, >= 0
  double restitution = 0.0;            ///< e in [0, 1]
  double erp = 0.2;                    ///< penetration removed per step beyond the slop
  double cfm = 1e-10;                  ///< normal and friction rows
  double slop = 5e-4;                  ///< allowed penetration (m)
  double restitution_threshold = 0.2;  ///< (m/s) slower approaches do not bounce
  double max_push_out = 3.0;           ///< (m/s) penetration is pushed out no faster
};

/// Sliding speeds (m/s) above which the first tangent follows the sliding direction.
inline constexpr double kSlidingSpeed = 1e-4;

/// Writes every field but the body indices of the normal row and the two friction rows
/// (`normal` = 0, the slot of the normal row) of contact c between bodies a and b in their current
/// states, for a step h, in place (the caller's row list: no copies); writes the tangents it used.
/// Row keys are the slots 0, 1, 2. `start_approach`: the speed (m/s) at which the points
/// approached at the start of the step, before its forces, which a bounce reflects: the speed the
/// bodies have where they are now (NaN: the approach in their current states).
void contactRows(const collision::ContactPoint& c, const BodyState& a, const BodyState& b,
                 const ContactLaw& law, double h, Row& normal, std::span<Row, 2> friction, Vec3& t1,
                 Vec3& t2, double start_approach = std::numeric_limits<double>::quiet_NaN());

}  // namespace linx::joints
