#pragma once

#include "solver/graph_colouring.hpp"
#include "solver/problem.hpp"

#include <Eigen/Core>

#include <cstdint>
#include <memory>
#include <vector>

namespace linx::solver {

/// Projected Gauss-Seidel (sequential impulses): sweep the rows, update each impulse from its
/// slack, clamp it to its bounds and apply the change to both bodies at once. Starts from the
/// given lambda (warm start); stops on the iteration cap or when the largest complementarity
/// violation falls below the tolerance.
///
/// The sweep runs on a compact copy of the rows (J and M^-1 J^T of both ends, side by side) and
/// of the body velocities, so that one row update reads one contiguous record and two velocity
/// slots: the buffers are kept between solves and do not allocate once grown.
///
/// Large problems (16,384 rows and more) are swept colour by colour: a greedy colouring splits the
/// normal and bilateral rows, then the friction rows, into groups whose rows share no movable
/// body, and the threads of Problem::threads split each group. The order of the sweep depends on
/// the rows alone, never on the thread count, so every count gives the same impulses to the bit.
/// Rows left without one of the 64 colours form a serial group.
///
/// A joint's equality rows (consecutive bilateral rows of one owner between the same two bodies,
/// at most six) are relaxed together as a block: their impulses change by -A_bb^-1 w_b at once,
/// with A_bb the block's part of A, inverted when the rows are gathered. Scalar sweeps converge at
/// a rate set by A's condition number; within one joint it is the ratio of the lever arm's
/// m r^2 to the body's own inertia, thousands for a light bob on a long arm, where 100 scalar
/// sweeps leave the joint open and the error reduction then pumps energy into the pendulum. The
/// block removes that coupling exactly; what is left to iterate is between joints and contacts.
class PgsSolver final : public ConstraintSolver {
 public:
  SolverReport solve(Problem& p, const SolverSettings& settings) override;
  std::unique_ptr<ConstraintSolver> another() const override {
    return std::make_unique<PgsSolver>();
  }

 private:
  struct Velocity {
    Vec3 v = Vec3::Zero(), w = Vec3::Zero();
  };
  struct CompactRow {
    Vec3 ja_v, ja_w, jb_v, jb_w;                     // J, linear and angular part of each end
    Vec3 wa_v, wa_w, wb_v, wb_w;                     // M^-1 J^T
    double inv_diag, diag, target, cfm, lo, hi, mu;  // diag: A_kk / sor, for the violation
    int a, b;    // velocity slots; a row end without a body points at a slot that stays zero
    int normal;  // friction rows: the normal row whose impulse bounds this one, else -1
  };
  /// A coupled row's bodies c and d: J, M^-1 J^T and velocity slots, as CompactRow's ends.
  struct CoupledEnds {
    Vec3 j_v[2], j_w[2], w_v[2], w_w[2];
    int body[2];
  };

  struct Group {  // consecutive items [begin, begin + size)
    int begin, size;
    bool parallel;  // a colour (items share no body), else swept in order by one thread
  };
  /// What the sweep relaxes in one go: one row, or a block of a joint's equality rows at
  /// consecutive sweep positions [begin, begin + size), with block_inverse_[block] = A_bb^-1.
  struct Item {
    int begin, size, block;  // block: -1 for a single row
  };
  static constexpr int kMaxBlock = 6;
  using BlockMatrix = Eigen::Matrix<double, kMaxBlock, kMaxBlock>;
  using BlockVector = Eigen::Matrix<double, kMaxBlock, 1>;
  /// Marks block_start_[k] for each row k that starts a block or stands alone (original order).
  void findBlocks(const Problem& p);
  void planSweep(Problem& p);  // order_ and groups_ for this problem
  /// items_ over the sweep order, and each block's inverse (rows_ must be gathered).
  void buildItems(const std::vector<int>& group_ends);

  std::vector<CompactRow> rows_;  // in sweep order
  std::vector<CoupledEnds> coupled_;
  std::vector<int> coupled_of_;  // per sweep position: its index in coupled_, or -1
  std::vector<double> lambda_;   // in sweep order
  std::vector<Velocity> velocities_;
  std::vector<int> order_;     // sweep position -> row
  std::vector<int> position_;  // row -> sweep position
  std::vector<Group> groups_;
  std::vector<std::uint8_t> block_start_;  // per row (original order): 0 continues a block
  std::vector<Item> items_;                // in sweep order
  std::vector<BlockMatrix> block_inverse_;
  std::vector<int> group_ends_;  // sweep position where each group ends
  std::vector<int> colour_of_;
  GraphColouring colouring_;  // of this phase's rows
  std::vector<double> thread_violation_;
};

}  // namespace linx::solver
