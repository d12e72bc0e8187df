#include <linx/joint.hpp>

#include <algorithm>
#include <cmath>
#include <vector>

namespace linx {

double Joint::error(const BodyState& b1, const BodyState& b2) const {
  // The rows' own phi is the error: equality rows count fully, limits only when overshot. Zero
  // velocities keep not-yet-reached limits out; h only scales the (unused) bias.
  const BodyState s1{b1.pose, Vec3::Zero(), Vec3::Zero()};
  const BodyState s2{b2.pose, Vec3::Zero(), Vec3::Zero()};
  std::vector<Row> rows(static_cast<std::size_t>(maxRows()));
  const int n = fill(JointContext{s1, s2, 1.0, 0.0, 0.0}, rows);
  double err = 0.0;
  for (int k = 0; k < n; ++k) {
    const Row& r = rows[static_cast<std::size_t>(k)];
    if (r.kind == RowKind::Bilateral) err = std::max(err, std::abs(r.phi));
    if (r.kind == RowKind::Unilateral) err = std::max(err, -r.phi);
  }
  return err;
}

}  // namespace linx
