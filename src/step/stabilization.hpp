// Post-stabilization of the joints (Cline & Pai 2003, "Post-stabilization for rigid body
// simulation with contact and constraints"). A velocity-level step leaves each joint a position
// error phi of second order in h: the rows hold J u = 0 at the poses the step began from, and the
// bodies then move along arcs. After the positions move, Newton iterations remove it: each
// assembles the joints' rows at the current poses and moves the bodies by the displacement of
// least kinetic metric that closes the error to first order,
//   dx = M^-1 J^T dl,   (J M^-1 J^T) dl = -phi
// (equality rows, and motors held where they are; not rows made soft by a cfm above the world's),
// solved by the exact solver: O(n) along the tree for mechanisms without loops. An iteration after
// one that cut the error 100-fold or more, with the last factorization made for an error below
// 1e-3, does not factor: the bodies moved little since, so that factorization and its J serve, and
// the iteration is a back-substitution. Where links turn fast, or contacts pushed the bodies apart
// (ragdolls: 8 cm), the iterations stay Newton's. Limits are left to the velocity solve: brought
// onto their bounds here they came and went from one iteration to the next, and the iterations did
// not converge.
//
// Projection alone would cost energy: the next step's velocity solve cuts the velocity back onto
// the new tangent, a loss of (h w)^2 of the energy per step (a pendulum at h = 1 ms lost 2.5 % a
// second). So the velocity solve aims at the manifold to second order instead: each equality row's
// target speed takes the constraint's curvature along the step (addCurvature), the step ends on
// the constraint to O(h^3), and the next velocity solve mirrors the velocity about the new tangent
// instead of cutting it (the pendulum keeps its period to 1e-6). The projection then only removes
// the third-order rest.
//
// Why not the step's own factorization (J at the poses the step began from), as Cline & Pai
// suggest: each back-solve is then one quasi-Newton iteration whose error falls by about h times
// the bodies' angular speed, and the benchmark's falling chains whip their links at 0.4 rad a
// step: the iterations stalled at 2e-4 m, and the 100-link chain went unstable.
#pragma once

#include <linx/body.hpp>
#include <linx/joint.hpp>
#include <linx/row.hpp>
#include <linx/solver.hpp>

#include "solver/exact_solver.hpp"
#include "solver/problem.hpp"
#include "step/geometric_stiffness.hpp"

#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

namespace linx::state {
class Archive;
}

namespace linx::step {

class PostStabilization {
 public:
  /// The curvature of the joints' constraints along the step: each equality row's target speed is
  /// lowered by half the change of its normal since the remembered rows (the last pass's, or the
  /// last substep's, at the poses the bodies moved from) times the bodies' current velocities,
  ///   g / 2 = (J(x) - J(x - h u)) u / 2  (= h/2 u^T (d2 phi/dx2) u + O(h^2)),
  /// the centripetal term of a pendulum. It is measured on the motion the bodies made rather than
  /// predicted by assembling the rows ahead at x + h u: the prediction, at the velocities before
  /// the solve, fed energy into the benchmark's 100-link chain, which whips its links at 0.4 rad a
  /// step, until it blew up. Rows are matched by key; `remember`: keep these rows for the next
  /// call. With `stiffness`, rows of stiffened bodies take a share of it (see the definition).
  void addCurvature(std::span<const Body> bodies, std::span<Row> rows, bool remember,
                    const GeometricStiffness* stiffness = nullptr);
  /// Forgets the remembered rows unless they are the last step's and no body was moved by hand
  /// since its endStep.
  void beginStep(std::span<const Body> bodies);
  /// Records the bodies' poses at the end of a step.
  void endStep(std::span<const Body> bodies);
  /// Forgets the remembered rows of joint `joint` (keys (joint + 1) << 8 | slot): a removed
  /// joint's slot, whose next joint's rows must not be measured against them.
  void forget(std::size_t joint);

  /// Runs at most `iterations` Newton iterations, stopping once every error is below
  /// `settings.projection_tolerance`. Bodies flagged in `frozen` (sleeping ones) are held where
  /// they are, as if static. The metric is the velocity solve's, the bodies' masses with their
  /// geometric stiffness. `time` is the bodies' (a prescribed coordinate's target is taken
  /// there). Returns the largest error measured (m or rad), before the last correction.
  double run(std::span<const std::unique_ptr<Joint>> joints, std::span<Body> bodies,
             const SolverSettings& settings, int iterations, std::span<const std::uint8_t> frozen,
             const GeometricStiffness& stiffness, double time);

  /// Reads or writes what carries to the next step (World::saveState).
  void persist(state::Archive& archive);

 private:
  /// The rows that carry a position error at the current poses, each made to remove all of it
  /// (erp = 1 over a unit time). Returns the largest error.
  double gather(std::span<const std::unique_ptr<Joint>> joints, std::span<const Body> bodies,
                const SolverSettings& settings, std::span<const std::uint8_t> frozen, double time);

  /// lambda_ = -phi of rows_ laid out on factored_'s rows (the last factorization's), 0 on those
  /// rows_ lacks. False when rows_ has a row factored_ lacks (a body fell asleep or woke).
  bool errorsOnFactoredRows();
  /// Moves the bodies by dx = M^-1 J^T dl, with factored_'s J and bodies_' inverse masses.
  template <typename Still>
  void displace(std::span<Body> bodies, std::span<const double> dl, const Still& still);

  std::vector<Row> rows_, factored_, previous_;
  std::vector<Vec6> dx_;
  std::vector<Pose> poses_;
  int ends_since_remembered_ = 0;  // endStep calls since previous_ was remembered
  std::vector<double> lambda_;
  std::vector<solver::SolverBody> bodies_;
  solver::ExactSolver solver_;
};

}  // namespace linx::step
