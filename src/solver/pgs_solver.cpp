#include "solver/pgs_solver.hpp"

#include "parallel/parallel_for.hpp"
#include "solver/row_system.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>

#include <omp.h>

namespace linx::solver {

namespace {
/// Problems of at least this many rows are swept colour by colour (see pgs_solver.hpp). Below it
/// the sweep keeps the rows' own order: with some 36 colours per sweep a smaller problem spends
/// more at the barriers between colours than a second thread saves (1,000 poured spheres, about
/// 10,000 rows, ran at 0.8 times the speed on two threads).
constexpr std::size_t kColourRows = 16384;
constexpr int kColours = GraphColouring::kColours;  // per phase; the rest is swept serially
/// Rows of a colour from which its warm start is split over the threads (a team costs more than a
/// few rows).
constexpr std::ptrdiff_t kParallelWarmRows = 1024;
}  // namespace

void PgsSolver::findBlocks(const Problem& p) {
  const std::size_t n = p.rows.size();
  block_start_.resize(n);
  // (A coupled row stands alone: the blocks' matrices see two bodies.)
  const auto equality = [](const Row& r) {
    return r.kind == RowKind::Bilateral && std::isinf(r.lo) && std::isinf(r.hi) && !r.coupled();
  };
  int run = 0;  // rows in the current block
  for (std::size_t k = 0; k < n; ++k) {
    const Row& r = p.rows[k];
    const bool continues = k > 0 && run > 0 && run < kMaxBlock && equality(r) &&
                           equality(p.rows[k - 1]) && (r.key >> 8) == (p.rows[k - 1].key >> 8) &&
                           r.body_a == p.rows[k - 1].body_a && r.body_b == p.rows[k - 1].body_b;
    block_start_[k] = !continues;
    run = continues ? run + 1 : (equality(r) ? 1 : 0);
  }
}

void PgsSolver::planSweep(Problem& p) {
  const std::size_t n = p.rows.size();
  findBlocks(p);
  order_.resize(n);
  groups_.clear();
  group_ends_.clear();
  if (n < kColourRows) {
    for (std::size_t k = 0; k < n; ++k) order_[k] = static_cast<int>(k);
    groups_.push_back(Group{0, 0, false});
    group_ends_.push_back(static_cast<int>(n));
    return;
  }
  // Greedy colouring, one phase for the normal and bilateral rows and one for the friction rows
  // (a sweep settles the normal impulses before friction, whose bounds follow them, as the
  // unordered sweep does). Within a phase, colour c holds rows that share no movable body; a
  // block's rows take the colour of its first row, and stay consecutive (the fill keeps the
  // rows' order within a colour).
  colour_of_.resize(n);
  std::size_t pos = 0;
  for (const bool friction : {false, true}) {
    colouring_.reset(p.bodies.size());
    std::array<int, kColours + 1> count{};
    for (std::size_t k = 0; k < n; ++k) {
      const Row& r = p.rows[k];
      if ((r.kind == RowKind::Friction) != friction) continue;
      if (!block_start_[k]) {
        colour_of_[k] = colour_of_[k - 1];
        ++count[static_cast<std::size_t>(colour_of_[k])];
        continue;
      }
      // A coupled row touches more than two bodies: the serial rest takes it.
      const int colour = r.coupled() ? kColours : colouring_.take(r.body_a, r.body_b);
      colour_of_[k] = colour;
      ++count[static_cast<std::size_t>(colour)];
    }
    std::array<int, kColours + 1> fill{};
    for (int c = 0; c <= kColours; ++c) {
      fill[static_cast<std::size_t>(c)] = static_cast<int>(pos);
      const int size = count[static_cast<std::size_t>(c)];
      pos += static_cast<std::size_t>(size);
      if (size > 0) {
        groups_.push_back(Group{0, 0, c < kColours});
        group_ends_.push_back(static_cast<int>(pos));
      }
    }
    for (std::size_t k = 0; k < n; ++k)
      if ((p.rows[k].kind == RowKind::Friction) == friction)
        order_[static_cast<std::size_t>(fill[static_cast<std::size_t>(colour_of_[k])]++)] =
            static_cast<int>(k);
  }
}

void PgsSolver::buildItems(const std::vector<int>& group_ends) {
  items_.clear();
  block_inverse_.clear();
  std::size_t group = 0;
  int group_begin = 0;  // sweep position where the current group starts
  const auto close = [&](int item_end) {
    groups_[group].begin = group_begin;
    groups_[group].size = item_end - group_begin;
    group_begin = item_end;
    ++group;
  };
  const int n = static_cast<int>(rows_.size());
  int pos = 0;
  while (pos < n) {
    const int end_of_group = group_ends[group];
    int end = pos + 1;
    while (end < end_of_group && !block_start_[static_cast<std::size_t>(order_[end])]) ++end;
    items_.push_back(Item{pos, end - pos, -1});
    if (end - pos > 1) {
      // A_bb: the block's rows share both bodies (an absent end has W = 0).
      const int size = end - pos;
      BlockMatrix a = BlockMatrix::Identity();
      for (int i = 0; i < size; ++i) {
        const CompactRow& ri = rows_[static_cast<std::size_t>(pos + i)];
        for (int j = 0; j < size; ++j) {
          const CompactRow& rj = rows_[static_cast<std::size_t>(pos + j)];
          a(i, j) = ri.ja_v.dot(rj.wa_v) + ri.ja_w.dot(rj.wa_w) + ri.jb_v.dot(rj.wb_v) +
                    ri.jb_w.dot(rj.wb_w) + (i == j ? ri.cfm : 0.0);
        }
      }
      // A dependent row (a pivot that vanishes against its diagonal) leaves the rows scalar.
      const Eigen::LDLT<BlockMatrix> ldlt(a);
      bool regular = ldlt.info() == Eigen::Success;
      for (int i = 0; i < size && regular; ++i)
        regular = ldlt.vectorD()(i) > 1e-10 * a(i, i) && a(i, i) > 0.0;
      if (regular) {
        items_.back().block = static_cast<int>(block_inverse_.size());
        block_inverse_.push_back(ldlt.solve(BlockMatrix::Identity()));
      } else {
        items_.back().size = 1;
        for (int k = pos + 1; k < end; ++k) items_.push_back(Item{k, 1, -1});
      }
    }
    pos = end;
    if (pos == end_of_group) close(static_cast<int>(items_.size()));
  }
  while (group < groups_.size()) close(static_cast<int>(items_.size()));  // empty problem
}

SolverReport PgsSolver::solve(Problem& p, const SolverSettings& settings) {
  SolverReport report;
  const std::size_t n = p.rows.size();
  report.rows = static_cast<int>(n);
  if (n == 0) return report;
  const int threads = std::max(1, p.threads);
  planSweep(p);

  // Gather: velocities (one extra slot, always zero, for "no body") and compact rows, in sweep
  // order, with each friction row's normal row as a sweep position.
  const int none = static_cast<int>(p.bodies.size());
  velocities_.resize(p.bodies.size() + 1);
  for (std::size_t i = 0; i < p.bodies.size(); ++i) velocities_[i] = {p.bodies[i].v, p.bodies[i].w};
  velocities_.back() = Velocity{};
  position_.resize(n);
  for (std::size_t pos = 0; pos < n; ++pos)
    position_[static_cast<std::size_t>(order_[pos])] = static_cast<int>(pos);
  rows_.resize(n);
  lambda_.resize(n);
  // The coupled rows' further ends, numbered in sweep order (before the parallel gather).
  coupled_.clear();
  std::vector<int>& coupled_of = coupled_of_;
  coupled_of.assign(n, -1);
  for (std::size_t pos = 0; pos < n; ++pos) {
    const Row& r = p.rows[static_cast<std::size_t>(order_[pos])];
    if (!r.coupled()) continue;
    coupled_of[pos] = static_cast<int>(coupled_.size());
    CoupledEnds e{};
    const int bodies[2] = {r.body_c, r.body_d};
    const Vec6* blocks[2] = {&r.Jc, &r.Jd};
    for (int i = 0; i < 2; ++i) {
      e.j_v[i] = blocks[i]->head<3>();
      e.j_w[i] = blocks[i]->tail<3>();
      e.body[i] = bodies[i] >= 0 ? bodies[i] : none;
      e.w_v[i].setZero();
      e.w_w[i].setZero();
      if (bodies[i] < 0) continue;
      const SolverBody& b = p.bodies[static_cast<std::size_t>(bodies[i])];
      e.w_v[i] = b.inv_mass * e.j_v[i];
      e.w_w[i] = b.inv_inertia * e.j_w[i];
    }
    coupled_.push_back(e);
  }
  const auto signed_n = static_cast<std::ptrdiff_t>(n);
  parallel::forEach(signed_n, threads, kColourRows, [&](std::ptrdiff_t ip) {
    const auto pos = static_cast<std::size_t>(ip);
    const Row& r = p.rows[static_cast<std::size_t>(order_[pos])];
    CompactRow& c = rows_[pos];
    c.ja_v = r.Ja.head<3>();
    c.ja_w = r.Ja.tail<3>();
    c.jb_v = r.Jb.head<3>();
    c.jb_w = r.Jb.tail<3>();
    double diag = r.cfm;
    c.a = none;
    c.wa_v.setZero();
    c.wa_w.setZero();
    if (r.body_a >= 0) {
      const SolverBody& b = p.bodies[static_cast<std::size_t>(r.body_a)];
      c.a = r.body_a;
      c.wa_v = b.inv_mass * c.ja_v;
      c.wa_w = b.inv_inertia * c.ja_w;
      diag += c.ja_v.dot(c.wa_v) + c.ja_w.dot(c.wa_w);
    }
    c.b = none;
    c.wb_v.setZero();
    c.wb_w.setZero();
    if (r.body_b >= 0) {
      const SolverBody& b = p.bodies[static_cast<std::size_t>(r.body_b)];
      c.b = r.body_b;
      c.wb_v = b.inv_mass * c.jb_v;
      c.wb_w = b.inv_inertia * c.jb_w;
      diag += c.jb_v.dot(c.wb_v) + c.jb_w.dot(c.wb_w);
    }
    if (coupled_of[pos] >= 0) {
      const CoupledEnds& e = coupled_[static_cast<std::size_t>(coupled_of[pos])];
      for (int i = 0; i < 2; ++i) diag += e.j_v[i].dot(e.w_v[i]) + e.j_w[i].dot(e.w_w[i]);
    }
    c.inv_diag = diag > 0.0 ? 1.0 / diag : 0.0;  // 0: a row that touches no movable body
    c.diag = diag > 0.0 ? diag / settings.sor : 0.0;
    c.target = r.target(p.h);
    c.cfm = r.cfm;
    c.lo = r.lo;
    c.hi = r.hi;
    c.mu = r.mu;
    c.normal = r.kind == RowKind::Friction && r.normal >= 0
                   ? position_[static_cast<std::size_t>(r.normal)]
                   : -1;  // friction without a normal row keeps its own bounds
    lambda_[pos] = p.lambda[static_cast<std::size_t>(order_[pos])];
  });

  double* lambda = lambda_.data();
  const auto bounds = [&](const CompactRow& c, double& lo, double& hi) {
    if (c.normal >= 0) {
      hi = c.mu * std::max(0.0, lambda[c.normal]);
      lo = -hi;
    } else {
      lo = c.lo;
      hi = c.hi;
    }
  };
  const auto slack = [&](const CompactRow& c, double l) {
    const Velocity& a = velocities_[static_cast<std::size_t>(c.a)];
    const Velocity& b = velocities_[static_cast<std::size_t>(c.b)];
    return c.ja_v.dot(a.v) + c.ja_w.dot(a.w) + c.jb_v.dot(b.v) + c.jb_w.dot(b.w) - c.target +
           c.cfm * l;
  };
  // The slot of "no body" is only read: rows of one colour may share it, so it is never written.
  const auto apply = [&](const CompactRow& c, double delta) {
    if (c.a != none) {
      Velocity& a = velocities_[static_cast<std::size_t>(c.a)];
      a.v += delta * c.wa_v;
      a.w += delta * c.wa_w;
    }
    if (c.b != none) {
      Velocity& b = velocities_[static_cast<std::size_t>(c.b)];
      b.v += delta * c.wb_v;
      b.w += delta * c.wb_w;
    }
  };
  // The rows at sweep position k with a coupled row's further ends (CoupledEnds): slack and apply
  // of the whole row. Only the rows' first two ends are in rows_, so the sweep's hot path stays
  // as it is for contacts; a coupled row is an item of its own (relaxItem).
  const auto coupledAt = [&](std::size_t k) -> const CoupledEnds* {
    if (coupled_.empty() || coupled_of_[k] < 0) return nullptr;
    return &coupled_[static_cast<std::size_t>(coupled_of_[k])];
  };
  const auto slackAt = [&](std::size_t k, double l) {
    double w = slack(rows_[k], l);
    if (const CoupledEnds* e = coupledAt(k))
      for (int i = 0; i < 2; ++i) {
        const Velocity& u = velocities_[static_cast<std::size_t>(e->body[i])];
        w += e->j_v[i].dot(u.v) + e->j_w[i].dot(u.w);
      }
    return w;
  };
  const auto applyAt = [&](std::size_t k, double delta) {
    apply(rows_[k], delta);
    if (const CoupledEnds* e = coupledAt(k))
      for (int i = 0; i < 2; ++i) {
        if (e->body[i] == none) continue;
        Velocity& u = velocities_[static_cast<std::size_t>(e->body[i])];
        u.v += delta * e->w_v[i];
        u.w += delta * e->w_w[i];
      }
  };

  // Warm start: apply the initial guess, clamped to the bounds it must respect; group by group
  // (rows of a colour share no body, and a friction row's normal is in an earlier group).
  const auto warm = [&](std::size_t k) {
    double lo, hi;
    bounds(rows_[k], lo, hi);
    lambda[k] = std::clamp(lambda[k], lo, hi);
    if (lambda[k] != 0.0) applyAt(k, lambda[k]);
  };
  buildItems(group_ends_);
  const auto warmItem = [&](int i) {
    const Item& item = items_[static_cast<std::size_t>(i)];
    for (int k = item.begin; k < item.begin + item.size; ++k) warm(static_cast<std::size_t>(k));
  };
  for (const Group& g : groups_) {
    if (g.parallel)
      parallel::forEach(g.size, threads, kParallelWarmRows,
                        [&](std::ptrdiff_t j) { warmItem(g.begin + static_cast<int>(j)); });
    else
      for (int j = 0; j < g.size; ++j) warmItem(g.begin + j);
  }

  // One row's update; returns its violation before the update, without a branch: |w| for a free
  // impulse, the part of w that pushes away from a bound the impulse sits at, and for an impulse
  // outside its (moved) bounds the distance to them in slack units. All are |next - l| / A_kk for
  // omega = 1. A row touching no movable body has inv_diag = 0 and never changes. Inlined into
  // each sweep: called through a function it cost 5 % on a pile of spheres.
  const double omega = settings.sor;
  const auto relax = [&](std::size_t k) __attribute__((always_inline)) {
    const CompactRow& c = rows_[k];
    double lo, hi;
    bounds(c, lo, hi);
    const double l = lambda[k];
    const double w = slack(c, l);
    const double next = std::clamp(l - omega * w * c.inv_diag, lo, hi);
    lambda[k] = next;
    apply(c, next - l);
    return std::abs(next - l) * c.diag;
  };
  // A coupled row, as relax does (off the hot path).
  const auto relaxCoupled = [&](std::size_t k) {
    double lo, hi;
    bounds(rows_[k], lo, hi);
    const double l = lambda[k];
    const double next = std::clamp(l - omega * slackAt(k, l) * rows_[k].inv_diag, lo, hi);
    lambda[k] = next;
    applyAt(k, next - l);
    return std::abs(next - l) * rows_[k].diag;
  };
  // A block of equality rows: all its impulses at once, lambda_b -= omega A_bb^-1 w_b, so the
  // block's rows hold together after its update. Its violation: the largest of its rows'.
  const auto relaxItem = [&](int i) {
    const Item& item = items_[static_cast<std::size_t>(i)];
    if (item.block < 0) {
      const auto k = static_cast<std::size_t>(item.begin);
      return coupledAt(k) ? relaxCoupled(k) : relax(k);
    }
    BlockVector w = BlockVector::Zero();
    for (int j = 0; j < item.size; ++j) {
      const auto k = static_cast<std::size_t>(item.begin + j);
      w(j) = slack(rows_[k], lambda[k]);
    }
    const BlockVector delta = -omega * (block_inverse_[static_cast<std::size_t>(item.block)] * w);
    double violation = 0.0;
    for (int j = 0; j < item.size; ++j) {
      const auto k = static_cast<std::size_t>(item.begin + j);
      lambda[k] += delta(j);
      apply(rows_[k], delta(j));
      violation = std::max(violation, std::abs(delta(j)) * rows_[k].diag);
    }
    return violation;
  };

  // Sweeps alternate direction (symmetric Gauss-Seidel): a one-way sweep leaves a bias towards
  // the rows it visits last, which tilts a symmetric pile of contacts. A backward sweep visits the
  // groups in reverse, and a serial group's items in reverse. The items of a colour share no body:
  // the threads split them, and the result is the same for any number of threads. With no block and
  // no coupled row, every item is its row and the sweep calls relax directly (the item's
  // indirection cost 10 % on a pile of spheres).
  report.converged = false;
  const int iterations = settings.iterations;
  const auto sweeps = [&](auto&& relaxOne) {
    if (n < kColourRows) {
      const int count = static_cast<int>(items_.size());
      for (int it = 0; it < iterations; ++it) {
        const bool forward = it % 2 == 0;
        double sweep_violation = 0.0;  // of each item as it is visited, before its update
        for (int visit = 0; visit < count; ++visit)
          sweep_violation =
              std::max(sweep_violation, relaxOne(forward ? visit : count - 1 - visit));
        report.iterations = it + 1;
        if (sweep_violation <= settings.tolerance) {
          report.converged = true;
          break;
        }
      }
    } else {
      const auto group_count = static_cast<std::ptrdiff_t>(groups_.size());
      thread_violation_.assign(static_cast<std::size_t>(threads), 0.0);
      bool stop = false;
#pragma omp parallel num_threads(threads)
      for (int it = 0; it < iterations; ++it) {
        const bool forward = it % 2 == 0;
        double sweep_violation = 0.0;
        for (std::ptrdiff_t visit = 0; visit < group_count; ++visit) {
          const Group& g =
              groups_[static_cast<std::size_t>(forward ? visit : group_count - 1 - visit)];
          if (g.parallel) {
#pragma omp for schedule(static)
            for (int j = g.begin; j < g.begin + g.size; ++j)
              sweep_violation = std::max(sweep_violation, relaxOne(j));
          } else {
#pragma omp single
            for (int j = 0; j < g.size; ++j) {
              const int k = forward ? g.begin + j : g.begin + g.size - 1 - j;
              sweep_violation = std::max(sweep_violation, relaxOne(k));
            }
          }
        }
        thread_violation_[static_cast<std::size_t>(omp_get_thread_num())] = sweep_violation;
#pragma omp barrier
#pragma omp single
        {
          report.iterations = it + 1;
          stop = *std::max_element(thread_violation_.begin(), thread_violation_.end()) <=
                 settings.tolerance;
          report.converged = stop;
        }
        if (stop) break;  // read by every thread after the single's barrier: all leave together
      }
    }
  };
  if (block_inverse_.empty() && coupled_.empty())
    sweeps([&](int k) { return relax(static_cast<std::size_t>(k)); });
  else
    sweeps(relaxItem);

  // Scatter the impulses and velocities; the residual is measured with them (a maximum, the
  // same in any order).
  parallel::forEach(signed_n, threads, kColourRows, [&](std::ptrdiff_t ip) {
    const auto pos = static_cast<std::size_t>(ip);
    p.lambda[static_cast<std::size_t>(order_[pos])] = lambda[pos];
  });
  parallel::forEach(static_cast<std::ptrdiff_t>(p.bodies.size()), threads, kColourRows,
                    [&](std::ptrdiff_t ii) {
                      const auto i = static_cast<std::size_t>(ii);
                      p.bodies[i].v = velocities_[i].v;
                      p.bodies[i].w = velocities_[i].w;
                    });
  const std::size_t chunks = n >= kColourRows ? static_cast<std::size_t>(threads) : 1;
  thread_violation_.assign(chunks, 0.0);
  parallel::forEach(static_cast<std::ptrdiff_t>(chunks), threads, 2, [&](std::ptrdiff_t c) {
    const auto chunk = static_cast<std::size_t>(c);
    double residual = 0.0;
    for (std::size_t k = n * chunk / chunks; k < n * (chunk + 1) / chunks; ++k) {
      double lo, hi;
      bounds(rows_[k], lo, hi);
      residual = std::max(residual, RowSystem::violation(lambda[k], lo, hi, slackAt(k, lambda[k])));
    }
    thread_violation_[chunk] = residual;
  });
  report.residual = *std::max_element(thread_violation_.begin(), thread_violation_.end());
  return report;
}

}  // namespace linx::solver
