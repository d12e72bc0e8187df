// The joints of the soft step, solved exactly inside each substep (issue 15, part 3): the contacts
// iterate, the joints do not. In every substep the joints' rows are assembled at the bodies'
// current poses, warm-started with the last substep's impulses, and after each sweep over the
// contacts re-solved by the exact solver (in O(n) along the tree for mechanisms without loops), so
// that the velocities leave every joint row satisfied whatever contact row was solved last. The
// solve is incremental: it finds the change dl of the joint impulses for the current velocities,
//   (J M^-1 J^T) dl = -(J v - xi),  lo - l <= dl <= hi - l,
// with xi = speed - (erp / h) phi in the sweep with bias and xi = speed in the relax sweep.
#pragma once

#include <linx/body.hpp>
#include <linx/joint.hpp>
#include <linx/row.hpp>
#include <linx/solver.hpp>

#include "solver/exact_solver.hpp"
#include "solver/soft_solver.hpp"
#include "step/assembly.hpp"
#include "step/joint_warm_start.hpp"
#include "step/stabilization.hpp"

#include <cstdint>
#include <memory>
#include <span>
#include <vector>

namespace linx::step {

class SubstepJoints {
 public:
  /// Assembles the joints' rows at the bodies' current poses for a substep h, keeps the rows that
  /// move a body flagged in `moving`, and loads their impulses from `warm` (the last substep's).
  /// With post-stabilization on, the rows aim at their manifold to second order: they take their
  /// curvature along the substep (PostStabilization::addCurvature); `start`: the substep's first
  /// prepare (before the positions move), whose rows the next substep measures its curvature from.
  void prepare(std::span<const std::unique_ptr<Joint>> joints, std::span<const Body> bodies,
               const SolverSettings& settings, double h, double time,
               std::span<const std::uint8_t> moving, JointWarmStart& warm, PostStabilization& post,
               bool start, std::span<const StartVelocity> start_velocities);
  bool empty() const { return rows_.empty(); }
  /// Applies the impulses to the velocities.
  void warmStart(std::span<solver::SoftSolver::Body> bodies) const;
  /// Solves the rows exactly for the bodies' current velocities, with the position bias or
  /// without it, and adds the change to the impulses. Returns the solve's report.
  SolverReport solve(std::span<solver::SoftSolver::Body> bodies, bool bias,
                     const SolverSettings& settings, double h, int threads);
  /// Keeps the impulses for the next substep's (or step's) load.
  void store(JointWarmStart& warm) const { warm.store(rows_, lambda_); }
  std::span<const Row> rows() const { return rows_; }
  /// The rows' impulses of the last solve (the substep's whole impulses).
  std::span<const double> impulses() const { return lambda_; }

 private:
  void apply(std::span<solver::SoftSolver::Body> bodies, std::span<const double> impulses) const;

  std::vector<Row> all_, rows_, shifted_;
  std::vector<double> lambda_, delta_;
  std::vector<solver::SolverBody> gathered_;
  solver::ExactSolver exact_;
};

}  // namespace linx::step
