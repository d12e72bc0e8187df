// The accelerations of bodies held by joints: the index-1 equations of motion of the accurate
// integrator (docs/integrators.md),
//   M a - J^T lambda = f(x, u),   J a = -(dJ/dt) u,
// with f gravity, the applied loads, the bodies' damping and the gyroscopic term -w x (I w), and
// lambda the joints' forces. They are the velocity solve's problem with the unconstrained
// accelerations in place of u*: the exact solver finds lambda (O(n) along the tree for mechanisms
// without loops; redundant rows, as in a planar loop of hinges, by its regularized LDL^T).
// The rows' curvature (dJ/dt) u is measured by a central difference of the rows along the bodies'
// velocities, over a time short enough that the difference is exact to about 1e-10 of it.
#pragma once

#include <linx/body.hpp>
#include <linx/joint.hpp>
#include <linx/row.hpp>
#include <linx/world.hpp>

#include "solver/dense_equalities.hpp"
#include "solver/exact_solver.hpp"
#include "solver/problem.hpp"

#include <cstdint>
#include <memory>
#include <span>
#include <vector>

namespace linx::step {

/// The keys of the joint limits (unilateral joint rows) the accurate integrator holds as
/// equalities at the time (step/limit_events), sorted.
using HeldLimits = std::span<const std::uint64_t>;

/// Whether a joint row is one the accurate integrator holds: an equality of the bodies' poses
/// alone (not a motor, drive, a prescribed motion, nor a joint softened by its cfm), or a limit
/// `held` names.
bool holdsExactly(const Row& row, const SolverSettings& settings, HeldLimits held = {});

/// Whether a joint row is a limit (of a coordinate, a ball's cone, a rope): phi is its gap, >= 0
/// where admissible, and J u the gap's rate.
inline bool isLimit(const Row& row) {
  return row.kind == RowKind::Unilateral;
}

/// Whether the accurate integrator can take a joint row: one it holds, or a limit (not softened by
/// its joint's cfm) it may hold.
inline bool mayHold(const Row& row, const SolverSettings& settings) {
  return holdsExactly(row, settings) || (isLimit(row) && row.cfm <= settings.cfm);
}

class ConstrainedDynamics {
 public:
  /// The accelerations of the bodies flagged in `moving` at their current state and `time`: their
  /// rates of linear and angular velocity (world frame) in `dv` and `dw` (one per body; the others
  /// are left alone), with the limits in `held` as equalities. The joints' rows that act on moving
  /// bodies must join them only to moving or still bodies.
  void accelerations(std::span<const std::unique_ptr<Joint>> joints, std::span<const Body> bodies,
                     const WorldSettings& settings, std::span<const std::uint8_t> moving,
                     HeldLimits held, double time, int threads, std::span<Vec3> dv,
                     std::span<Vec3> dw);

  /// The rows of the last call (the joints' equality rows on moving bodies, the held limits among
  /// them as equalities, then the coordinate forces) and their forces there (N or N m, positive
  /// along the row).
  std::span<const Row> rows() const { return rows_; }
  std::span<const double> forces() const { return lambda_; }
  /// The limits of the last call on moving bodies that are not held and within their margin of
  /// their bound (or past it): phi is the gap.
  std::span<const Row> openLimits() const { return open_; }

 private:
  /// The joints' rows on moving bodies at the bodies' current state, into rows_: the equalities
  /// (with their curvature in curvature_), then the coordinate forces and the drives' forces as
  /// coordinate forces (lo = hi = the force).
  void gather(std::span<const std::unique_ptr<Joint>> joints, std::span<const Body> bodies,
              const SolverSettings& settings, std::span<const std::uint8_t> moving, double time);
  /// The (dJ/dt) u of joint `ji`'s rows `rows` (filled from `ctx`) that hold exactly, appended to
  /// curvature_: in closed form where the joint type has it (Joint::curvature), else by the
  /// joint's rows filled again with its moving bodies moved by -eps and +eps along their
  /// velocities.
  void measureCurvature(std::span<const std::unique_ptr<Joint>> joints, std::size_t ji,
                        std::span<const Body> bodies, const SolverSettings& settings,
                        std::span<const std::uint8_t> moving, const JointContext& ctx,
                        std::span<const Row> rows, double eps);
  /// After the regularized solve of the first `equalities` rows: one step of iterated
  /// regularization, which takes back the regularization's error on well-conditioned rows.
  void refine(std::size_t equalities);

  std::vector<Row> rows_, forces_, open_, slots_, before_, after_;
  HeldLimits held_;
  std::vector<double> curvature_, closed_, lambda_, residual_;
  std::vector<solver::SolverBody> solver_bodies_;
  solver::ExactSolver solver_;
  solver::DenseEqualities dense_solver_;
  bool dense_ = false;  // the last solve was dense_solver_'s
};

/// Whether the accurate integrator applies a joint row as a force: a coordinate force
/// (Joint::setForce, "force"), a spring on a coordinate, or a position servo or damped motor (a
/// drive), the last two by their law F = -k phi - c (J u - speed), bounded by the drive's
/// max_force. (Velocity motors, friction and armature are constraints: their islands take the
/// step.)
bool actsAsForce(const Row& row, std::span<const std::unique_ptr<Joint>> joints);

/// Whether a row acts on a body flagged in `moving` and on no other dynamic or kinematic body.
bool actsOnMoving(const Row& row, std::span<const std::uint8_t> moving);

/// The joints' rows the accurate integrator holds (holdsExactly, the limits in `held` as
/// equalities) that act on moving bodies, at the bodies' current poses; `all` is scratch.
void gatherEqualities(std::span<const std::unique_ptr<Joint>> joints, std::span<const Body> bodies,
                      const SolverSettings& settings, std::span<const std::uint8_t> moving,
                      HeldLimits held, double time, std::vector<Row>& all, std::vector<Row>& out);

/// The speed of a row: J u with the bodies' velocities.
double rowSpeed(const Row& row, std::span<const Body> bodies);

}  // namespace linx::step
