// One velocity-level constraint row: the unit every joint, limit, motor and contact is made of.
//
// A row couples two bodies a and b (DESIGN.md section 3):
//   J = [ Ja (1x6) | Jb (1x6) ],  each block (linear part, angular part), world frame;
// a coupling of two joints (a mimic joint) adds the other joint's bodies c and d: [ Jc | Jd ].
// It holds J u+ = xi with the impulse lambda bounded by lo <= lambda <= hi, where
//   xi = speed - (erp / h) phi
// phi is the row's position error C (the constraint function whose time derivative is J u) and
// speed a target velocity (a motor's). Bilateral rows have infinite bounds, unilateral rows
// lo = 0; a friction row takes its bounds from another row's impulse: |lambda| <= mu lambda_n.
#pragma once

#include <linx/types.hpp>

#include <cstdint>

namespace linx {

enum class RowKind : std::uint8_t {
  Bilateral,   ///< an equality (joint)
  Unilateral,  ///< a one-sided inequality (limit, contact normal): takes part in projection
  Motor,       ///< a velocity target with a force bound: no position error
  Friction,    ///< bounded by mu times the impulse of the row `normal`
  /// A spring-damper or servo on a joint coordinate: phi, erp and cfm make its force, which is
  /// physics, not drift (no post-stabilization); the soft step keeps its impulse in the relax pass.
  Drive,
};

struct Row {
  Vec6 Ja = Vec6::Zero();  ///< body a block (linear, angular)
  Vec6 Jb = Vec6::Zero();  ///< body b block (linear, angular)
  double phi = 0.0;        ///< position error C (m or rad)
  double speed = 0.0;      ///< target velocity (m/s or rad/s)
  double lo = -kInfinity;  ///< impulse bounds (N s or N m s)
  double hi = kInfinity;
  double erp = 0.2;  ///< error reduction: fraction of phi removed per step, [0, 1]
  double cfm = 0.0;  ///< constraint force mixing (regularization), >= 0
  RowKind kind = RowKind::Bilateral;
  int normal = -1;  ///< friction rows: index of the normal row within the same owner
  double mu = 0.0;  ///< friction rows: coefficient
  /// Identity across steps, for warm starting: a joint sets its local slot (0..255; slot i
  /// always means the same constraint), assembly adds the owner's identity.
  std::uint64_t key = 0;
  int body_a = -1, body_b = -1;  ///< solver body indices (set by assembly), -1 for none
  /// A coupling's further bodies (Joint::coupledBodies): blocks and solver indices, -1 for none.
  /// Assembly folds a block whose body is a or b into that body's block, so the four bodies of a
  /// row are distinct. Contacts and the joints of two bodies leave them unused.
  Vec6 Jc = Vec6::Zero(), Jd = Vec6::Zero();
  int body_c = -1, body_d = -1;

  bool coupled() const { return body_c >= 0 || body_d >= 0; }
  /// f(body, J block) for each body the row acts on (body -1: none, the world or a static body).
  template <class F>
  void forEachBlock(F&& f) const {
    f(body_a, Ja);
    f(body_b, Jb);
    if (body_c >= 0) f(body_c, Jc);
    if (body_d >= 0) f(body_d, Jd);
  }

  /// The target of J u+ for a step of length h.
  double target(double h) const { return speed - (erp / h) * phi; }
};

}  // namespace linx
