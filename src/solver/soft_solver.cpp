#include "solver/soft_solver.hpp"

// The wide sweep's helpers take and return four-lane vectors; they are inlined within this file,
// so no call crosses the ABI that GCC warns about (a 32-byte vector passed without AVX).
#pragma GCC diagnostic ignored "-Wpsabi"

#include "parallel/parallel_for.hpp"
#include "solver/row_system.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <numbers>

// The bundle kernels in two versions, AVX2 and the baseline, picked at load time (GCC). Clang
// wants target_clones on a function's first declaration, in the header: built with clang (the fuzz
// harnesses) they are compiled once, for the baseline.
#if defined(__clang__)
#define LINX_AVX2_CLONES
#else
#define LINX_AVX2_CLONES __attribute__((target_clones("avx2", "default")))
#endif

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
  lambda_.push_back(0.0);  // the spare impulse of a wide row's empty lanes, always 0
  push_.assign(lambda_.size(), 0.0);
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
  parallel::forEach(static_cast<std::ptrdiff_t>(sweep.size()), settings.threads, kParallelPrepare,
                    [&](std::ptrdiff_t s) {
                      const auto b = static_cast<std::size_t>(sweep[static_cast<std::size_t>(s)]);
                      int i = first_row[static_cast<std::size_t>(s)];
                      for (int pos = units[static_cast<std::size_t>(blocks[b])];
                           pos < units[static_cast<std::size_t>(blocks[b + 1])]; ++pos, ++i) {
                        const auto k =
                            static_cast<std::size_t>(order_[static_cast<std::size_t>(pos)]);
                        compactRow(rows[k], lambda_[k], manifold, static_cast<int>(s),
                                   rows_[static_cast<std::size_t>(i)]);
                        index_[static_cast<std::size_t>(i)] = static_cast<int>(k);
                        compact_[k] = i;
                      }
                    });
  buildBundles();
  sweeps_ = 0;
}

bool SoftSolver::fitsBundle(std::size_t s) const {
  for (auto u = static_cast<std::size_t>(blocks_[s]); u < static_cast<std::size_t>(blocks_[s + 1]);
       ++u) {
    const auto first = static_cast<std::size_t>(units_[u]);
    if (units_[u + 1] - units_[u] != 3) return false;
    const CompactRow& n = rows_[first];
    if (!n.unilateral || !n.positional || n.friction) return false;
    for (std::size_t i = first + 1; i < first + 3; ++i)
      if (!rows_[i].friction || rows_[i].manifold != static_cast<int>(s) ||
          rows_[i].normal != index_[first])
        return false;
  }
  return true;
}

void SoftSolver::buildBundles() {
  const int none = static_cast<int>(bodies_.size()) - 1;
  bundles_.clear();
  tasks_.clear();
  task_start_.assign(1, 0);
  // Which blocks go in which bundle: a colour's blocks in order, kLanes at a time; blocks that
  // are not all contact points, and the overflow set, are solved alone.
  lane_block_.clear();
  std::size_t count_wide = 0;
  const std::size_t colours = colour_start_.size() - 1;  // the overflow set too
  for (std::size_t c = 0; c < colours; ++c) {
    const bool overflow = c + 1 == colours;
    std::vector<int>& alone = alone_scratch_;
    alone.clear();
    Bundle bundle;
    int lanes = 0;
    const auto close = [&] {
      if (lanes == 0) return;
      for (int l = lanes; l < kLanes; ++l) {
        bundle.a[static_cast<std::size_t>(l)] = bundle.b[static_cast<std::size_t>(l)] = none;
        lane_block_.push_back(-1);
      }
      bundle.first = static_cast<int>(count_wide);
      count_wide += 3 * static_cast<std::size_t>(bundle.units);
      tasks_.push_back(static_cast<int>(bundles_.size()));
      bundles_.push_back(bundle);
      bundle = Bundle{};
      lanes = 0;
    };
    for (int s = colour_start_[c]; s < colour_start_[c + 1]; ++s) {
      const auto k = static_cast<std::size_t>(s);
      if (overflow || !settings_.wide || !fitsBundle(k)) {
        alone.push_back(-1 - s);
        continue;
      }
      const CompactRow& r =
          rows_[static_cast<std::size_t>(units_[static_cast<std::size_t>(blocks_[k])])];
      const auto l = static_cast<std::size_t>(lanes);
      bundle.a[l] = r.a;
      bundle.b[l] = r.b;
      bundle.moves_a[l] = r.moves_a;
      bundle.moves_b[l] = r.moves_b;
      bundle.count[l] = blocks_[k + 1] - blocks_[k];
      bundle.units = std::max(bundle.units, bundle.count[l]);
      lane_block_.push_back(s);
      if (++lanes == kLanes) close();
    }
    close();
    tasks_.insert(tasks_.end(), alone.begin(), alone.end());
    task_start_.push_back(static_cast<int>(tasks_.size()));
  }
  // The wide rows, the bundles split over the threads.
  wide_.resize(count_wide);
  parallel::forEach(static_cast<std::ptrdiff_t>(bundles_.size()), settings_.threads,
                    kParallelPrepare / kLanes,
                    [&](std::ptrdiff_t b) { fillBundle(static_cast<std::size_t>(b)); });
}

void SoftSolver::clearLane(WideRow& w, std::size_t l) {
  for (int d = 0; d < 3; ++d) {
    w.ja_v[d][l] = w.ja_w[d][l] = w.jb_v[d][l] = w.jb_w[d][l] = 0.0;
    w.wa_v[d][l] = w.wa_w[d][l] = w.wb_v[d][l] = w.wb_w[d][l] = 0.0;
  }
  w.mass[l] = w.phi0[l] = w.speed[l] = w.lo[l] = w.hi[l] = w.mu[l] = w.spring[l] = 0.0;
}

void SoftSolver::fillBundle(std::size_t k) {
  // Each lane is written field by field (clearing the whole wide row first was 40 % of this).
  // Lane l of unit j's rows from the lane's block's unit j (zero, and the spare impulse, where
  // the block has fewer units).
  const int spare = static_cast<int>(lambda_.size()) - 1;
  const Bundle& bundle = bundles_[k];
  for (int j = 0; j < bundle.units; ++j)
    for (int r = 0; r < 3; ++r) {
      WideRow& w = wide_[static_cast<std::size_t>(bundle.first + 3 * j + r)];
      for (std::size_t l = 0; l < kLanes; ++l) {
        const int s = lane_block_[k * kLanes + l];
        if (s < 0 || j >= bundle.count[l]) {
          clearLane(w, l);
          w.lambda[l] = spare;
          continue;
        }
        const auto i = static_cast<std::size_t>(
            units_[static_cast<std::size_t>(blocks_[static_cast<std::size_t>(s)] + j)] + r);
        const CompactRow& c = rows_[i];
        for (int d = 0; d < 3; ++d) {
          w.ja_v[d][l] = c.ja_v[d];
          w.ja_w[d][l] = c.ja_w[d];
          w.jb_v[d][l] = c.jb_v[d];
          w.jb_w[d][l] = c.jb_w[d];
          w.wa_v[d][l] = c.wa_v[d];
          w.wa_w[d][l] = c.wa_w[d];
          w.wb_v[d][l] = c.wb_v[d];
          w.wb_w[d][l] = c.wb_w[d];
        }
        w.mass[l] = c.mass;
        w.phi0[l] = c.phi0;
        w.spring[l] = c.spring;
        w.speed[l] = c.speed;
        w.lo[l] = c.lo;
        w.hi[l] = c.hi;
        w.mu[l] = c.mu;
        w.lambda[l] = index_[i];
      }
    }
}

void SoftSolver::compactRow(const Row& r, double warm, std::span<const int> manifold, int block,
                            CompactRow& c) const {
  // Every field is written in place: value-initializing a local row first and copying it cost a
  // quarter of this function (rep stos; perf, 1,000 spheres).
  const int none = static_cast<int>(bodies_.size()) - 1;
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
  c.spring = settings_.spring_depth;
  if (const double omega2h = settings_.omega * settings_.omega * settings_.h;
      omega2h > 0.0 && c.mass > 0.0) {
    // Twice the depth the row's load (its warm start) sinks it to, k d h = lambda.
    const double load = std::max(0.0, warm);
    c.spring = std::max(c.spring, 2.0 * load / (c.mass * omega2h));
  }
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
void SoftSolver::eachTask(bool forward, F&& task) {
  const int colours = static_cast<int>(task_start_.size()) - 2;  // the overflow set apart
  const auto colourAt = [&](int phase) {
    return static_cast<std::size_t>(forward ? phase : colours - 1 - phase);
  };
  parallel::forEachInPhases(
      colours, settings_.threads, kParallelBlocks / kLanes,
      [&](int phase) {
        const std::size_t c = colourAt(phase);
        return static_cast<std::ptrdiff_t>(task_start_[c + 1] - task_start_[c]);
      },
      [&](int phase, std::ptrdiff_t i) {
        task(tasks_[static_cast<std::size_t>(task_start_[colourAt(phase)] + i)]);
      });
  const auto overflow = static_cast<std::size_t>(colours);
  for (int k = task_start_[overflow]; k < task_start_[overflow + 1]; ++k)
    task(tasks_[static_cast<std::size_t>(k)]);
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
    Body& b = bodies_[i];
    b.dp += h * (b.v + b.push_v);
    b.dq += h * (b.w + b.push_w);
    b.push_v.setZero();
    b.push_w.setZero();
  }
}

void SoftSolver::warmStart() {
  eachTask(true, [&](int task) {
    if (task >= 0) {
      warmStartBundle(static_cast<std::size_t>(task));
      return;
    }
    const auto k = static_cast<std::size_t>(-1 - task);
    const auto end = static_cast<std::size_t>(units_[static_cast<std::size_t>(blocks_[k + 1])]);
    for (auto i = static_cast<std::size_t>(units_[static_cast<std::size_t>(blocks_[k])]); i < end;
         ++i) {
      const double l = lambda_[static_cast<std::size_t>(index_[i])];
      if (l != 0.0) apply(rows_[i], l);
    }
  });
}

void SoftSolver::solve() {
  sweep(Pass::Solve);
}

void SoftSolver::relax() {
  sweep(Pass::Relax);
}

void SoftSolver::push() {
  // The sweep's kernels on the push velocities (zero at the start: move dropped the last ones)
  // and the push impulses: the bodies' velocities are swapped with them for the sweep.
  std::fill(push_.begin(), push_.end(), 0.0);
  const auto swap = [&] {
    for (Body& b : bodies_) {
      std::swap(b.v, b.push_v);
      std::swap(b.w, b.push_w);
    }
  };
  swap();
  sweep(Pass::Push);
  swap();
}

void SoftSolver::sweep(Pass pass) {
  // Every other sweep visits the colours, and each manifold's contact points, backwards (each
  // point's rows still in order): a one-way sweep leaves a bias towards the rows it visits last,
  // which walks a stack sideways.
  const bool forward = (sweeps_++ % 2) == 0;
  eachTask(forward, [&](int task) {
    if (task >= 0)
      solveBundle(static_cast<std::size_t>(task), forward, pass);
    else
      solveBlock(static_cast<std::size_t>(-1 - task), forward, pass);
  });
}

namespace {

// The wide kernel's arithmetic, the scalar path's to the bit: the same operations in the same
// order (Eigen's 3-vector dot is ((x0 y0 + x1 y1) + x2 y2), checked by SoftStep.WideIsScalar).
using Lanes = SoftSolver::Lanes;
[[gnu::always_inline]] inline Lanes dot(const Lanes* j, const Lanes (&x)[3]) {
  return j[0] * x[0] + j[1] * x[1] + j[2] * x[2];
}
[[gnu::always_inline]] inline void addScaled(Lanes (&x)[3], const Lanes& s, const Lanes* w) {
  for (int d = 0; d < 3; ++d) x[d] += s * w[d];
}

/// The impulses of a wide row's lanes.
template <class Impulses, class Indices>
[[gnu::always_inline]] inline Lanes gatherImpulses(const Impulses& lambda, const Indices& rows) {
  Lanes x;
  for (std::size_t l = 0; l < SoftSolver::kLanes; ++l)
    x[l] = lambda[static_cast<std::size_t>(rows[l])];
  return x;
}

/// A bundle's bodies' velocities, lane by lane.
struct WideVelocities {
  Lanes va[3], wa[3], vb[3], wb[3];
};

template <class Bodies, class Bundle>
[[gnu::always_inline]] inline void gather(const Bodies& bodies, const Bundle& bundle,
                                          WideVelocities& x) {
  for (std::size_t l = 0; l < SoftSolver::kLanes; ++l) {
    const SoftSolver::Body& a = bodies[static_cast<std::size_t>(bundle.a[l])];
    const SoftSolver::Body& b = bodies[static_cast<std::size_t>(bundle.b[l])];
    for (int d = 0; d < 3; ++d) {
      x.va[d][l] = a.v[d];
      x.wa[d][l] = a.w[d];
      x.vb[d][l] = b.v[d];
      x.wb[d][l] = b.w[d];
    }
  }
}

/// Writes the lanes' moving bodies back (a colour's blocks share the static and kinematic ones).
template <class Bodies, class Bundle>
[[gnu::always_inline]] inline void scatter(Bodies& bodies, const Bundle& bundle,
                                           const WideVelocities& x) {
  for (std::size_t l = 0; l < SoftSolver::kLanes; ++l) {
    if (bundle.moves_a[l]) {
      SoftSolver::Body& a = bodies[static_cast<std::size_t>(bundle.a[l])];
      a.v = Vec3(x.va[0][l], x.va[1][l], x.va[2][l]);
      a.w = Vec3(x.wa[0][l], x.wa[1][l], x.wa[2][l]);
    }
    if (bundle.moves_b[l]) {
      SoftSolver::Body& b = bodies[static_cast<std::size_t>(bundle.b[l])];
      b.v = Vec3(x.vb[0][l], x.vb[1][l], x.vb[2][l]);
      b.w = Vec3(x.wb[0][l], x.wb[1][l], x.wb[2][l]);
    }
  }
}

}  // namespace

LINX_AVX2_CLONES void SoftSolver::warmStartBundle(std::size_t k) {
  // The scalar warm start's arithmetic: a row whose impulse is zero adds nothing.
  const Bundle& bundle = bundles_[k];
  WideVelocities x;
  gather(bodies_, bundle, x);
  const Lanes zero{};
  const auto add = [&](Lanes(&v)[3], const Lanes& l, const Lanes* w)
      __attribute__((always_inline)) {
    for (int d = 0; d < 3; ++d) v[d] = l != zero ? v[d] + l * w[d] : v[d];
  };
  const auto end = static_cast<std::size_t>(bundle.first + 3 * bundle.units);
  for (auto i = static_cast<std::size_t>(bundle.first); i < end; ++i) {
    const WideRow& c = wide_[i];
    const Lanes l = gatherImpulses(lambda_, c.lambda);
    add(x.va, l, c.wa_v);
    add(x.wa, l, c.wa_w);
    add(x.vb, l, c.wb_v);
    add(x.wb, l, c.wb_w);
  }
  scatter(bodies_, bundle, x);
}

LINX_AVX2_CLONES void SoftSolver::solveBundle(std::size_t k, bool forward, Pass pass) {
  const bool push = pass == Pass::Push;
  const Bundle& bundle = bundles_[k];
  // Gather the lanes' bodies (structure of arrays).
  WideVelocities x;
  gather(bodies_, bundle, x);
  Lanes dpa[3], dqa[3], dpb[3], dqb[3];
  for (std::size_t l = 0; l < kLanes; ++l) {
    const Body& a = bodies_[static_cast<std::size_t>(bundle.a[l])];
    const Body& b = bodies_[static_cast<std::size_t>(bundle.b[l])];
    for (int d = 0; d < 3; ++d) {
      dpa[d][l] = a.dp[d];
      dqa[d][l] = a.dq[d];
      dpb[d][l] = b.dp[d];
      dqb[d][l] = b.dq[d];
    }
  }
  Lanes count{};  // each lane's units, 1 for an empty lane
  for (std::size_t l = 0; l < kLanes; ++l) count[l] = std::max(1, bundle.count[l]);
  const Softness& soft = settings_.contact;
  const double h = settings_.h;
  const Lanes zero{}, one = zero + 1.0;
  std::vector<double>& impulses = push ? push_ : lambda_;
  const auto load = [&](const WideRow& w) __attribute__((always_inline)) {
    return gatherImpulses(impulses, w.lambda);
  };
  const auto store = [&](const WideRow& w, const Lanes& x, int unit)
      __attribute__((always_inline)) {
    for (std::size_t l = 0; l < kLanes; ++l)
      if (unit < bundle.count[l]) impulses[static_cast<std::size_t>(w.lambda[l])] = x[l];
  };
  const auto solveRow = [&](const WideRow& c, Lanes& l, const Lanes& target, const Lanes& speed,
                            const Lanes& mass_scale, const Lanes& impulse_scale, const Lanes& lo,
                            const Lanes& hi) __attribute__((always_inline)) {
    const Lanes rate =
        dot(c.ja_v, x.va) + dot(c.ja_w, x.wa) + dot(c.jb_v, x.vb) + dot(c.jb_w, x.wb);
    const Lanes delta = -c.mass * mass_scale * (rate - speed + target) - impulse_scale * l;
    Lanes next = l + delta;  // std::clamp(next, lo, hi)
    next = next < lo ? lo : (hi < next ? hi : next);
    const Lanes applied = next - l;
    addScaled(x.va, applied, c.wa_v);
    addScaled(x.wa, applied, c.wa_w);
    addScaled(x.vb, applied, c.wb_v);
    addScaled(x.wb, applied, c.wb_w);
    l = next;
  };
  for (int visit = 0; visit < bundle.units; ++visit) {
    const int unit = forward ? visit : bundle.units - 1 - visit;
    const WideRow* rows = &wide_[static_cast<std::size_t>(bundle.first + 3 * unit)];
    // A lane whose block has fewer units visits nothing here: its rows have zero Jacobians and
    // mass, so nothing moves, and its impulses are not stored.
    {
      const WideRow& c = rows[0];
      Lanes l = load(c);
      const Lanes error =
          c.phi0 + dot(c.ja_v, dpa) + dot(c.ja_w, dqa) + dot(c.jb_v, dpb) + dot(c.jb_w, dqb);
      const auto gap = error > zero;
      // The spring's share of the error, and the push's (deeper than spring_depth).
      const Lanes deepest = zero - c.spring;
      const Lanes held = error < deepest ? deepest : error;  // std::max(error, -spring_depth)
      const Lanes beyond = error - held;
      Lanes target = zero, mass_scale = one, impulse_scale = zero, speed = c.speed;
      if (pass != Pass::Relax) {
        const Lanes part = push ? beyond : held;
        Lanes pushed = soft.bias_rate * part;  // std::max(pushed, -max_push_out)
        pushed = pushed < -settings_.max_push_out ? zero - settings_.max_push_out : pushed;
        const auto acts = part < zero;
        target = acts ? pushed : zero;
        mass_scale = acts ? zero + soft.mass_scale : one;
        impulse_scale = acts ? zero + soft.impulse_scale : zero;
      }
      if (push) speed = zero;
      if (!push) {
        target = gap ? error / h : target;  // a gap: it may close within the substep, no further
        mass_scale = gap ? one : mass_scale;
        impulse_scale = gap ? zero : impulse_scale;
      }
      solveRow(c, l, target, speed, mass_scale, impulse_scale, c.lo, c.hi);
      store(c, l, unit);
    }
    if (push) continue;
    // The friction rows' bound: mu times the mean normal impulse of the lane's manifold.
    Lanes sum = zero;
    for (int j = 0; j < bundle.units; ++j) {
      const Lanes n = load(wide_[static_cast<std::size_t>(bundle.first + 3 * j)]);
      sum += zero < n ? n : zero;  // std::max(0.0, n)
    }
    const Lanes bound = rows[1].mu * sum / count;
    for (int r = 1; r < 3; ++r) {
      const WideRow& c = rows[r];
      Lanes l = load(c);
      solveRow(c, l, zero, c.speed, one, zero, zero - bound, bound);
      store(c, l, unit);
    }
  }
  scatter(bodies_, bundle, x);
}

void SoftSolver::solveBlock(std::size_t k, bool forward, Pass pass) {
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
    solveUnit(forward ? visit : end - 1 - (visit - begin), pass, ends);
  if (first.moves_a) {
    a.v = ends.va;
    a.w = ends.wa;
  }
  if (first.moves_b) {
    b.v = ends.vb;
    b.w = ends.wb;
  }
}

void SoftSolver::solveUnit(std::size_t u, Pass pass, Ends& e) {
  const double h = settings_.h;
  const bool push = pass == Pass::Push;
  double bound = -1.0;  // the friction rows' bound, once the unit's normal row is solved
  for (auto i = static_cast<std::size_t>(units_[u]); i < static_cast<std::size_t>(units_[u + 1]);
       ++i) {
    const CompactRow& c = rows_[i];
    // A push moves only along the penetrating rows: a unilateral position error (a contact's).
    if (push && !(c.positional && c.unilateral && !c.friction)) continue;
    double& l = (push ? push_ : lambda_)[static_cast<std::size_t>(index_[i])];
    double lo = c.lo, hi = c.hi;
    if (c.friction && c.normal >= 0) {
      if (bound < 0.0) bound = frictionBound(c);
      hi = bound;
      lo = -hi;
    }
    double target = 0.0;  // the bias velocity
    double speed = push ? 0.0 : c.speed;
    double mass_scale = 1.0, impulse_scale = 0.0;
    if (c.positional) {
      const double error =
          c.phi0 + c.ja_v.dot(e.dpa) + c.ja_w.dot(e.dqa) + c.jb_v.dot(e.dpb) + c.jb_w.dot(e.dqb);
      // The spring's share of the error, and the push's (deeper than spring_depth).
      const double held = std::max(error, -c.spring);
      const double beyond = error - held;
      if (c.unilateral && error > 0.0) {
        if (!push) target = error / h;  // a gap: it may close within the substep, no further
      } else if (pass != Pass::Relax) {
        const double part = push ? beyond : held;
        if (part < 0.0) {
          const Softness& soft = settings_.contact;
          target = soft.bias_rate * part;
          target = std::max(target, -settings_.max_push_out);
          mass_scale = soft.mass_scale;
          impulse_scale = soft.impulse_scale;
        }
      }
    }
    const double rate = c.ja_v.dot(e.va) + c.ja_w.dot(e.wa) + c.jb_v.dot(e.vb) + c.jb_w.dot(e.wb);
    const double delta = -c.mass * mass_scale * (rate - speed + target) - impulse_scale * l;
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
