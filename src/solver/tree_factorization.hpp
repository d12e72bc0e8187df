// Linear-time factorization of A_FF = J_F M^-1 J_F^T + C_F for mechanisms without loops
// (Baraff 1996, "Linear-time dynamics using Lagrange multipliers"). The solver works on the
// equivalent quasi-definite system
//   [ -M   J^T ] [ y      ]   [ 0 ]
//   [  J   C   ] [ lambda ] = [ r ]
// whose graph has one node per movable body and one per group of rows joining the same two bodies.
// When bodies and groups form a forest, block elimination from the leaves to the roots creates no
// fill-in: each step costs O(bodies + rows). Rows to the world or to static bodies join their
// body's node (eliminated body first, so every pivot is well conditioned whatever the cfm).
// Loops (closed mechanisms, contact piles) are detected by analyse(); the caller then factors A
// as a general sparse matrix instead.
#pragma once

#include "solver/problem.hpp"

#include <cstdint>
#include <span>
#include <utility>
#include <vector>

namespace linx::solver {

class TreeFactorization {
 public:
  /// Groups the rows by body pair and orders the nodes leaves first. Returns false when the rows
  /// close a loop (or couple no movable body at all); nothing else may be called then. Rows with
  /// the same movable ends as the last analysis that succeeded keep it.
  bool analyse(const Problem& p);
  /// Factorizes for the rows with free[k] != 0. A row's pivot is shifted by 1e-13 of its diagonal,
  /// so redundant rows stay finite. Returns the number of pivots that are nothing but
  /// regularization: redundant rows.
  int factorize(const Problem& p, std::span<const std::uint8_t> free);
  /// Overwrites x (one entry per row) with A_FF^-1 x on the free rows; other entries become 0.
  void solve(std::span<double> x);

 private:
  struct Node {
    int body = -1;         // solver body index, or -1 for a group of rows between two bodies
    int parent = -1;       // node index, -1 for a root
    int parent_body = -1;  // a group's end that is its parent (a body node's parent is a group)
    int size = 0;          // unknowns: 6 (a body) + free rows of its own (its world rows)
    std::size_t d = 0;     // offset of the size x size factor in d_
    std::size_t l = 0;     // offset of L(parent, this): parent size x size, in l_
    std::size_t z = 0;     // offset of the node's unknowns in z_
    int row_begin = 0, row_end = 0;  // its rows in rows_ (all rows; free ones used)
  };

  std::vector<Node> nodes_;
  std::vector<int> order_;       // leaves first
  std::vector<int> rows_;        // row indices grouped by node
  std::vector<int> free_rows_;   // per node, the free ones (same ranges, compacted)
  std::vector<int> free_begin_;  // node -> start in free_rows_
  std::vector<int> body_node_;   // solver body -> node, -1 when it does not move
  // Work buffers, kept across steps: no allocation once they have grown.
  std::vector<double> d_, l_, z_, cfm_, h_;
  std::vector<std::pair<std::uint64_t, int>> pairs_;
  std::vector<int> row_node_, group_of_, dsu_, stack_;
  std::vector<std::uint8_t> seen_;
  // The last successful analysis: its rows' movable ends and the body count.
  bool analysed_ = false;
  std::vector<std::pair<int, int>> ends_;
  std::size_t analysed_bodies_ = 0;
  std::vector<std::vector<int>> adjacency_;
};

}  // namespace linx::solver
