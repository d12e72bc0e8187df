#pragma once

#include "solver/problem.hpp"

#include <cstdint>
#include <vector>

namespace linx::solver {

/// Projected Gauss-Seidel (sequential impulses): sweep the rows, update each impulse from its
/// slack, clamp it to its bounds and apply the change to both bodies at once. Starts from the
/// given lambda (warm start); stops on the iteration cap or when the largest complementarity
/// violation falls below the tolerance.
///
/// The sweep runs on a compact copy of the rows (J of both ends, the diagonal, bounds and target
/// in one 160-byte record) and of the body velocities, so that one row update reads one
/// contiguous record, two velocity slots and the two bodies' inverse masses and inertias: the
/// buffers are kept between solves and do not allocate once grown.
///
/// Large problems (16,384 rows and more) are swept colour by colour: a greedy colouring splits the
/// normal and bilateral rows, then the friction rows, into groups whose rows share no movable
/// body, and the threads of Problem::threads split each group. The order of the sweep depends on
/// the rows alone, never on the thread count, so every count gives the same impulses to the bit.
/// Rows left without one of the 64 colours form a serial group.
class PgsSolver final : public ConstraintSolver {
 public:
  SolverReport solve(Problem& p, const SolverSettings& settings) override;

 private:
  struct Velocity {
    Vec3 v = Vec3::Zero(), w = Vec3::Zero();
  };
  // 160 bytes: the sweep streams every row once per sweep, so the row's size sets its speed on a
  // large pile. M^-1 J^T is not kept: each end's inverse mass and inertia are read from the
  // bodies, which stay in cache, where the rows do not.
  struct CompactRow {
    Vec3 ja_v, ja_w, jb_v, jb_w;  // J, linear and angular part of each end
    double inv_diag, diag;        // 1 / A_kk, and A_kk / sor for the violation
    double target, cfm;
    double lo, hi;  // bounds; a friction row with a normal row keeps its friction coefficient in hi
    int a, b;       // velocity slots; a row end without a body points at a slot that stays zero
    int normal;     // friction rows: the normal row whose impulse bounds this one, else -1
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
