// Reusable constraint parts that joints are built from. Each fills rows for bodies 1 (a) and 2 (b)
// with body 2 as the reference frame, so that every part writes C = (something of body 1) minus
// (the same of body 2), and dC/dt = J u:
//
//   point      C = (p1 + r1) - (p2 + r2)                      3 rows
//              J_k = [ e_k, r1 x e_k | -e_k, -(r2 x e_k) ]
//   lock       C = R2 log(q2^-1 q1 q0^-1)  (relative rotation since creation, world frame)
//              J_k = [ 0, e_k | 0, -e_k ]                       3 rows (exact at C = 0)
//   align      C_j = t_j . (a2 x a1), a_i the hinge axis fixed in body i, t_j _|_ a2 fixed in
//              body 2                J_j = [ 0, t_j | 0, -t_j ]   2 rows (exact at C = 0)
//   linear     C = n . d, d = (p1 + r1) - (p2 + r2), n fixed in body 2
//              J = [ n, r1 x n | -n, -(r2 + d) x n ]          1 row per direction, exact
//   angular    C = theta about a (twist of q2^-1 q1 q0^-1), J = [ 0, a | 0, -a ]
//
// Limits and motors act on a coordinate row (linear or angular) through limitRow and motorRow.
#pragma once

#include <linx/joint.hpp>
#include <linx/row.hpp>

#include <cmath>
#include <limits>

namespace linx::joints {

/// Joint geometry captured at creation, in each body's frame.
struct JointFrames {
  Vec3 anchor1 = Vec3::Zero();    ///< anchor in body 1's frame
  Vec3 anchor2 = Vec3::Zero();    ///< anchor in body 2's frame
  Vec3 axis1 = Vec3::UnitZ();     ///< unit axis in body 1's frame
  Vec3 axis2 = Vec3::UnitZ();     ///< unit axis in body 2's frame
  Vec3 tangent1 = Vec3::UnitX();  ///< unit, _|_ axis2, body 2's frame
  Vec3 tangent2 = Vec3::UnitY();  ///< axis2 x tangent1
  Quat rest = Quat::Identity();   ///< q2^-1 q1 at creation: relative orientation that reads zero

  /// The tangents in the world frame: they turn with body 2.
  void tangents(const BodyState& b2, Vec3& t1, Vec3& t2) const {
    t1 = b2.pose.orientation * tangent1;
    t2 = b2.pose.orientation * tangent2;
  }

  static JointFrames capture(const JointDef& def, const BodyState& b1, const BodyState& b2);
};

/// A cross (universal joint, hinge-2): arm a1 fixed in body 1 and arm a2 fixed in body 2, kept
/// perpendicular by one row,
///   C = a1 . a2,  J = [ 0, n | 0, -n ],  n = a1 x a2   (d/dt a1 . a2 = n . (w1 - w2)),
/// so that body 1 turns on the cross about a1 (angle1) and the cross turns in body 2 about a2
/// (angle2): w1 - w2 = angle1' a1 + angle2' a2.
struct Cross {
  Vec3 arm1 = Vec3::UnitZ();    ///< a1 in body 1's frame
  Vec3 arm2 = Vec3::UnitY();    ///< a2 in body 2's frame
  Vec3 start1 = Vec3::UnitY();  ///< a2 at creation, in body 1's frame
  Vec3 start2 = Vec3::UnitZ();  ///< a1 at creation, in body 2's frame

  /// From the world-frame arms at creation, perpendicular (joints::validate checks them).
  static Cross capture(const Vec3& a1, const Vec3& a2, const BodyState& b1, const BodyState& b2);
  Vec3 a1(const BodyState& b1) const { return b1.pose.orientation * arm1; }
  Vec3 a2(const BodyState& b2) const { return b2.pose.orientation * arm2; }
  void row(const BodyState& b1, const BodyState& b2, Row& row) const;
  /// The row's curvature (dJ/dt) u: n = a1 x a2 turns with both arms, (w1 x a1) x a2 + a1 x
  /// (w2 x a2), against w1 - w2.
  double curvature(const BodyState& b1, const BodyState& b2) const {
    const Vec3 u1 = a1(b1), u2 = a2(b2);
    return (b1.w.cross(u1).cross(u2) + u1.cross(b2.w.cross(u2))).dot(b1.w - b2.w);
  }
  /// (angle1, angle2) in (-pi, pi], zero at creation: each arm as the other body sees it,
  /// against where it was at creation (to be unwrapped).
  Eigen::Vector2d angles(const BodyState& b1, const BodyState& b2) const;
  /// Closed form of the cross row's stiffness for its impulse l: the torque l (a1 x a2) turns
  /// with both arms, d(a1 x a2) = [a2]x [a1]x dtheta1 - [a1]x [a2]x dtheta2.
  void addStiffness(const BodyState& b1, const BodyState& b2, double l, Mat12& k) const;
};

/// Two points, one on each body (distance and spring joints): the distance between them,
///   C = |d|, d = (p1 + r1) - (p2 + r2), n = d / |d|,  J = [ n, r1 x n | -n, -(r2 x n) ]
/// (d/dt |d| = n . d', exact).
struct PointPair {
  Vec3 point1 = Vec3::Zero();  ///< on body 1, its frame
  Vec3 point2 = Vec3::Zero();  ///< on body 2, its frame

  /// From JointDef::anchor and anchor2 (default: the bodies' centres of mass); throws
  /// std::invalid_argument naming `anchor2` unless they are apart at creation.
  static PointPair capture(const JointDef& def, const BodyState& b1, const BodyState& b2);
  double distance(const BodyState& b1, const BodyState& b2) const {
    return (b1.pose.toWorld(point1) - b2.pose.toWorld(point2)).norm();
  }
  /// The row of C (phi = |d|). Points that meet have no direction between them: any will do, C
  /// is at its extreme there.
  void row(const BodyState& b1, const BodyState& b2, Row& row) const;
  /// The row's curvature (dJ/dt) u: n turns as the points move across it, n' = (d' - n (n . d'))
  /// / |d|, and the lever arms turn with their bodies.
  double curvature(const BodyState& b1, const BodyState& b2) const;
};

/// World-frame lever arms (centre of mass to anchor) and anchor separation of the current state.
struct Arms {
  Vec3 r1, r2;
  Vec3 d;  ///< (p1 + r1) - (p2 + r2)
  static Arms of(const JointFrames& f, const BodyState& b1, const BodyState& b2);
};

/// Relative rotation of body 1 with respect to body 2 since creation, in body 2's frame.
Quat relativeRotation(const JointFrames& f, const BodyState& b1, const BodyState& b2);
/// The angle body 1 has turned relative to body 2 about the frames' axis since creation: the twist
/// of relativeRotation about it (right-hand rule), on the branch nearest `last` (counting turns).
double axisAngle(const JointFrames& f, const BodyState& b1, const BodyState& b2, double last);

void pointRows(const Arms& arms, std::span<Row, 3> rows);
/// Joint::curvature of a row whose curvature has no closed form here: measured by differences.
inline constexpr double kMeasuredCurvature = std::numeric_limits<double>::quiet_NaN();
/// out[k] = of(slot) for each of `rows`, slot its joint's local slot (Row::key's low byte).
template <class F>
void curvatureBySlot(std::span<const Row> rows, std::span<double> out, F&& of) {
  for (std::size_t k = 0; k < rows.size(); ++k) out[k] = of(static_cast<int>(rows[k].key & 0xff));
}
/// The curvature (dJ/dt) u of pointRows' three rows (the lever arms turn with their bodies):
/// w1 x (w1 x r1) - w2 x (w2 x r2), row k its component k.
Vec3 pointCurvature(const Arms& arms, const BodyState& b1, const BodyState& b2);
/// The curvature of a row J = [ 0, t | 0, -t ] whose direction t is fixed in body 2 (alignRows,
/// angularRow about a body-2 axis): (w2 x t) . (w1 - w2). A lock row's t is the world's: 0.
inline double turningCurvature(const Vec3& t, const BodyState& b1, const BodyState& b2) {
  return b2.w.cross(t).dot(b1.w - b2.w);
}
void lockRows(const JointFrames& f, const BodyState& b1, const BodyState& b2,
              std::span<Row, 3> rows);
void alignRows(const JointFrames& f, const BodyState& b1, const BodyState& b2,
               std::span<Row, 2> rows);
/// One linear row along the world direction n (fixed in body 2), C = n . d.
void linearRow(const Arms& arms, const Vec3& n, Row& row);
/// The curvature (dJ/dt) u of linearRow's row: n turns with body 2, the lever arms with their
/// bodies, and d moves at d' = v1 + w1 x r1 - v2 - w2 x r2.
double linearCurvature(const Arms& arms, const Vec3& n, const BodyState& b1, const BodyState& b2);
/// One angular row about the world axis a, C = theta.
void angularRow(const Vec3& a, double theta, Row& row);

/// Turns a coordinate row (J, phi = coordinate) into a limit row if the coordinate is within
/// `margin` of `bound` or past it, or will cross it within this step at its current rate; returns
/// whether it did. A gap still open is closed exactly in one step at most (speculative: such a row
/// never pushes before the bound is reached), an overshoot is removed at the row's erp.
/// The margin keeps the row while the coordinate rests on its bound: other rows (a motor) can
/// drive it within the solve, which the unconstrained rate does not show.
/// lower: coordinate >= bound; otherwise coordinate <= bound.
bool limitRow(const JointContext& ctx, double bound, bool lower, double margin, Row& row);
/// Margins of limitRow: within reach of a step, small against any useful range of motion.
inline constexpr double kLinearLimitMargin = 1e-3;   ///< (m)
inline constexpr double kAngularLimitMargin = 2e-2;  ///< (rad)
/// Turns a coordinate row into a velocity motor row: J u = target, |lambda| <= h max_force.
void motorRow(const JointContext& ctx, double target, double max_force, Row& row);

/// Turns a coordinate row (J, phi = coordinate) into the equality of a prescribed coordinate:
/// C = coordinate - target(t), its rate target'(t), the whole error removed in the step (erp 1),
/// so that a step ends on the target, and position correction (at the bodies' time) keeps it
/// there.
void prescribedRow(const JointContext& ctx, const Signal& target, Row& row);

/// Turns a coordinate row into a joint friction row: J u = 0, |lambda| <= h friction, softened by a
/// constraint force mixing of kFrictionSoftness of the row's own inverse mass. The row shares its
/// J with the coordinate's limit rows: at a limit both would hold the same rate, a singular pair
/// for the direct solvers; the softness makes the pair definite while the rate it lets through,
/// kFrictionSoftness of the change the friction impulse itself makes, is negligible.
void frictionRow(const JointContext& ctx, double friction, Row& row);
inline constexpr double kFrictionSoftness = 1e-6;
/// J M^-1 J^T of one row: the inverse of the mass that the row's direction alone moves.
double inverseMassAlong(const Row& row, const BodyInertia& m1, const BodyInertia& m2);
/// The smallest implicit share of a spring (see implicitShare).
inline constexpr double kMinImplicitShare = 1e-4;
/// How much of a spring's force is taken at the end of the step: the force is -k (x + beta h x'+),
/// x' integrated to x by the step's symplectic Euler. beta = 0 is symplectic Euler: no numerical
/// damping, stable while h omega < 2 (omega^2 = k / m, m the row's own mass, `1 / inverse_mass`);
/// beta = 1 is implicit Euler: stable at any stiffness, the stiff limit settles in a step (what a
/// servo wants), but it damps (18 % of the amplitude a period at 100 steps a period).
/// Taken is 1 - 1 / (h omega)^2, at least kMinImplicitShare: none while h omega <= 1, then
/// (h omega)^2 (1 - 2 beta) = 2 - (h omega)^2 < 4 (stable; the row's own mass is the lightest the
/// body can move with, so the real omega is lower), tending to implicit Euler as k grows.
double implicitShare(double stiffness, double inverse_mass, double h);
/// Turns a coordinate row (J, phi = coordinate minus its target at the step's start) into a drive
/// row: the impulse is h F with F = -stiffness phi + (damping + beta h stiffness) (target_rate -
/// J u+), bounded by |F| <= max_force (docs/joints.md).
void driveRow(const JointContext& ctx, double stiffness, double damping, double target_rate,
              double max_force, Row& row);

/// Turns a coordinate row into the armature A of a coordinate (CoordinateDef::armature): a damper
/// of A / h towards the rate at the step's start (JointContext::start: before gravity and applied
/// forces, which do not act on the rotor), so that its impulse A (x'0 - x'+) is the rotor's change
/// of momentum: implicit, the coordinate moves as if A were added to its inertia.
void armatureRow(const JointContext& ctx, double armature, Row& row);

/// Turns a coordinate row into a given force F along the coordinate (CoordinateDef::force): its
/// impulse is h F, whatever the rest of the solve does (lo = hi = h F).
void forceRow(const JointContext& ctx, double force, Row& row);

/// Row slot of part `part` (0 lower limit, 1 upper limit, 2 motor, 3 spring, 4 friction, 5 lock,
/// 6 prescribed, 7 armature, 8 force)
/// of free coordinate `index`: after every joint's equality rows (slots below 16).
constexpr int coordinateSlot(int index, int part) {
  return 16 + 16 * index + part;
}
/// The sign of a coordinate's row (slot >= 16) against the coordinate's own: -1 for the upper
/// limit's (coordinate <= bound is taken as -coordinate >= -bound, limitRow), +1 for the others.
/// A coordinate row's curvature is the coordinate's times it.
constexpr double coordinateRowSign(int slot) {
  return slot >= 16 && (slot - 16) % 16 == 1 ? -1.0 : 1.0;
}
/// Whether a row's slot (its key's low byte) is a prescribed coordinate's (part 6).
constexpr bool isPrescribedSlot(int slot) {
  return slot >= 16 && (slot - 16) % 16 == 6;
}
/// Rows a free coordinate may add: two limits, a motor, a spring, friction, armature, a force.
inline constexpr int kCoordinateRows = 7;

/// Appends the limit rows (only those reached), the motor row, the spring row and the friction row
/// of free coordinate `index` (as `c` defines them) to rows[n...]; `coordinateRow(row)` fills a
/// row with the coordinate's J and phi. Writes at most kCoordinateRows rows; returns the new count.
template <class CoordinateRow>
int coordinateRows(const JointContext& ctx, const CoordinateDef& c, int index, double margin,
                   CoordinateRow&& coordinateRow, std::span<Row> rows, int n) {
  // The coordinate counts from its reference; a lock holds it where it was made.
  const auto next = [&](int part) -> Row& {
    Row& row = rows[static_cast<std::size_t>(n)];
    coordinateRow(row);
    if (part != 5) row.phi += c.reference;
    row.key = coordinateSlot(index, part);
    return row;
  };
  if (c.locked) {  // C = the coordinate, zero at creation: an equality row
    Row& row = next(5);
    row.kind = RowKind::Bilateral;
    row.lo = -kInfinity;
    row.hi = kInfinity;
    return n + 1;
  }
  if (c.prescribed) {
    prescribedRow(ctx, *c.prescribed, next(6));
    return n + 1;
  }
  if (c.limits) {
    for (const bool lower : {true, false}) {
      Row& row = next(lower ? 0 : 1);
      if (limitRow(ctx, lower ? c.limits->lower : c.limits->upper, lower, margin, row)) ++n;
    }
  }
  if (c.motor) {
    const JointMotor& motor = *c.motor;
    Row& row = next(2);
    if (motor.isServo()) {
      const Signal* position = motor.target_position ? &*motor.target_position : nullptr;
      // The position target at the step's start (where phi is), the rate over the step.
      row.phi = position ? row.phi - position->at(ctx.time) : 0.0;
      const double rate =
          motor.target_velocity.at(ctx.time + ctx.h) + (position ? position->rate(ctx.time) : 0.0);
      driveRow(ctx, position ? motor.stiffness : 0.0, motor.damping, rate, motor.max_force, row);
    } else {
      motorRow(ctx, motor.target_velocity.at(ctx.time + ctx.h), motor.max_force, row);
    }
    ++n;
  }
  if (c.spring && (c.spring->stiffness > 0.0 || c.spring->damping > 0.0)) {
    Row& row = next(3);
    row.phi -= c.spring->rest;
    driveRow(ctx, c.spring->stiffness, c.spring->damping, 0.0, kInfinity, row);
    ++n;
  }
  if (c.friction > 0.0) {
    frictionRow(ctx, c.friction, next(4));
    ++n;
  }
  if (c.armature > 0.0) {
    armatureRow(ctx, c.armature, next(7));
    ++n;
  }
  if (c.force) {  // over the step, taken at its middle
    forceRow(ctx, c.force->at(ctx.time + 0.5 * ctx.h), next(8));
    ++n;
  }
  return n;
}

/// coordinateRows for each of a joint's free coordinates: `coordinateRow(i, row)` fills a row with
/// coordinate i's J and phi, `margins[i]` is its limit margin. Skips coordinates with nothing on
/// them (their value is not even computed).
template <class CoordinateRow>
int freeCoordinateRows(const JointContext& ctx, const JointDef& def,
                       std::span<const double> margins, CoordinateRow&& coordinateRow,
                       std::span<Row> rows, int n) {
  for (std::size_t i = 0; i < margins.size(); ++i) {
    const CoordinateDef& c = def.coordinates[i];
    if (c.empty()) continue;
    n = coordinateRows(
        ctx, c, static_cast<int>(i), margins[i], [&](Row& row) { coordinateRow(i, row); }, rows, n);
  }
  return n;
}

/// Closed forms of Joint::stiffness for the parts above, added to k.
/// Point rows with impulse vector l = sum lambda_k e_k: the torques r1 x l and -(r2 x l) turn
/// with the arms, K(rot 1, rot 1) += [l]x [r1]x and K(rot 2, rot 2) -= [l]x [r2]x.
void addPointStiffness(const Arms& arms, const Vec3& impulse, Mat12& k);
/// The impulse vector l of a joint's point rows (slots 0-2, as pointRows writes them).
Vec3 pointImpulse(std::span<const Row> rows, std::span<const double> lambda);
/// Rows [0, a | 0, -a] with a fixed in body 2 (align, angular, their limits and motors), torque
/// tau = sum lambda a: tau and -tau turn with body 2, K(rot 1, rot 2) -= [tau]x and
/// K(rot 2, rot 2) += [tau]x. (Lock rows' axes are the world's: they do not turn.)
void addBody2AxisStiffness(const Vec3& torque, Mat12& k);
/// The same for rows whose axis a is fixed in body 1: K(rot 1, rot 1) -= [tau]x and
/// K(rot 2, rot 1) += [tau]x.
void addBody1AxisStiffness(const Vec3& torque, Mat12& k);

/// The angle equal to `raw` modulo a turn that is nearest `last`: an angle that counts turns.
inline double unwrap(double raw, double last) {
  constexpr double kTurn = 2.0 * 3.14159265358979323846;
  return raw + kTurn * std::round((last - raw) / kTurn);
}

/// Rate J u of a row for the given body states.
double rowRate(const Row& row, const BodyState& b1, const BodyState& b2);

}  // namespace linx::joints
