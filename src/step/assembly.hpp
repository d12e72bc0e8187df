// Constraint assembly in four moves: count (each joint's maximum), allocate, fill (each joint its
// own rows, from the bodies' current state), verify (finite rows). The result is one list of rows:
// the global block-sparse Jacobian with its bias, bounds and cfm.
#pragma once

#include <linx/body.hpp>
#include <linx/joint.hpp>
#include <linx/solver.hpp>

#include <memory>
#include <span>
#include <vector>

namespace linx::step {

/// A joint's state of a body: identity and zero velocity for the world frame.
BodyState stateOf(std::span<const Body> bodies, BodyId id);

/// A body's velocities at a (sub)step's start, before gravity and applied forces
/// (JointContext::start).
struct StartVelocity {
  Vec3 v = Vec3::Zero();
  Vec3 w = Vec3::Zero();
};
/// Each body's velocities now (the step keeps them before it integrates the forces).
void keepStartVelocities(std::span<const Body> bodies, std::vector<StartVelocity>& start);
/// What joint `j` fills its rows from for a step of length h starting at `time`: its bodies' states
/// and inertia, its error reduction and cfm (its own, else the world's), the time of its targets.
/// With `start` (one per body), the context's start velocities are those.
JointContext contextOf(std::span<const Body> bodies, const Joint& j, const SolverSettings& settings,
                       double h, double time, std::span<const StartVelocity> start = {});

/// Joint `ji`'s rows from `ctx` into `slots` (its maxRows(), each blanked first), as assembleRows
/// places them: on the solver bodies, keyed, verified; friction rows' `normal` stays the joint's
/// own index. Returns how many, 0 for a joint between static bodies.
int fillJoint(std::span<const std::unique_ptr<Joint>> joints, std::size_t ji,
              std::span<const Body> bodies, const JointContext& ctx, std::span<Row> slots);

/// Assembles the rows of all joints for a step of length h starting at `time` (motors' targets).
/// Solver body indices are body indices, -1 for the world and for static bodies; joints between two
/// such are skipped (nothing moves). Row keys are unique and stable across steps; friction rows'
/// `normal` becomes a list index. Throws std::logic_error when a joint writes more rows than its
/// maxRows(). Throws std::domain_error naming the joint if it produces a non-finite row.
void assembleRows(std::span<const std::unique_ptr<Joint>> joints, std::span<const Body> bodies,
                  const SolverSettings& settings, double h, double time, std::vector<Row>& rows,
                  std::span<const StartVelocity> start = {});

}  // namespace linx::step
