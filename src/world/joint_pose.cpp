// Newton's method on body 1's six displacements: the joint's equality rows (exact J) keep their
// value, its free coordinates (their gradients by central differences of Joint::coordinates) change
// by what is asked of them, the minimum-norm step of that system each iteration; every body of
// body 1's side moves with body 1 as one rigid piece.
#include "world/joint_pose.hpp"

#include "math/rotation.hpp"

#include <fmt/format.h>

#include <Eigen/QR>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <vector>

namespace linx {

namespace {

BodyState stateOf(std::span<const Body> bodies, BodyId id) {
  if (id.isWorld()) return BodyState{};
  const Body& b = bodies[static_cast<std::size_t>(id.index)];
  return BodyState{b.pose(), b.linearVelocity(), b.angularVelocity()};
}

/// Body 1's side: the bodies reachable from body 1 through the other enabled joints, not through
/// static bodies. Throws if it reaches body 2, the world or a static body.
std::vector<int> sideOf(std::span<const Body> bodies,
                        std::span<const std::unique_ptr<Joint>> joints, std::size_t joint) {
  std::vector<int> side{joints[joint]->body1().index};
  std::vector<std::uint8_t> seen(bodies.size(), 0);
  seen[static_cast<std::size_t>(side[0])] = 1;
  for (std::size_t k = 0; k < side.size(); ++k) {
    for (std::size_t j = 0; j < joints.size(); ++j) {
      const Joint& other = *joints[j];
      if (j == joint || !other.enabled()) continue;
      const BodyId a = other.body1(), b = other.body2();
      if (a.index != side[k] && b.index != side[k]) continue;
      const BodyId next = a.index == side[k] ? b : a;
      const bool fixed = next.isWorld() || bodies[static_cast<std::size_t>(next.index)].isStatic();
      if (fixed || next == joints[joint]->body2())
        throw std::invalid_argument(fmt::format(
            "initial: body1's side is also held by joint '{}' (a closed loop, or fixed to the "
            "world): it cannot move alone",
            other.name()));
      if (!seen[static_cast<std::size_t>(next.index)]) {
        seen[static_cast<std::size_t>(next.index)] = 1;
        side.push_back(next.index);
      }
    }
  }
  return side;
}

/// Body 1's pose moved by dx (translation, then a rotation vector about its centre).
BodyState moved(BodyState s, const Vec6& dx) {
  s.pose.position += dx.head<3>();
  s.pose.orientation = math::integrate(s.pose.orientation, dx.tail<3>(), 1.0);
  return s;
}

}  // namespace

void moveToCoordinate(std::span<Body> bodies, std::span<const std::unique_ptr<Joint>> joints,
                      std::size_t joint, int coordinate, double value) {
  Joint& j = *joints[joint];
  const int free = j.freeCoordinates();
  if (coordinate < 0 || coordinate >= free)
    throw std::invalid_argument(fmt::format("coordinates[{}]: a {} joint has {} free coordinates",
                                            coordinate, j.type(), free));
  const std::vector<int> side = sideOf(bodies, joints, joint);
  const BodyState b2 = stateOf(bodies, j.body2());
  const auto fill = [&](const BodyState& b1, std::vector<Row>& rows) {
    rows.assign(static_cast<std::size_t>(j.maxRows()), Row{});
    JointContext ctx{BodyState{b1.pose, Vec3::Zero(), Vec3::Zero()},
                     BodyState{b2.pose, Vec3::Zero(), Vec3::Zero()}, 1.0};
    rows.resize(static_cast<std::size_t>(j.fill(ctx, rows)));
    // The equality rows of the joint itself (slots below the coordinates').
    std::erase_if(
        rows, [](const Row& r) { return r.kind != RowKind::Bilateral || (r.key & 0xff) >= 16; });
  };
  const JointCoordinates start = j.coordinates(stateOf(bodies, j.body1()), b2);
  JointCoordinates goal = start.head(free);
  goal[coordinate] = value;
  std::vector<Row> rows;
  constexpr double kStep = 0.5;      // (rad or m) per iteration at most: turns stay counted
  constexpr double kFarthest = 1e4;  // (m or rad) from where the joint was built
  const double distance = std::abs(value - start[coordinate]);
  if (!(distance <= kFarthest))
    throw std::invalid_argument(
        fmt::format("initial: {} is {:.3g} (m or rad) from where the joint was built; at most {:g}",
                    value, distance, kFarthest));
  // Enough iterations to walk there in steps of kStep, and to converge.
  const int iterations = 100 + static_cast<int>(std::ceil(distance / kStep));
  const auto unreached = [&](const JointCoordinates& q) {
    return std::invalid_argument(
        fmt::format("initial: {} cannot be reached: moving the bodies towards it stops at {:.6g} "
                    "(the joint's geometry allows no more)",
                    value, q[coordinate]));
  };
  for (int iteration = 0; iteration < iterations; ++iteration) {
    const BodyState b1 = stateOf(bodies, j.body1());
    const JointCoordinates q = j.coordinates(b1, b2).head(free);
    fill(b1, rows);
    double miss = (goal - q).cwiseAbs().maxCoeff();
    for (const Row& r : rows) miss = std::max(miss, std::abs(r.phi));
    if (miss < 1e-12) return;
    const auto m = static_cast<Eigen::Index>(rows.size());
    Eigen::MatrixXd a(m + free, 6);
    Eigen::VectorXd rhs(m + free);
    for (Eigen::Index r = 0; r < m; ++r) {
      a.row(r) = rows[static_cast<std::size_t>(r)].Ja.transpose();
      rhs[r] = -rows[static_cast<std::size_t>(r)].phi;
    }
    constexpr double eps = 1e-7;
    for (int c = 0; c < 6; ++c) {
      Vec6 d = Vec6::Zero();
      d[c] = eps;
      const JointCoordinates plus = j.coordinates(moved(b1, d), b2).head(free);
      const JointCoordinates minus = j.coordinates(moved(b1, -d), b2).head(free);
      a.block(m, c, free, 1) = (plus - minus) / (2 * eps);
    }
    rhs.tail(free) = (goal - q).cwiseMax(-kStep).cwiseMin(kStep);
    const Vec6 dx = a.completeOrthogonalDecomposition().solve(rhs);
    if (!dx.allFinite() || dx.isZero(0.0)) throw unreached(q);
    // The side turns about body 1's centre by dtheta and moves by dp, as one rigid piece.
    const Vec3 centre = b1.pose.position;
    const Quat turn = math::expMap(dx.tail<3>());
    for (const int i : side) {
      Body& b = bodies[static_cast<std::size_t>(i)];
      b.setPose(Pose{centre + dx.head<3>() + turn * (b.position() - centre),
                     (turn * b.orientation()).normalized()});
      b.setLinearVelocity(turn * b.linearVelocity());
      b.setAngularVelocity(turn * b.angularVelocity());
    }
    j.track(stateOf(bodies, j.body1()), b2);
  }
  throw unreached(j.coordinates(stateOf(bodies, j.body1()), b2).head(free));
}

}  // namespace linx
