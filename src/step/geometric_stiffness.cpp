#include "step/geometric_stiffness.hpp"

#include "world/state_archive.hpp"

#include "step/assembly.hpp"

#include <algorithm>

namespace linx::step {

void GeometricStiffness::measure(std::span<const std::unique_ptr<Joint>> joints,
                                 std::span<const Body> bodies, const SolverSettings& settings,
                                 double h, std::span<const Row> rows,
                                 std::span<const double> lambda) {
  measured_.assign(bodies.size(), Vec6::Zero());
  std::size_t begin = 0;
  for (std::size_t ji = 0; ji < joints.size() && begin < rows.size(); ++ji) {
    // This joint's rows: assembly keyed them (ji + 1) << 8 | slot, in joint order.
    const auto owner = static_cast<std::uint64_t>(ji + 1);
    std::size_t end = begin;
    while (end < rows.size() && (rows[end].key >> 8) == owner) ++end;
    const std::span<const Row> own = rows.subspan(begin, end - begin);
    const std::span<const double> impulse = lambda.subspan(begin, end - begin);
    begin = end;
    if (std::all_of(impulse.begin(), impulse.end(), [](double l) { return l == 0.0; })) continue;

    const Joint& j = *joints[ji];
    // The stiffness is of J, not of the targets: any time will do.
    const JointContext ctx = contextOf(bodies, j, settings, h, 0.0);
    Mat12 k = j.stiffness(ctx, own, impulse);
    // Only the bodies that move count: a static end's force is no coordinate of the system.
    const int ends[2] = {own.front().body_a, own.front().body_b};
    for (int e = 0; e < 2; ++e)
      if (ends[e] < 0) k.middleRows<6>(6 * e).setZero();
    // h^2 K with K measured on impulses (force times h): h times it.
    for (int e = 0; e < 2; ++e) {
      if (ends[e] < 0) continue;
      Vec6& m = measured_[static_cast<std::size_t>(ends[e])];
      for (int c = 0; c < 6; ++c) m[c] += h * k.col(6 * e + c).norm();
    }
  }
  // What goes beyond the bodies' own masses and inertias (at the poses of the measure).
  for (std::size_t i = 0; i < bodies.size(); ++i) {
    Vec6& k = measured_[i];
    if (k.isZero(0)) continue;
    const Body& body = bodies[i];
    if (!body.isDynamic()) {
      k.setZero();
      continue;
    }
    const Mat3 inertia = body.inertiaWorld();
    for (int c = 0; c < 3; ++c) {
      k[c] = std::max(0.0, k[c] - body.mass());
      k[3 + c] = std::max(0.0, k[3 + c] - inertia(c, c));
    }
  }
}

Vec6 GeometricStiffness::added(std::size_t i) const {
  return i < measured_.size() ? measured_[i] : Vec6::Zero();
}

void GeometricStiffness::stiffen(std::size_t i, const Body& body, solver::SolverBody& b) const {
  if (b.inv_mass <= 0.0) return;
  const Vec6 a = added(i);
  if (a.isZero(0)) return;
  // The solver body's mass is one number: the largest of the three serves.
  b.inv_mass = 1.0 / (1.0 / b.inv_mass + a.head<3>().maxCoeff());
  b.inv_inertia = (body.inertiaWorld() + Mat3(a.tail<3>().asDiagonal())).inverse();
}

double GeometricStiffness::ownShare(std::size_t i, const Body& body, const Vec3& w) const {
  const Vec6 a = added(i);
  if (a.isZero(0)) return 1.0;
  const double own = w.dot(body.inertiaWorld() * w);
  const double total = own + w.dot(a.tail<3>().cwiseProduct(w));
  return total > 0.0 ? own / total : 1.0;
}

void GeometricStiffness::persist(state::Archive& a) {
  a(measured_);
}

}  // namespace linx::step
