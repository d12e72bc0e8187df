#include "joints/contact_joint.hpp"

#include <algorithm>

#include "math/rotation.hpp"

namespace linx::joints {

namespace {
/// A row J = [ -d, -(r_a x d) | d, r_b x d ]: the velocity of b's point relative to a's along d.
void relativeRow(const Vec3& d, const Vec3& ra, const Vec3& rb, Row& row) {
  row.Ja << -d, -ra.cross(d);
  row.Jb << d, rb.cross(d);
}
}  // namespace

void contactRows(const collision::ContactPoint& c, const BodyState& a, const BodyState& b,
                 const ContactLaw& law, double h, Row& normal, std::span<Row, 2> friction, Vec3& t1,
                 Vec3& t2, double start_approach) {
  const Vec3& n = c.normal;
  const Vec3 ra = c.point - a.pose.position, rb = c.point - b.pose.position;
  const Vec3 rel = (b.v + b.w.cross(rb)) - (a.v + a.w.cross(ra));  // b's point relative to a's
  const double vn = n.dot(rel);
  const Vec3 slide = rel - vn * n;
  if (slide.norm() > kSlidingSpeed) {
    t1 = slide.normalized();
    t2 = n.cross(t1);
  } else {
    math::orthonormalBasis(n, t1, t2);
  }

  relativeRow(n, ra, rb, normal);
  normal.kind = RowKind::Unilateral;
  normal.normal = -1;
  normal.mu = 0.0;
  normal.lo = 0.0;
  normal.hi = kInfinity;
  normal.cfm = law.cfm;
  normal.speed = 0.0;
  normal.key = 0;
  const double gap = -c.depth;
  if (gap > 0.0) {  // speculative: reach the surface by the end of the step, no sooner
    normal.phi = gap;
    normal.erp = 1.0;
  } else {  // penetrating: push out what lies beyond the slop, at max_push_out at most, by a
            // split impulse (the positions move, the velocity keeps none of it)
    normal.phi = std::min(0.0, gap + law.slop);
    normal.erp = law.erp;
    if (normal.erp * -normal.phi > law.max_push_out * h)
      normal.phi = -law.max_push_out * h / normal.erp;
  }
  const double approach = -vn;
  if (law.restitution > 0.0 && approach > law.restitution_threshold &&
      approach * h >= std::max(gap, 0.0)) {
    // The bounce reverses the bodies where they are now, so it reflects the speed they have here:
    // the approach before this step's forces. The approach after them (`approach`) is faster by
    // the step's acceleration times h, and an e = 1 ball dropped 0.4 m at h = 1 ms gained its
    // weight times 3 mm at each bounce (0.85 % of its energy).
    const double reflected = std::isnan(start_approach) ? approach : start_approach;
    const double bounce = law.restitution * std::max(0.0, reflected);
    if (gap <= 0.0) {
      normal.speed = bounce;  // the penetration is still pushed out, by the split impulse
    } else if (bounce > normal.target(h)) {
      normal.speed = bounce;
      normal.phi = 0.0;
    }
  }

  for (int k = 1; k <= 2; ++k) {
    Row& f = friction[static_cast<std::size_t>(k - 1)];
    relativeRow(k == 1 ? t1 : t2, ra, rb, f);
    f.kind = RowKind::Friction;
    f.normal = 0;
    f.mu = law.friction;
    f.lo = -kInfinity;  // the solvers bound friction rows by mu lambda_n
    f.hi = kInfinity;
    f.phi = 0.0;
    f.speed = 0.0;
    f.erp = 0.0;
    f.cfm = law.cfm;
    f.key = static_cast<std::uint64_t>(k);
  }
}

}  // namespace linx::joints
