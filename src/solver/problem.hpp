// What a constraint solver works on: the rows of one step and a compact state of the bodies
// (gathered once per step, apart from the rich Body objects).
#pragma once

#include <linx/row.hpp>
#include <linx/solver.hpp>

#include <memory>
#include <span>
#include <vector>

namespace linx::solver {

/// Compact solver state of one body: inverse mass, world inverse inertia, velocity.
struct SolverBody {
  double inv_mass = 0.0;
  Mat3 inv_inertia = Mat3::Zero();
  Vec3 v = Vec3::Zero();
  Vec3 w = Vec3::Zero();
};

/// The boxed mixed LCP of one step (DESIGN.md section 3):
///   w = A lambda + b,  A = J M^-1 J^T + diag(cfm),  b = J u* - xi,  lo <= lambda <= hi.
/// On entry the bodies hold u* and lambda an initial guess; on exit the bodies hold
/// u+ = u* + M^-1 J^T lambda and lambda the solution.
struct Problem {
  std::span<const Row> rows;
  std::span<SolverBody> bodies;
  std::span<double> lambda;
  double h = 0.0;
  int threads = 1;  ///< worker threads the solver may use; results do not depend on it
};

/// A solver keeps only work buffers between calls; its settings come with each solve.
class ConstraintSolver {
 public:
  virtual ~ConstraintSolver() = default;
  virtual SolverReport solve(Problem& problem, const SolverSettings& settings) = 0;
  /// A new solver of the same kind, with empty buffers (threads solving islands side by side
  /// each use their own).
  virtual std::unique_ptr<ConstraintSolver> another() const = 0;
};

/// A solver of the given type.
std::unique_ptr<ConstraintSolver> makeSolver(SolverType type);

}  // namespace linx::solver
