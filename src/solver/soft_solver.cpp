#include "solver/soft_solver.hpp"

#include "parallel/parallel_for.hpp"
#include "solver/row_system.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <numbers>

namespace linx::solver {

namespace {

constexpr int kColours = GraphColouring::kColours;
/// Blocks of a colour from which it is split over the threads.
constexpr std::ptrdiff_t kParallelBlocks = 32;
/// Blocks from which prepare builds their rows over the threads.
constexpr std::ptrdiff_t kParallelPrepare = 256;

bool takesImpulses(const SoftSolver::Body& b) {
  return b.inv_mass > 0.0 || !b.inv_inertia.isZero(0.0);
}

}  // namespace

Softness Softness::of(double hertz, double damping_ratio, double h) {
  if (!(hertz > 0.0)) return Softness{};
  const double omega = 2.0 * std::numbers::pi * hertz;
  const double a1 = 2.0 * damping_ratio + h * omega;
  const double a2 = h * omega * a1;
  const double a3 = 1.0 / (1.0 + a2);
  return Softness{omega / a1, a2 * a3, a3};
}

void SoftSolver::prepare(std::span<const Row> rows, std::span<const double> lambda,
                         std::span<const std::uint8_t> active, std::span<const int> manifold,
                         std::span<const SolverBody> bodies, const Settings& settings) {
  settings_ = settings;
  const std::size_t n = rows.size();
  bodies_.resize(bodies.size() + 1);
  for (std::size_t i = 0; i < bodies.size(); ++i)
    bodies_[i] = Body{bodies[i].inv_mass, bodies[i].inv_inertia, bodies[i].v,
                      bodies[i].w,        Vec3::Zero(),          Vec3::Zero()};
  bodies_.back() = Body{};
  lambda_.assign(lambda.begin(), lambda.end());
  total_.resize(n);
  // The sweep's order: each contact point's normal row followed by its friction rows (friction's
  // bound follows the normal impulse just solved), the other rows as they come.
  order_.clear();
  frictions_.assign(n, -1);
  for (std::size_t k = 0; k < n; ++k)
    if (rows[k].kind == RowKind::Friction && rows[k].normal >= 0) {
      const auto normal = static_cast<std::size_t>(rows[k].normal);
      if (frictions_[normal] < 0) frictions_[normal] = static_cast<int>(k);  // the first
    }
  for (std::size_t k = 0; k < n; ++k) {
    if (rows[k].kind == RowKind::Friction && rows[k].normal >= 0) continue;  // with its normal
    order_.push_back(static_cast<int>(k));
    if (const int f = frictions_[k]; f >= 0)
      for (std::size_t j = static_cast<std::size_t>(f);
           j < n && rows[j].kind == RowKind::Friction && rows[j].normal == static_cast<int>(k); ++j)
        order_.push_back(static_cast<int>(j));
  }
  for (std::size_t k = 0; k < n; ++k)  // a sleeping row keeps its impulse, in every substep
    total_[k] = active[k] ? 0.0 : lambda_[k] * settings.substeps;
  // Units (a contact point's rows, or a row alone) and blocks (a manifold's units, or a unit
  // alone) of the rows that act, by positions in order_.
  std::vector<int>& units = unit_scratch_;
  units.clear();
  std::size_t kept = 0;
  for (const int ok : order_) {
    const auto k = static_cast<std::size_t>(ok);
    const Row& r = rows[k];
    if (!active[k] || (r.body_a < 0 && r.body_b < 0)) continue;
    if (!(r.kind == RowKind::Friction && r.normal >= 0)) units.push_back(static_cast<int>(kept));
    order_[kept++] = ok;
  }
  order_.resize(kept);
  units.push_back(static_cast<int>(kept));
  std::vector<int>& blocks = block_scratch_;
  blocks.clear();
  for (std::size_t u = 0; u + 1 < units.size(); ++u) {
    const auto first = [&](std::size_t unit) -> std::size_t {
      return static_cast<std::size_t>(order_[static_cast<std::size_t>(units[unit])]);
    };
    const std::size_t k = first(u);
    const bool joins = u > 0 && manifold[k] >= 0 && manifold[first(u - 1)] == manifold[k] &&
                       rows[first(u - 1)].body_a == rows[k].body_a &&
                       rows[first(u - 1)].body_b == rows[k].body_b;
    if (!joins) blocks.push_back(static_cast<int>(u));
  }
  blocks.push_back(static_cast<int>(units.size()) - 1);
  // The compact rows, block by block in sweep order (colour by colour), so that a sweep reads
  // them in the order they are stored (in the order they came, a colour's rows lay scattered and
  // nearly every row a sweep read missed the cache: measured on 1,000 spheres). First where each
  // block's units and rows go, then the rows, the blocks split over the threads.
  const std::span<const int> sweep = colour(rows, units, blocks);
  blocks_.resize(sweep.size() + 1);
  units_.clear();
  std::vector<int>& first_row = block_rows_;
  first_row.resize(sweep.size());
  int count_rows = 0;
  for (std::size_t s = 0; s < sweep.size(); ++s) {
    const auto b = static_cast<std::size_t>(sweep[s]);
    blocks_[s] = static_cast<int>(units_.size());
    first_row[s] = count_rows;
    for (auto u = static_cast<std::size_t>(blocks[b]); u < static_cast<std::size_t>(blocks[b + 1]);
         ++u) {
      units_.push_back(count_rows);
      count_rows += units[u + 1] - units[u];
    }
  }
  blocks_.back() = static_cast<int>(units_.size());
  units_.push_back(count_rows);
  rows_.resize(static_cast<std::size_t>(count_rows));
  index_.resize(static_cast<std::size_t>(count_rows));
  compact_.assign(n, -1);
  parallel::forEach(
      static_cast<std::ptrdiff_t>(sweep.size()), settings.threads, kParallelPrepare,
      [&](std::ptrdiff_t s) {
        const auto b = static_cast<std::size_t>(sweep[static_cast<std::size_t>(s)]);
        int i = first_row[static_cast<std::size_t>(s)];
        for (int pos = units[static_cast<std::size_t>(blocks[b])];
             pos < units[static_cast<std::size_t>(blocks[b + 1])]; ++pos, ++i) {
          const auto k = static_cast<std::size_t>(order_[static_cast<std::size_t>(pos)]);
          rows_[static_cast<std::size_t>(i)] = compactRow(rows[k], manifold, static_cast<int>(s));
          index_[static_cast<std::size_t>(i)] = static_cast<int>(k);
          compact_[k] = i;
        }
      });
  sweeps_ = 0;
}

SoftSolver::CompactRow SoftSolver::compactRow(const Row& r, std::span<const int> manifold,
                                              int block) const {
  const int none = static_cast<int>(bodies_.size()) - 1;
  CompactRow c{};
  c.ja_v = r.Ja.head<3>();
  c.ja_w = r.Ja.tail<3>();
  c.jb_v = r.Jb.head<3>();
  c.jb_w = r.Jb.tail<3>();
  c.a = r.body_a >= 0 ? r.body_a : none;
  c.b = r.body_b >= 0 ? r.body_b : none;
  const Body& a = bodies_[static_cast<std::size_t>(c.a)];
  const Body& b = bodies_[static_cast<std::size_t>(c.b)];
  c.wa_v = a.inv_mass * c.ja_v;
  c.wa_w = a.inv_inertia * c.ja_w;
  c.wb_v = b.inv_mass * c.jb_v;
  c.wb_w = b.inv_inertia * c.jb_w;
  const double k_eff =
      c.ja_v.dot(c.wa_v) + c.ja_w.dot(c.wa_w) + c.jb_v.dot(c.wb_v) + c.jb_w.dot(c.wb_w) + r.cfm;
  c.mass = k_eff > 0.0 ? 1.0 / k_eff : 0.0;
  c.phi0 = r.phi;
  c.speed = r.speed;
  c.lo = r.lo;
  c.hi = r.hi;
  c.mu = r.mu;
  c.friction = r.kind == RowKind::Friction;
  c.normal = c.friction ? r.normal : -1;
  // A friction row's bound follows its manifold's normal rows: its block's units' first rows.
  c.manifold =
      c.friction && r.normal >= 0 && manifold[static_cast<std::size_t>(r.normal)] >= 0 ? block : -1;
  c.unilateral = r.kind == RowKind::Unilateral;
  c.positional = r.kind == RowKind::Bilateral || c.unilateral;
  c.moves_a = c.a != none && takesImpulses(a);
  c.moves_b = c.b != none && takesImpulses(b);
  c.rate0 = rate(c);
  return c;
}

std::span<const int> SoftSolver::colour(std::span<const Row> rows, std::span<const int> units,
                                        std::span<const int> blocks) {
  // First fit: a block takes the lowest colour that none of its moving bodies has yet; one with a
  // static or kinematic end starts at colour 1 (Box2D v3), so the contacts between moving bodies
  // are solved first and those holding them up after.
  const std::size_t count_blocks = blocks.size() - 1;
  const auto moves = [&](int body) {
    return body >= 0 && takesImpulses(bodies_[static_cast<std::size_t>(body)]);
  };
  colouring_.reset(bodies_.size());
  std::vector<int>& colour_of = colour_of_;
  colour_of.resize(count_blocks);
  std::array<int, kColours + 1> count{};
  for (std::size_t k = 0; k < count_blocks; ++k) {
    const Row& r = rows[static_cast<std::size_t>(
        order_[static_cast<std::size_t>(units[static_cast<std::size_t>(blocks[k])])])];
    const bool moves_a = moves(r.body_a), moves_b = moves(r.body_b);
    const int colour = colouring_.take(moves_a ? r.body_a : -1, moves_b ? r.body_b : -1,
                                       moves_a && moves_b ? 0 : 1);
    colour_of[k] = colour;
    ++count[static_cast<std::size_t>(colour)];
  }
  // Colours in use (empty ones dropped), then the overflow set; blocks in order within each.
  std::array<int, kColours + 1> fill{};
  colour_start_.assign(1, 0);
  for (int c = 0; c <= kColours; ++c) {
    const int size = count[static_cast<std::size_t>(c)];
    if (size == 0 && c < kColours) continue;
    fill[static_cast<std::size_t>(c)] = colour_start_.back();
    colour_start_.push_back(colour_start_.back() + size);
  }
  std::vector<int>& order = sweep_blocks_;
  order.resize(count_blocks);
  for (std::size_t k = 0; k < count_blocks; ++k)
    order[static_cast<std::size_t>(fill[static_cast<std::size_t>(colour_of[k])]++)] =
        static_cast<int>(k);
  return order;
}

template <class F>
void SoftSolver::eachBlock(bool forward, F&& block) {
  const int colours = static_cast<int>(colour_start_.size()) - 2;  // the overflow set apart
  const auto colourAt = [&](int phase) {
    return static_cast<std::size_t>(forward ? phase : colours - 1 - phase);
  };
  parallel::forEachInPhases(
      colours, settings_.threads, kParallelBlocks,
      [&](int phase) {
        const std::size_t c = colourAt(phase);
        return static_cast<std::ptrdiff_t>(colour_start_[c + 1] - colour_start_[c]);
      },
      [&](int phase, std::ptrdiff_t i) {
        block(static_cast<std::size_t>(colour_start_[colourAt(phase)] + i));
      });
  const auto overflow = static_cast<std::size_t>(colours);
  for (int k = colour_start_[overflow]; k < colour_start_[overflow + 1]; ++k)
    block(static_cast<std::size_t>(k));
}

double SoftSolver::phi(const CompactRow& c) const {
  const Body& a = bodies_[static_cast<std::size_t>(c.a)];
  const Body& b = bodies_[static_cast<std::size_t>(c.b)];
  return c.phi0 + c.ja_v.dot(a.dp) + c.ja_w.dot(a.dq) + c.jb_v.dot(b.dp) + c.jb_w.dot(b.dq);
}

double SoftSolver::rate(const CompactRow& c) const {
  const Body& a = bodies_[static_cast<std::size_t>(c.a)];
  const Body& b = bodies_[static_cast<std::size_t>(c.b)];
  return c.ja_v.dot(a.v) + c.ja_w.dot(a.w) + c.jb_v.dot(b.v) + c.jb_w.dot(b.w);
}

void SoftSolver::apply(const CompactRow& c, double delta) {
  // Only moving ends are written: a colour's blocks share the static and kinematic bodies.
  if (c.moves_a) {
    Body& a = bodies_[static_cast<std::size_t>(c.a)];
    a.v += delta * c.wa_v;
    a.w += delta * c.wa_w;
  }
  if (c.moves_b) {
    Body& b = bodies_[static_cast<std::size_t>(c.b)];
    b.v += delta * c.wb_v;
    b.w += delta * c.wb_w;
  }
}

void SoftSolver::move(double h) {
  for (std::size_t i = 0; i + 1 < bodies_.size(); ++i) {
    bodies_[i].dp += h * bodies_[i].v;
    bodies_[i].dq += h * bodies_[i].w;
  }
}

void SoftSolver::warmStart() {
  eachBlock(true, [&](std::size_t k) {
    const auto end = static_cast<std::size_t>(units_[static_cast<std::size_t>(blocks_[k + 1])]);
    for (auto i = static_cast<std::size_t>(units_[static_cast<std::size_t>(blocks_[k])]); i < end;
         ++i) {
      const double l = lambda_[static_cast<std::size_t>(index_[i])];
      if (l != 0.0) apply(rows_[i], l);
    }
  });
}

void SoftSolver::sweep(bool bias) {
  // Every other sweep visits the colours, and each manifold's contact points, backwards (each
  // point's rows still in order): a one-way sweep leaves a bias towards the rows it visits last,
  // which walks a stack sideways.
  const bool forward = (sweeps_++ % 2) == 0;
  eachBlock(forward, [&](std::size_t k) { solveBlock(k, forward, bias); });
}

void SoftSolver::solveBlock(std::size_t k, bool forward, bool bias) {
  // A block's rows share their two bodies: their velocities stay in registers while its units are
  // solved, and are written back once (only the moving ends: a colour's blocks share the static
  // and kinematic ones).
  const auto begin = static_cast<std::size_t>(blocks_[k]);
  const auto end = static_cast<std::size_t>(blocks_[k + 1]);
  const CompactRow& first = rows_[static_cast<std::size_t>(units_[begin])];
  Body& a = bodies_[static_cast<std::size_t>(first.a)];
  Body& b = bodies_[static_cast<std::size_t>(first.b)];
  Ends ends{a.v, a.w, b.v, b.w, a.dp, a.dq, b.dp, b.dq};
  for (std::size_t visit = begin; visit < end; ++visit)
    solveUnit(forward ? visit : end - 1 - (visit - begin), bias, ends);
  if (first.moves_a) {
    a.v = ends.va;
    a.w = ends.wa;
  }
  if (first.moves_b) {
    b.v = ends.vb;
    b.w = ends.wb;
  }
}

void SoftSolver::solveUnit(std::size_t u, bool bias, Ends& e) {
  const double h = settings_.h;
  double bound = -1.0;  // the friction rows' bound, once the unit's normal row is solved
  for (auto i = static_cast<std::size_t>(units_[u]); i < static_cast<std::size_t>(units_[u + 1]);
       ++i) {
    const CompactRow& c = rows_[i];
    double& l = lambda_[static_cast<std::size_t>(index_[i])];
    double lo = c.lo, hi = c.hi;
    if (c.friction && c.normal >= 0) {
      if (bound < 0.0) bound = frictionBound(c);
      hi = bound;
      lo = -hi;
    }
    double target = 0.0;  // the bias velocity
    double mass_scale = 1.0, impulse_scale = 0.0;
    if (c.positional) {
      const double error =
          c.phi0 + c.ja_v.dot(e.dpa) + c.ja_w.dot(e.dqa) + c.jb_v.dot(e.dpb) + c.jb_w.dot(e.dqb);
      if (c.unilateral && error > 0.0) {
        target = error / h;  // a gap: it may close within the substep, no further
      } else if (bias) {
        const Softness& soft = settings_.contact;
        target = soft.bias_rate * error;
        target = std::max(target, -settings_.max_push_out);
        mass_scale = soft.mass_scale;
        impulse_scale = soft.impulse_scale;
      }
    }
    const double rate = c.ja_v.dot(e.va) + c.ja_w.dot(e.wa) + c.jb_v.dot(e.vb) + c.jb_w.dot(e.wb);
    const double delta = -c.mass * mass_scale * (rate - c.speed + target) - impulse_scale * l;
    const double next = std::clamp(l + delta, lo, hi);
    const double applied = next - l;
    if (c.moves_a) {
      e.va += applied * c.wa_v;
      e.wa += applied * c.wa_w;
    }
    if (c.moves_b) {
      e.vb += applied * c.wb_v;
      e.wb += applied * c.wb_w;
    }
    l = next;
  }
}

void SoftSolver::accumulate() {
  for (std::size_t i = 0; i < rows_.size(); ++i) {
    const auto k = static_cast<std::size_t>(index_[i]);
    total_[k] += lambda_[k];
  }
}

double SoftSolver::frictionBound(const CompactRow& c) const {
  if (c.manifold < 0) return c.mu * std::max(0.0, lambda_[static_cast<std::size_t>(c.normal)]);
  const auto block = static_cast<std::size_t>(c.manifold);
  const int first = blocks_[block], last = blocks_[block + 1];
  double sum = 0.0;
  for (int u = first; u < last; ++u)
    sum +=
        std::max(0.0, lambda_[static_cast<std::size_t>(
                          index_[static_cast<std::size_t>(units_[static_cast<std::size_t>(u)])])]);
  return c.mu * sum / (last - first);
}

void SoftSolver::restitution(std::span<const Bounce> bounces) {
  for (const Bounce& b : bounces) {
    const int i = compact_[static_cast<std::size_t>(b.row)];
    if (i < 0) continue;
    const CompactRow& c = rows_[static_cast<std::size_t>(i)];
    const auto k = static_cast<std::size_t>(b.row);
    if (c.rate0 > -b.threshold || total_[k] == 0.0) continue;
    const double next = std::max(0.0, lambda_[k] - c.mass * (rate(c) + b.e * c.rate0));
    apply(c, next - lambda_[k]);
    total_[k] += next - lambda_[k];
    lambda_[k] = next;
  }
}

double SoftSolver::residual() const {
  double worst = 0.0;
  for (std::size_t i = 0; i < rows_.size(); ++i) {
    const CompactRow& c = rows_[i];
    const double l = lambda_[static_cast<std::size_t>(index_[i])];
    double lo = c.lo, hi = c.hi;
    if (c.friction && c.normal >= 0) {
      hi = frictionBound(c);
      lo = -hi;
    }
    double w = rate(c) - c.speed;
    if (c.unilateral) {
      const double error = phi(c);
      if (error > 0.0) w += error / settings_.h;
    }
    worst = std::max(worst, RowSystem::violation(l, lo, hi, w));
  }
  return worst;
}

}  // namespace linx::solver
