#include "step/island_solver.hpp"

#include "parallel/parallel_for.hpp"
#include "step/split_impulse.hpp"

#include <algorithm>
#include <stdexcept>
#include <typeinfo>

namespace linx::step {

namespace {
/// Rows of an island from which its gather is split over the threads.
constexpr std::ptrdiff_t kParallelRows = 4096;
}  // namespace

void rowLinks(std::span<const Row> rows, std::vector<std::pair<int, int>>& links) {
  links.resize(rows.size());
  for (std::size_t k = 0; k < rows.size(); ++k) links[k] = {rows[k].body_a, rows[k].body_b};
  // A coupled row joins its further bodies to its first one as well.
  for (const Row& r : rows) {
    if (!r.coupled()) continue;
    int first = -1;
    r.forEachBlock([&](int body, const Vec6&) {
      if (body < 0) return;
      if (first >= 0)
        links.emplace_back(first, body);
      else
        first = body;
    });
  }
}

namespace {

void merge(SolverReport& total, const SolverReport& report) {
  total.rows += report.rows;
  total.iterations = std::max(total.iterations, report.iterations);
  total.residual = std::max(total.residual, report.residual);
  total.redundant_rows += report.redundant_rows;
  total.converged = total.converged && report.converged;
}

/// The split impulse of an island gathered in `out` (solveIslands), whose split rows' errors
/// were taken out of the velocity solve into `push_phi` (one per row, 0 for the others): the
/// pseudo velocities of the island's own bodies into `push`, by the same solver on the same rows,
/// each targetting -(erp / h) phi of its push_phi, from bodies at rest and no impulse.
void solvePush(std::span<const int> own, double h, solver::ConstraintSolver& solver,
               const SolverSettings& settings, IslandProblem& out, std::span<PushVelocity> push,
               int threads) {
  if (std::none_of(out.push_phi.begin(), out.push_phi.end(), [](double p) { return p < 0.0; }))
    return;
  for (std::size_t j = 0; j < out.rows.size(); ++j) {
    Row& r = out.rows[j];
    r.speed = 0.0;
    r.phi = out.push_phi[j];
  }
  out.push_bodies.resize(out.bodies.size());
  for (std::size_t l = 0; l < out.bodies.size(); ++l)
    out.push_bodies[l] = solver::SolverBody{out.bodies[l].inv_mass, out.bodies[l].inv_inertia,
                                            Vec3::Zero(), Vec3::Zero()};
  out.push_lambda.assign(out.rows.size(), 0.0);
  solver::Problem problem{out.rows, out.push_bodies, out.push_lambda, h, threads};
  solver.solve(problem, settings);
  for (std::size_t l = 0; l < own.size(); ++l)
    push[static_cast<std::size_t>(own[l])] =
        PushVelocity{out.push_bodies[l].v, out.push_bodies[l].w};
}

/// Gathers island i into `out`, solves it with `solver` on `threads` and scatters the impulses
/// and its own bodies' velocities back, and their pseudo velocities into `push` (solvePush).
/// Writes only the island's rows and bodies.
SolverReport solveIsland(int i, const Islands& islands, std::span<const Row> rows,
                         std::span<solver::SolverBody> bodies, std::span<double> lambda, double h,
                         solver::ConstraintSolver& solver, const SolverSettings& settings,
                         const IslandWorkspace& work, std::span<PushVelocity> push,
                         IslandProblem& out, int threads) {
  const int* begin = work.row_list.data() + work.row_start[static_cast<std::size_t>(i)];
  const auto m = static_cast<std::size_t>(work.row_start[static_cast<std::size_t>(i) + 1] -
                                          work.row_start[static_cast<std::size_t>(i)]);
  const std::span<const int> own = islands.bodies(i);

  // The non-movable bodies the rows refer to (read only: their velocity enters J u).
  out.statics.clear();
  for (std::size_t j = 0; j < m; ++j) {
    const Row& r = rows[static_cast<std::size_t>(begin[j])];
    r.forEachBlock([&](int body, const Vec6&) {
      if (body >= 0 && islands.islandOf(body) < 0) out.statics.push_back(body);
    });
  }
  std::sort(out.statics.begin(), out.statics.end());
  out.statics.erase(std::unique(out.statics.begin(), out.statics.end()), out.statics.end());
  const auto local = [&](int body) {
    if (body < 0) return -1;
    if (islands.islandOf(body) >= 0) return work.local_body[static_cast<std::size_t>(body)];
    const auto it = std::lower_bound(out.statics.begin(), out.statics.end(), body);
    return static_cast<int>(own.size()) + static_cast<int>(it - out.statics.begin());
  };

  out.rows.resize(m);
  out.lambda.resize(m);
  out.push_phi.resize(m);
  parallel::forEach(static_cast<std::ptrdiff_t>(m), threads, kParallelRows, [&](std::ptrdiff_t j) {
    const auto k = static_cast<std::size_t>(begin[j]);
    Row& r = out.rows[static_cast<std::size_t>(j)];
    r = rows[k];
    r.body_a = local(r.body_a);
    r.body_b = local(r.body_b);
    r.body_c = local(r.body_c);
    r.body_d = local(r.body_d);
    if (r.normal >= 0) r.normal = work.local_row[static_cast<std::size_t>(r.normal)];
    out.lambda[static_cast<std::size_t>(j)] = lambda[k];
    // A penetration goes to the split impulse: the velocity solve holds J u+ = speed.
    out.push_phi[static_cast<std::size_t>(j)] = splitsPenetration(r) ? r.phi : 0.0;
    if (splitsPenetration(r)) r.phi = 0.0;
  });
  out.bodies.resize(own.size() + out.statics.size());
  parallel::forEach(static_cast<std::ptrdiff_t>(own.size()), threads, kParallelRows,
                    [&](std::ptrdiff_t l) {
                      out.bodies[static_cast<std::size_t>(l)] =
                          bodies[static_cast<std::size_t>(own[static_cast<std::size_t>(l)])];
                    });
  for (std::size_t l = 0; l < out.statics.size(); ++l)
    out.bodies[own.size() + l] = bodies[static_cast<std::size_t>(out.statics[l])];

  solver::Problem problem{out.rows, out.bodies, out.lambda, h, threads};
  const SolverReport report = solver.solve(problem, settings);
  solvePush(own, h, solver, settings, out, push, threads);

  parallel::forEach(static_cast<std::ptrdiff_t>(m), threads, kParallelRows, [&](std::ptrdiff_t j) {
    lambda[static_cast<std::size_t>(begin[j])] = out.lambda[static_cast<std::size_t>(j)];
  });
  parallel::forEach(static_cast<std::ptrdiff_t>(own.size()), threads, kParallelRows,
                    [&](std::ptrdiff_t l) {
                      bodies[static_cast<std::size_t>(own[static_cast<std::size_t>(l)])] =
                          out.bodies[static_cast<std::size_t>(l)];
                    });
  return report;
}

}  // namespace

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
    int island = -1;
    rows[k].forEachBlock([&](int body, const Vec6&) {
      const int i = islandOf(body);
      if (island >= 0 && i >= 0 && i != island)
        throw std::invalid_argument("solveIslands: a row joins two islands");
      if (i >= 0) island = i;
    });
    work.row_island[k] = island;
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
  work.push.assign(bodies.size(), PushVelocity{});

  // Local numbers: a row among its island's rows, a movable body among its island's bodies. Each
  // row and body is in one island at most, so every island's numbers can be written at once.
  parallel::forEach(signed_n, threads, kParallelRows, [&](std::ptrdiff_t k) {
    if (work.row_island[static_cast<std::size_t>(k)] < 0)
      lambda[static_cast<std::size_t>(k)] = 0.0;  // touches nothing that moves
  });
  work.local_row.resize(n);
  work.local_body.resize(bodies.size());
  for (int i = 0; i < count; ++i) {
    const int first = work.row_start[static_cast<std::size_t>(i)];
    const int last = work.row_start[static_cast<std::size_t>(i) + 1];
    for (int j = first; j < last; ++j)
      work.local_row[static_cast<std::size_t>(work.row_list[static_cast<std::size_t>(j)])] =
          j - first;
    const std::span<const int> own = islands.bodies(i);
    for (std::size_t l = 0; l < own.size(); ++l)
      work.local_body[static_cast<std::size_t>(own[l])] = static_cast<int>(l);
  }

  // Sleeping islands keep their impulses and their bodies; islands with no row need no solve.
  SolverReport total;
  work.small.clear();
  for (int i = 0; i < count; ++i) {
    const int first = work.row_start[static_cast<std::size_t>(i)];
    const int last = work.row_start[static_cast<std::size_t>(i) + 1];
    if (!island_awake.empty() && island_awake[static_cast<std::size_t>(i)] == 0) continue;
    if (first == last) continue;
    if (threads > 1 && last - first < kParallelRows) {
      work.small.push_back(i);  // solved side by side below
      continue;
    }
    merge(total, solveIsland(i, islands, rows, bodies, lambda, h, solver, settings, work, work.push,
                             work.large, threads));
  }
  if (work.small.empty()) return total;

  // Small islands side by side: runs of consecutive islands, a run per task, each with its own
  // buffers and solver. A run's report is merged in run order.
  const std::size_t tasks = std::min(work.small.size(), 16 * static_cast<std::size_t>(threads));
  if (work.tasks.size() < tasks) work.tasks.resize(tasks);
  parallel::forEachTask(static_cast<std::ptrdiff_t>(tasks), threads, [&](std::ptrdiff_t t) {
    IslandTask& task = work.tasks[static_cast<std::size_t>(t)].value;
    if (!task.solver) task.solver = solver.another();
    const solver::ConstraintSolver& mine = *task.solver;
    if (typeid(mine) != typeid(solver)) task.solver = solver.another();
    task.report = SolverReport{};
    const std::size_t first = work.small.size() * static_cast<std::size_t>(t) / tasks;
    const std::size_t last = work.small.size() * static_cast<std::size_t>(t + 1) / tasks;
    for (std::size_t s = first; s < last; ++s)
      merge(task.report, solveIsland(work.small[s], islands, rows, bodies, lambda, h, *task.solver,
                                     settings, work, work.push, task.problem, 1));
  });
  for (std::size_t t = 0; t < tasks; ++t) merge(total, work.tasks[t].value.report);
  return total;
}

}  // namespace linx::step
