// The accurate integrator's projection onto the joints' manifold after each of its steps
// (docs/integrators.md): the Runge-Kutta step leaves the positions off the constraints by its
// local error, and the index-1 equations do not pull them back. Newton iterations move the bodies
// by the displacement of least kinetic metric that closes the errors to first order,
//   dx = M^-1 J^T dl,   (J M^-1 J^T) dl = -phi,
// and the velocities then lose their component off the manifold's tangent in the same metric,
//   u+ = u + M^-1 J^T l,   (J M^-1 J^T) l = -J u,
// both solved dense for a few bodies (solver/dense_equalities) and otherwise, or when rows are
// redundant, by the exact solver. Both corrections are of the size of
// the step's local error, which the step's control keeps below its tolerance.
#pragma once

#include <linx/body.hpp>
#include <linx/joint.hpp>
#include <linx/row.hpp>
#include <linx/solver.hpp>

#include "solver/dense_equalities.hpp"
#include "solver/exact_solver.hpp"
#include "solver/problem.hpp"
#include "step/constrained_dynamics.hpp"

#include <cstdint>
#include <memory>
#include <span>
#include <vector>

namespace linx::step {

class ManifoldProjection {
 public:
  /// Projects the poses, then the velocities, of the bodies flagged in `moving` onto the joints'
  /// equality manifold at `time`, the rows `switches` holds among the equalities: at most
  /// `iterations` Newton iterations, stopping once every error is below `tolerance` (m or rad).
  /// Returns the largest error left (measured before the last iteration's correction when the
  /// iterations ran out). A held limit that was closing loses its closing rate (a plastic impact);
  /// a held velocity row (which holds no position) takes its target rate.
  double project(std::span<const std::unique_ptr<Joint>> joints, std::span<Body> bodies,
                 const SolverSettings& settings, std::span<const std::uint8_t> moving,
                 const Switches& switches, double time, int iterations, double tolerance,
                 int threads);

 private:
  /// Solves (J M^-1 J^T) l = target - J u* for the rows, with u* the solver bodies' velocities,
  /// which become u* + M^-1 J^T l.
  void solve(const SolverSettings& settings, int threads);

  std::vector<Row> all_, gathered_, rows_;
  std::vector<double> targets_, lambda_;
  std::vector<solver::SolverBody> solver_bodies_;
  solver::ExactSolver solver_;
  solver::DenseEqualities dense_;
};

}  // namespace linx::step
