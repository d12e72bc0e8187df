#include "world/island_solver.hpp"

#include "parallel/parallel_for.hpp"

#include <algorithm>
#include <stdexcept>

namespace linx::world {

namespace {
/// Rows of an island from which its gather is split over the threads.
constexpr std::ptrdiff_t kParallelRows = 4096;
}  // namespace

void rowLinks(std::span<const Row> rows, std::vector<std::pair<int, int>>& links) {
  links.resize(rows.size());
  for (std::size_t k = 0; k < rows.size(); ++k) links[k] = {rows[k].body_a, rows[k].body_b};
}

SolverReport solveIslands(const Islands& islands, std::span<const std::uint8_t> island_awake,
                          std::span<const Row> rows, std::span<solver::SolverBody> bodies,
                          std::span<double> lambda, double h, solver::ConstraintSolver& solver,
                          const SolverSettings& settings, IslandWorkspace& work, int threads) {
  const int body_count = islands.bodyCount();
  const int count = islands.count();
  const std::size_t n = rows.size();
  if (bodies.size() < static_cast<std::size_t>(body_count))
    throw std::invalid_argument("solveIslands: fewer solver bodies than bodies");
  if (lambda.size() != n) throw std::invalid_argument("solveIslands: one impulse per row");
  if (!island_awake.empty() && island_awake.size() != static_cast<std::size_t>(count))
    throw std::invalid_argument("solveIslands: one awake flag per island");

  // Each row to the island of its movable end.
  auto islandOf = [&](int body) {
    if (body < 0) return -1;
    if (body >= body_count) throw std::invalid_argument("solveIslands: row body out of range");
    return islands.islandOf(body);
  };
  const auto signed_n = static_cast<std::ptrdiff_t>(n);
  work.row_island.resize(n);
  parallel::forEach(signed_n, threads, kParallelRows, [&](std::ptrdiff_t ik) {
    const auto k = static_cast<std::size_t>(ik);
    const int a = islandOf(rows[k].body_a), b = islandOf(rows[k].body_b);
    if (a >= 0 && b >= 0 && a != b)
      throw std::invalid_argument("solveIslands: a row joins two islands");
    work.row_island[k] = a >= 0 ? a : b;
  });
  parallel::forEach(signed_n, threads, kParallelRows, [&](std::ptrdiff_t ik) {
    const auto k = static_cast<std::size_t>(ik);
    const int normal = rows[k].normal;
    if (normal < 0) return;
    if (static_cast<std::size_t>(normal) >= n ||
        work.row_island[static_cast<std::size_t>(normal)] != work.row_island[k])
      throw std::invalid_argument("solveIslands: a friction row's normal row is in another island");
  });
  bucketByIsland(work.row_island, count, work.row_start, work.row_list);
  parallel::forEach(signed_n, threads, kParallelRows, [&](std::ptrdiff_t k) {
    if (work.row_island[static_cast<std::size_t>(k)] < 0)
      lambda[static_cast<std::size_t>(k)] = 0.0;  // touches nothing that moves
  });
  work.local_row.resize(n);
  work.local_body.assign(bodies.size(), -1);

  SolverReport total;
  for (int i = 0; i < count; ++i) {
    const auto begin = work.row_list.begin() + work.row_start[static_cast<std::size_t>(i)];
    const auto end = work.row_list.begin() + work.row_start[static_cast<std::size_t>(i) + 1];
    if (!island_awake.empty() && island_awake[static_cast<std::size_t>(i)] == 0) {
      for (auto it = begin; it != end; ++it) lambda[static_cast<std::size_t>(*it)] = 0.0;
      continue;
    }
    if (begin == end) continue;  // nothing to solve: u+ = u*

    // Gather: the island's bodies first (these are scattered back), then any non-movable body a
    // row refers to (read only).
    work.gathered.clear();
    auto local = [&](int body) {
      if (body < 0) return -1;
      int& l = work.local_body[static_cast<std::size_t>(body)];
      if (l < 0) {
        l = static_cast<int>(work.gathered.size());
        work.gathered.push_back(body);
      }
      return l;
    };
    for (const int b : islands.bodies(i)) local(b);
    const std::size_t own = work.gathered.size();
    const auto m = static_cast<std::size_t>(end - begin);
    work.rows.resize(m);
    work.lambda.resize(m);
    parallel::forEach(static_cast<std::ptrdiff_t>(m), threads, kParallelRows,
                      [&](std::ptrdiff_t j) {
                        work.local_row[static_cast<std::size_t>(begin[j])] = static_cast<int>(j);
                      });
    for (std::size_t j = 0; j < m; ++j) {  // number the bodies first, in row order
      const Row& r = rows[static_cast<std::size_t>(begin[static_cast<std::ptrdiff_t>(j)])];
      local(r.body_a);
      local(r.body_b);
    }
    parallel::forEach(static_cast<std::ptrdiff_t>(m), threads, kParallelRows,
                      [&](std::ptrdiff_t j) {  // then copy the rows, each to its own slot
                        const auto k = static_cast<std::size_t>(begin[j]);
                        Row& r = work.rows[static_cast<std::size_t>(j)];
                        r = rows[k];
                        if (r.body_a >= 0)
                          r.body_a = work.local_body[static_cast<std::size_t>(r.body_a)];
                        if (r.body_b >= 0)
                          r.body_b = work.local_body[static_cast<std::size_t>(r.body_b)];
                        if (r.normal >= 0)
                          r.normal = work.local_row[static_cast<std::size_t>(r.normal)];
                        work.lambda[static_cast<std::size_t>(j)] = lambda[k];
                      });
    work.bodies.resize(work.gathered.size());
    parallel::forEach(
        static_cast<std::ptrdiff_t>(work.gathered.size()), threads, kParallelRows,
        [&](std::ptrdiff_t l) {
          work.bodies[static_cast<std::size_t>(l)] =
              bodies[static_cast<std::size_t>(work.gathered[static_cast<std::size_t>(l)])];
        });

    solver::Problem problem{work.rows, work.bodies, work.lambda, h, threads};
    const SolverReport report = solver.solve(problem, settings);

    // Scatter.
    parallel::forEach(
        static_cast<std::ptrdiff_t>(m), threads, kParallelRows, [&](std::ptrdiff_t j) {
          lambda[static_cast<std::size_t>(begin[j])] = work.lambda[static_cast<std::size_t>(j)];
        });
    parallel::forEach(
        static_cast<std::ptrdiff_t>(own), threads, kParallelRows, [&](std::ptrdiff_t l) {
          bodies[static_cast<std::size_t>(work.gathered[static_cast<std::size_t>(l)])] =
              work.bodies[static_cast<std::size_t>(l)];
        });
    for (const int b : work.gathered) work.local_body[static_cast<std::size_t>(b)] = -1;

    total.rows += report.rows;
    total.iterations = std::max(total.iterations, report.iterations);
    total.residual = std::max(total.residual, report.residual);
    total.redundant_rows += report.redundant_rows;
    total.converged = total.converged && report.converged;
  }
  return total;
}

}  // namespace linx::world
