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

#include <algorithm>
#include <cstdint>
#include <memory>
#include <span>
#include <utility>
#include <vector>

namespace linx::step {

/// Whether a joint row is a limit (of a coordinate, a ball's cone, a rope): phi is its gap, >= 0
/// where admissible, and J u the gap's rate.
inline bool isLimit(const Row& row) {
  return row.kind == RowKind::Unilateral;
}

/// Whether a joint row is a velocity row: a velocity motor's or joint friction's, a target rate
/// (its speed) held by a force within a bound (lo < hi; a coordinate force pins lo = hi).
inline bool isVelocityRow(const Row& row) {
  return row.kind == RowKind::Motor && row.lo < row.hi;
}

/// A velocity row's force bound (N or N m) from its impulse bound over the rows' assembly step.
double velocityBound(const Row& row);

/// The joint rows the accurate integrator switches as they stand (step/row_events): the limits
/// and velocity rows it holds as equalities, by key (sorted), and the direction (+1 or -1) in
/// which each velocity row it does not hold pushes with its bound (sorted by key).
struct Switches {
  std::span<const std::uint64_t> held;
  std::span<const std::pair<std::uint64_t, double>> pushing;

  bool holds(std::uint64_t key) const { return std::binary_search(held.begin(), held.end(), key); }
  /// The direction a velocity row not held pushes in: its listed one, else `otherwise`.
  double push(std::uint64_t key, double otherwise) const {
    const auto it = std::lower_bound(pushing.begin(), pushing.end(), std::pair{key, -kInfinity});
    return it != pushing.end() && it->first == key ? it->second : otherwise;
  }
};

/// Whether a joint row is one the accurate integrator holds: an equality of the bodies' poses
/// alone (not a motor, drive, a prescribed motion, nor a joint softened by its cfm), or a limit
/// or velocity row `switches` holds.
bool holdsExactly(const Row& row, const SolverSettings& settings, const Switches& switches = {});

/// Whether the accurate integrator can take a joint row: one it holds, or one it may switch (a
/// limit not softened by its joint's cfm, a velocity row: events of its steps).
inline bool mayHold(const Row& row, const SolverSettings& settings) {
  return holdsExactly(row, settings) || (isLimit(row) && row.cfm <= settings.cfm) ||
         isVelocityRow(row);
}

class ConstrainedDynamics {
 public:
  /// The accelerations of the bodies flagged in `moving` at their current state and `time`: their
  /// rates of linear and angular velocity (world frame) in `dv` and `dw` (one per body; the others
  /// are left alone), with the rows `switches` holds as equalities (a velocity row's at its
  /// target rate) and the velocity rows it does not hold at their bound. The joints' rows that act
  /// on moving bodies must join them only to moving or still bodies.
  void accelerations(std::span<const std::unique_ptr<Joint>> joints, std::span<const Body> bodies,
                     const WorldSettings& settings, std::span<const std::uint8_t> moving,
                     const Switches& switches, double time, int threads, std::span<Vec3> dv,
                     std::span<Vec3> dw);

  /// The rows of the last call (the joints' equality rows on moving bodies, the held rows among
  /// them as equalities, then the coordinate forces and the velocity rows' bounds) and their
  /// forces there (N or N m, positive along the row).
  std::span<const Row> rows() const { return rows_; }
  std::span<const double> forces() const { return lambda_; }
  /// The switched rows of the last call on moving bodies that are not held: the limits within
  /// their margin of their bound (or past it; phi is the gap), the velocity rows.
  std::span<const Row> openRows() const { return open_; }

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
  Switches switches_;
  std::vector<double> curvature_, closed_, lambda_, residual_;
  std::vector<double> target_rate_;  // per equality: a held velocity row's d(target)/dt, else 0
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

/// The joints' rows the accurate integrator holds (holdsExactly, those `switches` holds as
/// equalities) that act on moving bodies, at the bodies' current poses; `all` is scratch. With
/// `targets`: each row's target rate in the velocity projection, its speed for a velocity row
/// (which has no position), NaN for the others (their target is zero, and they hold a position).
void gatherEqualities(std::span<const std::unique_ptr<Joint>> joints, std::span<const Body> bodies,
                      const SolverSettings& settings, std::span<const std::uint8_t> moving,
                      const Switches& switches, double time, std::vector<Row>& all,
                      std::vector<Row>& out, std::vector<double>* targets = nullptr);

/// The speed of a row: J u with the bodies' velocities.
double rowSpeed(const Row& row, std::span<const Body> bodies);

}  // namespace linx::step
