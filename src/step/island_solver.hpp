// Solving a step's rows island by island: each island's rows form an independent boxed LCP, so
// solving them separately gives the monolithic solution (the exact solver to round-off, PGS the
// same sweeps when it runs a fixed number of them), with smaller factorizations, per-island
// convergence, and islands that are asleep left out.
#pragma once

#include <linx/row.hpp>
#include <linx/solver.hpp>

#include "parallel/task_output.hpp"
#include "solver/problem.hpp"
#include "step/islands.hpp"

#include <cstdint>
#include <memory>
#include <span>
#include <utility>
#include <vector>

namespace linx::step {

/// The links (body_a, body_b) of rows, one per row: link k is row k, so Islands::links(i) lists
/// the rows of island i. Reuses `links`' storage.
void rowLinks(std::span<const Row> rows, std::vector<std::pair<int, int>>& links);

/// One island's problem, gathered: its rows with local body indices, its bodies (its own movable
/// bodies first, in Islands::bodies order, then the non-movable bodies its rows refer to, in
/// ascending index) and its impulses.
struct IslandProblem {
  std::vector<int> statics;  ///< the non-movable bodies the rows refer to, ascending
  std::vector<Row> rows;
  std::vector<solver::SolverBody> bodies;
  std::vector<double> lambda;
  // The split impulse: each row's position error left to the pseudo-velocity solve (a contact's
  // penetration; 0 for the others), and that problem's bodies and impulses.
  std::vector<double> push_phi;
  std::vector<solver::SolverBody> push_bodies;
  std::vector<double> push_lambda;
};

/// A body's pseudo velocity from the split impulse: it moves the body's position over the step
/// (x += h (v + push.v)) and is not kept in its velocity.
struct PushVelocity {
  Vec3 v = Vec3::Zero();
  Vec3 w = Vec3::Zero();
};

/// The buffers of one run of islands solved on one thread, with its own solver instance.
struct IslandTask {
  IslandProblem problem;
  std::unique_ptr<solver::ConstraintSolver> solver;  ///< another() of the given solver
  SolverReport report;                               ///< of the islands this task solved, merged
};

/// Reusable buffers of solveIslands: no allocation once they have grown to the problem's size
/// (the solvers' own buffers aside).
struct IslandWorkspace {
  std::vector<int> row_island;           ///< island of each row, -1 for none
  std::vector<int> row_start, row_list;  ///< rows of each island (CSR, ascending)
  std::vector<int> local_row;            ///< global row -> its index among its island's rows
  std::vector<int> local_body;           ///< movable body -> its index among its island's bodies
  IslandProblem large;                   ///< islands solved one after another, each on every thread
  std::vector<int> small;                ///< islands solved side by side, ascending
  std::vector<parallel::TaskOutput<IslandTask>> tasks;  ///< runs of `small`, one per task
  /// Output: each body's pseudo velocity (zero but in islands whose split rows push).
  std::vector<PushVelocity> push;
};

/// Solves the rows of each awake island separately with `solver`.
///
/// rows: the step's rows; body_a/body_b are body indices, -1 for none. A row belongs to the island
///   of its movable end (Islands::islandOf of body_a, else of body_b); both ends movable must lie
///   in the same island, and a friction row in the island of its `normal` row
///   (std::invalid_argument otherwise). A row with no movable end belongs to no island: it is not
///   solved, lambda 0.
/// bodies: solver bodies indexed by body index (at least islands.bodyCount()); on entry u*, on exit
///   u+ for the bodies of awake islands. Non-movable bodies a row refers to are read (their
///   velocity enters J u), never written.
/// lambda: one per row; on entry the warm start, on exit the impulses. Rows of islands that are
///   not awake keep their lambda (the impulses they rest on, for when they wake) and their bodies
///   are left untouched.
/// island_awake: one flag per island (islands.count()), or empty for all awake.
/// `threads`: islands of 4,096 rows and more are solved one after another, each with all the
///   threads (Problem::threads); smaller islands are solved side by side, in runs of consecutive
///   islands, each run on one thread with its own solver (`solver.another()`; the given `solver`
///   itself on one thread). Every island's solve depends on its own rows alone, so the results are
///   the same for any count.
/// Split impulse: a contact's penetration (a contact normal row with phi < 0: deeper than its
///   slop) is not in the velocity solve, whose target for it is its speed (0, or a bounce).
///   An island with one is solved a second time, for pseudo velocities: the same rows and bounds
///   from bodies at rest, the contacts' penetrations with their targets -(erp / h) phi, every
///   other row with target 0 (joints and friction hold, a speculative gap may not close). They go
///   to work.push, which moves the positions and is not kept in the velocity (Bullet's split
///   impulse; Box2D v3's relax pass does the same for the soft step), so a body created inside
///   another is pushed out and stays.
/// Returns the islands' reports merged (of the velocity solves): rows summed over the solved
/// islands, iterations and residual the largest, redundant rows summed, converged if every island
/// converged.
SolverReport solveIslands(const Islands& islands, std::span<const std::uint8_t> island_awake,
                          std::span<const Row> rows, std::span<solver::SolverBody> bodies,
                          std::span<double> lambda, double h, solver::ConstraintSolver& solver,
                          const SolverSettings& settings, IslandWorkspace& work, int threads = 1);

}  // namespace linx::step
