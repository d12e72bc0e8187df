#pragma once

#include "solver/problem.hpp"

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

  struct Group {  // consecutive sweep positions [begin, begin + size)
    int begin, size;
    bool parallel;  // a colour (rows share no body), else swept in order by one thread
  };
  void planSweep(Problem& p);  // order_ and groups_ for this problem

  std::vector<CompactRow> rows_;  // in sweep order
  std::vector<double> lambda_;    // in sweep order
  std::vector<Velocity> velocities_;
  std::vector<int> order_;     // sweep position -> row
  std::vector<int> position_;  // row -> sweep position
  std::vector<Group> groups_;
  std::vector<int> colour_of_;
  std::vector<std::uint64_t> taken_;  // per body: the colours of its rows in this phase
  std::vector<double> thread_violation_;
};

}  // namespace linx::solver
