// The row solver of the soft step (docs/solver.md, "The soft step"; Catto's soft step of Box2D
// v3, Macklin et al. "Small Steps", 2019). The rows are prepared once per step; each substep of
// length h then warm-starts them, solves them once with a soft position bias, pushes the deep
// penetrations out through push velocities of their own, moves the positions by both, and
// relaxes the rows once without the bias.
//
// A row's position error follows the bodies within the step without a new collision pass: with
// dx the translation and rotation vector each body made since the step began,
//   phi = phi0 + J_a dx_a + J_b dx_b.
// Soft constraint (a spring-damper on the row, stable for any h): with omega = 2 pi f and zeta,
//   a1 = 2 zeta + h omega, a2 = h omega a1, a3 = 1 / (1 + a2),
//   bias rate = omega / a1, mass scale = a2 a3, impulse scale = a3,
//   dlambda = -m_eff (mass_scale (J v - speed + bias_rate phi)) - impulse_scale lambda.
// The rows are contacts' (the joints are solved exactly, step/substep_joints). A row whose error
// is a gap (phi > 0: a speculative contact) is rigid: it lets the gap close within the substep, no
// further (bias phi / h). Friction rows are rigid and bounded by mu times the mean normal impulse
// of their manifold.
// The spring in the velocities carries the load and damps the sweeps; it holds a penetration to
// its row's `spring` depth (twice what the row's load sinks it to, at least
// Settings::spring_depth). What lies deeper is a split impulse: the same soft constraint acts on
// push velocities, which start at zero each substep, take impulses of their own (>= 0, no
// friction), move the positions with the velocities, and are then dropped. (With all of the
// penetration in the velocities, one relax sweep took out only part of the push for a box's four
// points or a stack: a box 1 mm deep at h = 1e-5 s left at 1.1 m/s.) A penetration is pushed out no
// faster than max_push_out.
//
// Graph colouring (Box2D v3's constraint graph): a contact's rows with the same two bodies (a
// manifold: all points of one shape pair) form a block; blocks are coloured so that no two of one
// colour move the same body (static and kinematic ends do not count, and contacts with one of them
// never take colour 0). The sweep solves the colours in turn, each colour's blocks split over the
// threads; blocks that find no colour (a body in more than 64 of them) are solved last, in order,
// on one thread. The results are the same to the bit for any thread count.
//
// Wide sweep (Box2D v3's wide contact solver, in doubles): a colour's contact blocks are solved
// four at a time, one per lane of a structure-of-arrays copy of their rows, with AVX2 where the
// processor has it (a clone chosen at load time) and two SSE2 halves where it has not. Each lane
// does exactly the scalar path's operations, so the result is the scalar one to the bit
// (tests/test_soft_solver.cpp); blocks that are not all contact points, and the overflow set,
// take the scalar path.
#pragma once

#include <linx/row.hpp>
#include <linx/solver.hpp>

#include "solver/graph_colouring.hpp"
#include "solver/problem.hpp"

#include <array>
#include <cstdint>
#include <span>
#include <vector>

namespace linx::solver {

/// Spring-damper coefficients of a soft row for a substep h.
struct Softness {
  double bias_rate = 0.0;  ///< (1/s)
  double mass_scale = 1.0;
  double impulse_scale = 0.0;
  /// hertz <= 0: rigid (bias_rate 0, mass scale 1, impulse scale 0).
  static Softness of(double hertz, double damping_ratio, double h);
};

class SoftSolver {
 public:
  /// The wide sweep's lanes: blocks of one colour solved side by side.
  static constexpr int kLanes = 4;
  using Lanes = double __attribute__((vector_size(kLanes * sizeof(double))));

  /// The body state the substeps work on: velocities, and the motion since the step began.
  /// Aligned to cache lines: threads solving one colour write different bodies, and two bodies
  /// sharing a line made the two-thread sweep no faster than one (measured on 1,000 spheres).
  struct alignas(64) Body {
    double inv_mass = 0.0;
    Mat3 inv_inertia = Mat3::Zero();
    Vec3 v = Vec3::Zero(), w = Vec3::Zero();
    Vec3 dp = Vec3::Zero(), dq = Vec3::Zero();  ///< translation (m), rotation vector (rad)
    /// This substep's push velocities (the split impulse's), zero outside push and move.
    Vec3 push_v = Vec3::Zero(), push_w = Vec3::Zero();
  };

  struct Settings {
    Softness contact;
    double max_push_out = 3.0;  ///< (m/s)
    /// The deepest (m) a penetration is held by the spring in the velocities at least; a row
    /// holds twice the depth its load sinks it to (its warm-start impulse over m omega^2 h), if
    /// deeper. The push removes the rest.
    double spring_depth = 0.0;
    double omega = 0.0;  ///< the contacts' spring (rad/s)
    double h = 0.0;      ///< substep (s)
    int substeps = 1;    ///< of the step
    int threads = 1;     ///< worker threads of the sweeps
    /// Solve a colour's contact blocks kLanes at a time (false: one at a time, the scalar path
    /// that the wide one matches to the bit; for tests and measurements).
    bool wide = true;
  };

  /// Takes the rows (body indices into `bodies`, -1 for none; a friction row's `normal` an index
  /// into rows), their warm-start impulses, and the bodies at the start of the step.
  /// `active[k] == 0` leaves row k out (a sleeping island's): its impulse is kept as given.
  /// The rows are contacts' (the soft step solves the joints exactly, step/substep_joints).
  /// `manifold[k]` groups a contact's normal rows by shape pair (equal numbers, -1 for other
  /// rows): a friction row is bounded by mu times the mean normal impulse of its manifold.
  void prepare(std::span<const Row> rows, std::span<const double> lambda,
               std::span<const std::uint8_t> active, std::span<const int> manifold,
               std::span<const SolverBody> bodies, const Settings& settings);

  /// The bodies' substep state (as many as given to prepare): the caller integrates their
  /// velocities before warmStart and moves them (move) by v + push_v after the push.
  std::span<Body> bodies() { return std::span<Body>(bodies_).first(bodies_.size() - 1); }
  /// Records that every body moved by h times its velocity and push velocity (after the positions
  /// are integrated), and drops the push velocities.
  void move(double h);

  /// Applies the impulses to the bodies' velocities (the start of each substep).
  void warmStart();
  /// One sweep over the rows: a penetration with the soft constraint to at most spring_depth,
  /// a gap with its bias.
  void solve();
  /// One sweep of the soft constraint on the push velocities, for the penetrations deeper than
  /// spring_depth.
  void push();
  /// One rigid sweep over the rows, after the positions moved (the gaps' bias only).
  void relax();
  /// Adds this substep's impulses to the step's totals (after the relax pass).
  void accumulate();

  /// A contact's normal row that may bounce: restitution e, below `threshold` (m/s) no bounce.
  struct Bounce {
    int row;
    double e, threshold;
  };
  /// After the substeps: each normal row that approached faster than its threshold at the start
  /// of the step and took an impulse in it is pushed to leave at e times that approach speed.
  void restitution(std::span<const Bounce> bounces);

  /// The impulse of each row in the last substep (the next step's warm start).
  std::span<const double> lambda() const {
    return std::span<const double>(lambda_).first(lambda_.size() - 1);
  }
  /// The impulse of each row over the whole step (what contacts() reports).
  std::span<const double> total() const { return total_; }
  /// The largest complementarity violation of the last relax pass's impulses, as PGS reports it.
  double residual() const;

 private:
  enum class Pass { Solve, Push, Relax };
  struct CompactRow {
    Vec3 ja_v, ja_w, jb_v, jb_w;  // J of each end
    Vec3 wa_v, wa_w, wb_v, wb_w;  // M^-1 J^T
    double mass;                  // 1 / (J M^-1 J^T), 0 for a row that moves nothing
    double rate0;                 // J u at the start of the step
    double phi0, speed, lo, hi, mu;
    double spring;  // the deepest penetration (m) the spring holds in the velocities
    int a, b;       // body slots; an absent end points at a slot that stays zero
    int normal;     // friction: the normal row, else -1
    int manifold;   // a friction row of a manifold: its block (whose units' first rows are the
                    // manifold's normal rows), else -1
    bool unilateral, friction, positional;  // positional: phi is a position error
    bool moves_a, moves_b;                  // the end takes impulses (not static or kinematic)
  };
  /// Writes row r, whose warm-start impulse is `warm`, for the sweep into c; `block`: its block's
  /// place in the sweep.
  void compactRow(const Row& r, double warm, std::span<const int> manifold, int block,
                  CompactRow& c) const;
  double phi(const CompactRow& c) const;
  double rate(const CompactRow& c) const;
  void apply(const CompactRow& c, double delta);

  std::vector<CompactRow> rows_;
  std::vector<int> index_;    // compact row -> row
  std::vector<int> compact_;  // row -> compact row, -1 for a row left out
  double frictionBound(const CompactRow& c) const;
  /// Colours the blocks (units [blocks[b], blocks[b + 1]), whose rows are
  /// order_[units[u]] .. order_[units[u + 1] - 1]) and returns them in sweep order.
  std::span<const int> colour(std::span<const Row> rows, std::span<const int> units,
                              std::span<const int> blocks);
  // The wide sweep: blocks of one colour (which share no moving body) solved side by side, one
  // per lane, with the same arithmetic as the scalar path, so that each lane's result is the
  // scalar one to the bit.

  /// One row of a bundle's blocks, lane by lane (structure of arrays).
  struct alignas(32) WideRow {  // aligned for the AVX2 clone of the sweep, whatever the target
    Lanes ja_v[3], ja_w[3], jb_v[3], jb_w[3];
    Lanes wa_v[3], wa_w[3], wb_v[3], wb_w[3];
    Lanes mass, phi0, speed, lo, hi, mu, spring;
    std::array<int, kLanes> lambda;  // each lane's row in lambda_ (the spare entry for none)
  };
  /// Up to kLanes blocks of one colour whose units are contact points (a unilateral normal row
  /// and two friction rows bounded by the manifold): unit j of every lane in wide rows
  /// first + 3 j .. first + 3 j + 2.
  struct Bundle {
    int first = 0, units = 0;                   // its first wide row; the most units of its blocks
    std::array<int, kLanes> a{}, b{}, count{};  // each lane's bodies and units (0: empty lane)
    std::array<bool, kLanes> moves_a{}, moves_b{};
  };
  /// Whether block s (in sweep order) can be a bundle's lane.
  bool fitsBundle(std::size_t s) const;
  /// Groups each colour's blocks into bundles and builds their wide rows.
  void buildBundles();
  /// Zeroes lane l of a wide row (an empty lane: no block, or a block with fewer units).
  static void clearLane(WideRow& w, std::size_t l);
  /// Builds bundle k's wide rows from its blocks' compact rows.
  void fillBundle(std::size_t k);
  /// Applies bundle k's impulses to its bodies, as warmStart does a block's.
  void warmStartBundle(std::size_t k);
  /// Solves bundle k's blocks side by side, like solveBlock.
  void solveBundle(std::size_t k, bool forward, Pass pass);
  std::vector<Bundle> bundles_;
  std::vector<WideRow> wide_;
  // Each colour's work: bundles (>= 0) then blocks solved alone (-1 - block); colours as in
  // colour_start_.
  std::vector<int> tasks_, task_start_;
  std::vector<int> lane_block_, alone_scratch_;  // buildBundles' buffers

  /// A block's two bodies while its rows are solved: velocities, and the motion since the step
  /// began.
  struct Ends {
    Vec3 va, wa, vb, wb;
    Vec3 dpa, dqa, dpb, dqb;
  };
  /// Solves block k's units, in order or (`forward` false) backwards; in a push only their normal
  /// rows (the bodies' velocities swapped with their push velocities, push_ for lambda_).
  void solveBlock(std::size_t k, bool forward, Pass pass);
  /// Solves a unit's rows: its normal (or lone) row, then (not in a push) its friction rows.
  void solveUnit(std::size_t u, Pass pass, Ends& ends);
  /// One sweep of the given pass.
  void sweep(Pass pass);
  /// Calls task(t) for every task (a bundle, or a block solved alone), colour by colour
  /// (backwards when `forward` is false), each colour's tasks split over the threads, then the
  /// overflow set in order.
  template <class F>
  void eachTask(bool forward, F&& task);
  std::vector<double> lambda_, total_;  // by row
  std::vector<double> push_;            // by row, as lambda_: this substep's push impulses
  std::vector<Body> bodies_;            // and one more, always at rest, for an absent end
  Settings settings_;
  std::vector<int> order_;  // the rows that act, each contact point's normal then its friction rows
  std::vector<int> frictions_;     // per row: its first friction row, -1 for none
  std::vector<int> units_;         // rows_ [units_[u], units_[u + 1]) are solved together, in order
  std::vector<int> blocks_;        // units [blocks_[b], blocks_[b + 1]): one manifold (same bodies)
  std::vector<int> colour_start_;  // blocks of each colour, in sweep order; the last: the overflow
  // prepare's and colour's buffers, kept for their capacity
  std::vector<int> unit_scratch_, block_scratch_, colour_of_, sweep_blocks_, block_rows_;
  GraphColouring colouring_;
  int sweeps_ = 0;  // sweeps since prepare
};

}  // namespace linx::solver
