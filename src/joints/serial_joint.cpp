// Serial joint: k hinges and slides in series (1 <= k <= 6), as a body with several joints in
// MJCF: body 1 moves on the last axis, which moves on the one before, ..., on the first, fixed in
// body 2. With T0 body 1's pose in body 2's frame at creation and E_i the motion of axis i by its
// coordinate q_i (a turn about the axis through its point, or a shift along it), in body 1's frame,
//   T(q) = T0 E_1(q_1) E_2(q_2) ... E_k(q_k).
// Full coordinates keep no q: each step finds it, the q whose chain ends nearest body 1 (Gauss-
// Newton, least squares, from the last step's q: it counts turns). At the chain's pose, axis i
// (world direction u_i through x_i) moves body 1 relative to body 2 with the twist, at body 1's
// centre c,
//   S_i = (u_i, u_i x (c - x_i)) for a hinge, (0, u_i) for a slide,
// and the relative twist of the bodies V = (w1 - w2, v1 - v2 - w2 x (c - p2)) = S q'. Rows, each a
// weight g = (g_w, g_v) on V:  J = [ g_v, g_w | -g_v, -(g_w + (c - p2) x g_v) ].
//   held directions (6 - k rows): g _|_ every S_i, C = g . r, r = (rotation vector, shift) from
//     the chain's end to body 1, which the fit leaves _|_ to the S_i (exact at C = 0);
//   coordinate i: g = row i of (S^T W S)^-1 S^T W (g . S_j = delta_ij; W weighs rotation over
//     displacement, see kRateMetric), C = q_i: its limits,
//     motor, spring, friction and armature (joints/row_parts.hpp, coordinateRows).
// The held basis is the last step's, turned with body 1, projected off the S_i and made
// orthonormal (symmetric orthonormalization: the nearest orthonormal basis): it turns smoothly,
// so a row keeps its meaning (warm start, the stiffness's differences). S must keep full rank:
// axes that come into line (a gimbal lock) leave the joint singular there.
#include "joints/serial_joint.hpp"

#include "world/state_archive.hpp"

#include "math/rotation.hpp"

#include <fmt/format.h>

#include <Eigen/Eigenvalues>
#include <Eigen/SVD>

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>

namespace linx::joints {

namespace {

using Axis = SerialJoint::Axis;
using Twists = SerialJoint::Twists;
using Held = SerialJoint::Held;
using Gram =
    Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, kMaxCoordinates, kMaxCoordinates>;

// The chain at coordinates q: where it puts body 1, and each axis in the world.
struct Chain {
  Pose end;
  std::array<Vec3, kMaxCoordinates> direction{}, point{};
};

Chain chainAt(const std::vector<Axis>& axes, const Quat& rest_rotation, const Vec3& rest_offset,
              const JointCoordinates& q, const Pose& body2) {
  Chain chain;
  Quat r = body2.orientation * rest_rotation;
  Vec3 t = body2.toWorld(rest_offset);
  for (std::size_t i = 0; i < axes.size(); ++i) {
    const Axis& a = axes[i];
    const double qi = q[static_cast<Eigen::Index>(i)];
    const Vec3 u = r * a.direction;
    chain.direction[i] = u;
    if (a.linear) {
      chain.point[i] = t;
      t += qi * u;
    } else {
      const Vec3 x = t + r * a.point;  // stays put as the hinge turns
      chain.point[i] = x;
      r = (r * Quat(Eigen::AngleAxisd(qi, a.direction))).normalized();
      t = x - r * a.point;
    }
  }
  chain.end = Pose{t, r};
  return chain;
}

// The axes' twists at the point c.
Twists twistsAt(const std::vector<Axis>& axes, const Chain& chain, const Vec3& c) {
  Twists s(6, static_cast<Eigen::Index>(axes.size()));
  for (std::size_t i = 0; i < axes.size(); ++i) {
    const Vec3& u = chain.direction[i];
    const auto col = static_cast<Eigen::Index>(i);
    if (axes[i].linear) {
      s.col(col) << Vec3::Zero(), u;
    } else {
      s.col(col) << u, u.cross(c - chain.point[i]);
    }
  }
  return s;
}

// (S^T W S)^-1 S^T W: the coordinates' rates of a relative twist (exact for a twist the axes
// make), the least-squares fit of any other in the metric W = diag(1, 1, 1, w, w, w) (rad^2 and
// w m^2).
using Rates = Eigen::Matrix<double, Eigen::Dynamic, 6, 0, kMaxCoordinates, 6>;
Rates ratesOf(const Twists& s, double w = 1.0) {
  Twists ws = s;
  ws.bottomRows<3>() *= w;
  const Gram gram = s.transpose() * ws;
  return gram.ldlt().solve(ws.transpose());
}
// The metric of the coordinates' rows: the bodies' velocities at a step's start, which the solve
// made to fit the joint at the poses before, do not quite fit it at the new ones (a hinge's
// centre, carried round by the turn, has a little velocity across it, O(omega^2 r h)), and armature
// acts on the coordinate's rate there: weighing rotation over displacement (a displacement of 10 m
// counts as a radian) keeps a hinge's rate its turning rate, as a hinge joint's angle row has it.
constexpr double kRateMetric = 1e-2;

// The row whose J u is g . V (see the top of the file); arm2 = c - p2.
void weightRow(const Vec6& g, const Vec3& arm2, Row& row) {
  const Vec3 gw = g.head<3>(), gv = g.tail<3>();
  row.Ja << gv, gw;
  row.Jb << -gv, -(gw + arm2.cross(gv));
}

// Each 3-block of a basis turned by `turn`.
Held turned(const Held& basis, const Quat& turn) {
  const Mat3 r = turn.toRotationMatrix();
  Held out(6, basis.cols());
  out.topRows<3>() = r * basis.topRows<3>();
  out.bottomRows<3>() = r * basis.bottomRows<3>();
  return out;
}

}  // namespace

SerialJoint::SerialJoint(const JointDef& def, const BodyState& b1, const BodyState& b2)
    : Joint(def) {
  const Quat to1 = b1.pose.orientation.conjugate();
  for (const SerialAxis& a : def.axes)
    axes_.push_back(Axis{a.linear, to1 * a.axis.normalized(), b1.pose.toLocal(a.anchor)});
  rest_rotation_ = (b2.pose.orientation.conjugate() * b1.pose.orientation).normalized();
  rest_offset_ = b2.pose.toLocal(b1.pose.position);
  const auto k = static_cast<Eigen::Index>(axes_.size());
  last_ = JointCoordinates::Zero(k);

  // The axes must move body 1 in k independent ways; the held directions are what they leave.
  const Chain chain = chainAt(axes_, rest_rotation_, rest_offset_, last_, b2.pose);
  const Twists s = twistsAt(axes_, chain, b1.pose.position);
  for (Eigen::Index i = 1; i <= k; ++i) {
    const Eigen::JacobiSVD<Twists> svd(s.leftCols(i));
    const auto& sigma = svd.singularValues();
    if (sigma[i - 1] < 1e-9 * std::max(1.0, sigma[0]))
      throw std::invalid_argument(
          fmt::format("axes[{}]: adds no motion that the axes before it do not already allow "
                      "(the axes must be independent)",
                      i - 1));
  }
  const Eigen::JacobiSVD<Eigen::Matrix<double, Eigen::Dynamic, 6, 0, kMaxCoordinates, 6>> svd(
      s.transpose(), Eigen::ComputeFullV);
  held_ = turned(svd.matrixV().rightCols(6 - k), to1);
}

SerialJoint::Fit SerialJoint::fit(const BodyState& b1, const BodyState& b2) const {
  constexpr int kIterations = 30;
  constexpr double kStep = 0.5;  // (rad or m) per iteration at most: turns stay counted
  Fit f{last_, {}, Vec6::Zero()};
  for (int iteration = 0; iteration < kIterations; ++iteration) {
    const Chain chain = chainAt(axes_, rest_rotation_, rest_offset_, f.q, b2.pose);
    f.twists = twistsAt(axes_, chain, chain.end.position);
    f.residual << math::logMap(b1.pose.orientation * chain.end.orientation.conjugate()),
        b1.pose.position - chain.end.position;
    const auto rates = ratesOf(f.twists);
    double largest = 0.0;
    std::array<double, kMaxCoordinates> dq{};
    for (Eigen::Index i = 0; i < f.q.size(); ++i) {
      dq[static_cast<std::size_t>(i)] = rates.row(i).dot(f.residual);
      largest = std::max(largest, std::abs(dq[static_cast<std::size_t>(i)]));
    }
    if (largest < 1e-14 || iteration + 1 == kIterations) {
      f.twists = twistsAt(axes_, chain, b1.pose.position);
      break;
    }
    for (Eigen::Index i = 0; i < f.q.size(); ++i)
      f.q[i] += std::clamp(dq[static_cast<std::size_t>(i)], -kStep, kStep);
  }
  return f;
}

SerialJoint::Held SerialJoint::held(const Fit& fit, const BodyState& b1) const {
  const Held last = turned(held_, b1.pose.orientation);
  const Held a = last - fit.twists * (ratesOf(fit.twists) * last);
  return orthonormalized(a);
}

SerialJoint::Held SerialJoint::orthonormalized(const Held& a) {
  // The nearest orthonormal basis, a (a^T a)^-1/2 (the polar factor). The basis turned and
  // projected from the last step's is orthonormal to within the step's motion: Newton-Schulz,
  // y <- y (3 - y^T y) / 2, converges to it quadratically, for a few small products.
  const auto m = a.cols();
  Held y = a;
  for (int k = 0; k < 8; ++k) {
    const Gram e = y.transpose() * y - Gram::Identity(m, m);
    const double off = e.cwiseAbs().maxCoeff();
    if (off < 4e-15) return y;
    if (!(off < 0.5)) break;  // too far for the iteration: the eigen decomposition below
    y = y * (Gram::Identity(m, m) - 0.5 * e);
  }
  // Padded to 6 x 6 with the identity, which the inverse square root keeps apart.
  Eigen::Matrix<double, 6, 6> gram = Eigen::Matrix<double, 6, 6>::Identity();
  gram.topLeftCorner(m, m) = a.transpose() * a;
  const Eigen::Matrix<double, 6, 6> inverse_sqrt =
      Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, 6, 6>>(gram).operatorInverseSqrt();
  return a * inverse_sqrt.topLeftCorner(m, m);
}

JointCoordinates SerialJoint::coordinates(const BodyState& b1, const BodyState& b2) const {
  return fit(b1, b2).q;
}

void SerialJoint::track(const BodyState& b1, const BodyState& b2) {
  const Fit f = fit(b1, b2);
  held_ = turned(held(f, b1), b1.pose.orientation.conjugate());
  last_ = f.q;
}

void SerialJoint::persistTracked(state::Archive& a) {
  a(last_);
  a(held_);
}

int SerialJoint::fill(const JointContext& ctx, std::span<Row> rows) const {
  const Fit f = fit(ctx.b1, ctx.b2);
  const Held c = held(f, ctx.b1);
  const Vec3 arm2 = ctx.b1.pose.position - ctx.b2.pose.position;
  int n = 0;
  for (Eigen::Index j = 0; j < c.cols(); ++j, ++n) {
    Row& row = rows[static_cast<std::size_t>(n)];
    weightRow(c.col(j), arm2, row);
    row.phi = c.col(j).dot(f.residual);
    row.key = n;
  }
  const auto free = axes_.size();
  if (std::all_of(def().coordinates.begin(), def().coordinates.begin() + static_cast<long>(free),
                  [](const CoordinateDef& d) { return d.empty(); }))
    return n;
  const Rates rates = ratesOf(f.twists, kRateMetric);
  std::array<double, kMaxCoordinates> margins{};
  for (std::size_t i = 0; i < free; ++i)
    margins[i] = axes_[i].linear ? kLinearLimitMargin : kAngularLimitMargin;
  return freeCoordinateRows(
      ctx, def(), std::span<const double>(margins.data(), free),
      [&](std::size_t i, Row& row) {
        const auto index = static_cast<Eigen::Index>(i);
        weightRow(rates.row(index).transpose(), arm2, row);
        row.phi = f.q[index];
      },
      rows, n);
}

}  // namespace linx::joints
