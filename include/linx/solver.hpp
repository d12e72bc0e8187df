// Solver choice and settings, and what a step reports about its solve.
#pragma once

#include <string_view>

namespace linx {

enum class SolverType {
  Auto,   ///< per island: Exact without friction rows (mechanisms), Pgs with them (contacts)
  Exact,  ///< sparse factorization + active set: joints to round-off, closed loops included
  Pgs,    ///< projected Gauss-Seidel with warm starting
  /// The soft step (docs/solver.md): rows prepared once per step, then `substeps` substeps of
  /// one soft sweep and one relax sweep each, positions integrated in between.
  Soft,
};

struct SolverSettings {
  SolverType type = SolverType::Auto;
  int iterations = 100;      ///< PGS sweeps / exact active-set iterations, at most
  double tolerance = 1e-10;  ///< stop when the largest complementarity violation is below (m/s)
  double erp = 0.2;          ///< error reduction per step, [0, 1]
  double cfm = 1e-10;        ///< constraint force mixing, >= 0
  bool warm_start = true;    ///< start from the previous step's impulses (matched by row key)
  double sor = 1.0;          ///< PGS over-relaxation, (0, 2)
  /// Each step split into this many assemble-solve-integrate passes; with type Soft, the
  /// substeps of the soft step (the rows are prepared once per step).
  int substeps = 1;
  /// Newton iterations per step, at most, that close the joints after the positions move, the
  /// joints' rows aiming at their constraint to second order (every solver; docs/solver.md,
  /// "Post-stabilization"); 0 turns both off (error reduction alone).
  int post_stabilization = 4;
  bool projection = false;        ///< the older name: at least projection_iterations of the above
  int projection_iterations = 3;  ///< iterations with projection on
  double projection_tolerance = 1e-12;  ///< stop the iterations below this error (m or rad)
  /// The joints' geometric stiffness in the velocity solve (docs/solver.md): the turning of their
  /// last forces, lumped onto the bodies' masses, keeps chains with heavy bodies stable.
  bool geometric_stiffness = true;
};

/// Figures of the last step's solve (the last substep's when substepping).
struct SolverReport {
  int rows = 0;            ///< rows assembled
  int iterations = 0;      ///< PGS sweeps, or active-set iterations of the exact solver
  double residual = 0.0;   ///< largest complementarity violation, |w| on free rows (m/s, rad/s)
  int redundant_rows = 0;  ///< exact solver: rows found linearly dependent (over-constrained)
  bool converged = true;   ///< met the tolerance within the iteration cap
};

std::string_view solverTypeName(SolverType type);

/// Error reduction and constraint force mixing that make a row a spring-damper.
struct SoftRow {
  double erp = 0.0;
  double cfm = 0.0;
};

/// The erp and cfm under which a row acts as a spring of stiffness k (N/m or N m/rad) with a
/// damper c (N s/m or N m s/rad) at step h (s): erp = h k / (h k + c), cfm = 1 / (h (h k + c)).
/// (linx's rows carry impulses, hence the 1/h on cfm against the force-level form.)
SoftRow springDamper(double stiffness, double damping, double h);

}  // namespace linx
