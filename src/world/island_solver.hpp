// Solving a step's rows island by island: each island's rows form an independent boxed LCP, so
// solving them separately gives the monolithic solution (the exact solver to round-off, PGS the
// same sweeps when it runs a fixed number of them), with smaller factorizations, per-island
// convergence, and islands that are asleep left out.
#pragma once

#include <linx/row.hpp>
#include <linx/solver.hpp>

#include "solver/problem.hpp"
#include "world/islands.hpp"

#include <cstdint>
#include <span>
#include <utility>
#include <vector>

namespace linx::world {

/// The links (body_a, body_b) of rows, one per row: link k is row k, so Islands::links(i) lists
/// the rows of island i. Reuses `links`' storage.
void rowLinks(std::span<const Row> rows, std::vector<std::pair<int, int>>& links);

/// Reusable buffers of solveIslands: no allocation once they have grown to the problem's size
/// (the solver's own buffers aside).
struct IslandWorkspace {
  std::vector<int> row_island;           ///< island of each row, -1 for none
  std::vector<int> row_start, row_list;  ///< rows of each island (CSR, ascending)
  std::vector<int> local_row;            ///< global row -> local row index of its island
  std::vector<int> local_body;           ///< global body -> local body index (-1 when not gathered)
  std::vector<int> gathered;             ///< local body -> global body, of the island being solved
  std::vector<Row> rows;                 ///< the island's rows, with local body indices
  std::vector<solver::SolverBody> bodies;  ///< the island's bodies
  std::vector<double> lambda;              ///< the island's impulses
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
///   not awake get lambda 0 and their bodies are left untouched.
/// island_awake: one flag per island (islands.count()), or empty for all awake.
/// `threads` go to each island's solve (Problem::threads).
/// Returns the islands' reports merged: rows summed over the solved islands, iterations and
/// residual the largest, redundant rows summed, converged if every island converged.
SolverReport solveIslands(const Islands& islands, std::span<const std::uint8_t> island_awake,
                          std::span<const Row> rows, std::span<solver::SolverBody> bodies,
                          std::span<double> lambda, double h, solver::ConstraintSolver& solver,
                          const SolverSettings& settings, IslandWorkspace& work, int threads = 1);

}  // namespace linx::world
