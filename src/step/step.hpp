// The step as a list of named stages. World::step() runs `substeps` passes of them, each of
// length h; every stage is a function of what it reads and what it writes, in this order (the
// same list is in docs/solver.md):
//
//   wake        bodies disturbed from outside since the last pass wake, with their neighbours
//   velocities  u* = u + h M^-1 (f_ext - gyroscopic), for awake bodies      dynamics/integrator
//   collide     shapes -> broadphase -> narrowphase -> contact points       step/contact_stage
//   prepare     joint rows, then contact rows, each with its warm-start impulse
//                                                    step/assembly, step/joint_warm_start
//   islands     bodies linked by the rows; an island with an awake body wakes entirely
//                                                    step/islands, step/sleep
//   accurate    with integrator "accurate": islands of joints alone move over the pass by the
//               accurate integrator; the stages below leave them     step/accurate_integrator
//               ("auto": those whose one step of it holds the tolerance) step/integrator_choice
//   solve       each awake island's boxed LCP: impulses lambda, u+ = u* + M^-1 J^T lambda
//                                                    step/island_solver, solver/
//   store       impulses kept for the next pass's warm start and the contacts() report
//   positions   x += h v+, q = exp(h w+) q, for awake bodies                dynamics/integrator
//   stabilize   Newton iterations remove the joints' position errors; the velocities follow
//               the step's part of the correction                           step/stabilization
//   track       joints follow their history (a hinge counts turns)
//   sleep       islands resting on contacts for long enough fall asleep     step/sleep
//
// With solver type Soft, World::step() runs softStep instead: wake, collide, prepare and islands
// once, then `substeps` (velocities, warm start, soft sweep, positions, relax per substep;
// solver/soft_solver), restitution, store, stabilize, track and sleep.
//
// After the passes World::step() runs `check` (step/check): a non-finite state, or energy made
// while nothing drives the world, stops the run.
#pragma once

#include <linx/body.hpp>
#include <linx/joint.hpp>
#include <linx/row.hpp>
#include <linx/solver.hpp>
#include <linx/world.hpp>

#include "solver/problem.hpp"
#include "solver/soft_solver.hpp"
#include "step/accurate_integrator.hpp"
#include "step/assembly.hpp"
#include "step/contact_stage.hpp"
#include "step/geometric_stiffness.hpp"
#include "step/integrator_choice.hpp"
#include "step/island_solver.hpp"
#include "step/islands.hpp"
#include "step/joint_loads.hpp"
#include "step/joint_warm_start.hpp"
#include "step/sleep.hpp"
#include "step/stabilization.hpp"
#include "step/substep_joints.hpp"

#include <cstdint>
#include <memory>
#include <span>
#include <vector>

namespace linx::state {
class Archive;
}

namespace linx::step {

/// What a pass works on, lent by the world for the call.
struct Scene {
  std::span<Body> bodies;
  std::span<const std::unique_ptr<Joint>> joints;
  const WorldSettings& settings;
  int threads = 1;    ///< resolved worker count (>= 1)
  double time = 0.0;  ///< (s) at the start of the pass
};

/// The rows of a pass: joint rows first, then contact rows, with one impulse each.
struct Rows {
  std::vector<Row> rows;
  std::vector<double> lambda;  ///< warm start before the solve, the impulses after it
  std::size_t joint_rows = 0;  ///< rows [0, joint_rows) are the joints'
};

/// A body's pose and velocities, to put it back.
struct BodyState {
  Pose pose;
  Vec3 v = Vec3::Zero();
  Vec3 w = Vec3::Zero();
};

/// What the step keeps from one pass to the next (warm starts, contacts, sleep) and its buffers.
struct State {
  Rows rows;
  JointWarmStart joint_warm;
  JointLoads joint_loads;  ///< what each joint applied over the last (sub)step
  ContactStage contact;
  Islands islands;
  SleepTracker sleep;
  IslandWorkspace island_work;
  std::vector<solver::SolverBody> solver_bodies;
  std::unique_ptr<solver::ConstraintSolver> solver;
  SolverType solver_type = SolverType::Auto;  ///< what `solver` is
  // scratch
  std::vector<std::pair<int, int>> links;
  std::vector<std::uint8_t> movable, may_sleep, row_active;
  std::vector<int> row_manifold;
  std::vector<std::uint8_t> moving;             // soft step: movable and awake
  std::vector<StartVelocity> start_velocities;  // before the (sub)step's forces (armature)
  SubstepJoints substep_joints;
  PostStabilization stabilization;
  GeometricStiffness geometric_stiffness;
  std::vector<double> last_joint_impulses;  // without warm start: the geometric stiffness's
  solver::SoftSolver soft;
  std::vector<solver::SoftSolver::Bounce> bounces;
  AccurateIntegrator accurate;
  IntegratorChoice choice;                    ///< integrator "auto": which islands try `accurate`
  std::vector<std::uint8_t> accurate_bodies;  // moved by `accurate` this pass (one per body)
  std::vector<std::uint8_t> tried_accurate;   // "auto": the bodies that tried it
  std::vector<std::uint8_t> behind;           ///< per body: its velocity is the step's (Handover)
  std::vector<BodyState> left;                // each body's state as the last pass left it
  std::vector<std::uint8_t> unprojected;     // per body: its state is not the accurate integrator's
  std::vector<BodyState> before_accurate;    // their state before, in body order
  std::vector<Row> accurate_rows;            // soft step: the joint rows `accurate` moved
  std::vector<double> accurate_lambda;       // and their impulses
  std::vector<std::uint8_t> island_stepped;  // awake islands the step solves
  IntegratorReport accurate_report;
  std::vector<int> neighbours;

  /// Reads or writes what carries from one step to the next (World::saveState; carried_state.cpp):
  /// not the scratch above, which each step rebuilds.
  void persist(state::Archive& archive);
};

/// One pass of length h (s) through the stages above (the soft step's with solver type Soft).
/// Returns the solve's report.
SolverReport pass(const Scene& scene, State& state, double h);

/// The soft step of length dt (solver type Soft): wake, collide, prepare, islands once, then
/// `substeps` substeps of (velocities, warm start, soft sweep, positions, relax), then store,
/// stabilize, track and sleep.
SolverReport softStep(const Scene& scene, State& state, double dt);

/// Wakes body `index` (unless static) and the bodies it touched in the last pass: if it moves
/// away, or was moved away, they must notice.
void wakeWithNeighbours(std::span<const Body> bodies, State& state, int index);

}  // namespace linx::step
