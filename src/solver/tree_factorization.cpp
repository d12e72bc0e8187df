#include "solver/tree_factorization.hpp"

#include "solver/dense_ldlt.hpp"

#include <algorithm>
#include <cmath>
#include <type_traits>
#include <utility>

namespace linx::solver {

namespace {

// The block kernels below take the block size n as a template argument where it is one of the
// common ones (a body's 6, a hinge's 5, a ball's 3, a body with its joint to the world 11...), so
// that the compiler unrolls their loops; Size == 0 is the same code for any n. The operations and
// their order are the same either way, so the results are too, to the bit.
constexpr int kLargestFixedBlock = 12;

// Calls f(std::integral_constant<int, n>) for n up to kLargestFixedBlock, else with 0.
template <typename F>
void withBlockSize(int n, F&& f) {
  switch (n) {
#define LINX_BLOCK_CASE(k)               \
  case k:                                \
    f(std::integral_constant<int, k>{}); \
    return;
    LINX_BLOCK_CASE(1)
    LINX_BLOCK_CASE(2)
    LINX_BLOCK_CASE(3)
    LINX_BLOCK_CASE(4)
    LINX_BLOCK_CASE(5)
    LINX_BLOCK_CASE(6)
    LINX_BLOCK_CASE(7)
    LINX_BLOCK_CASE(8)
    LINX_BLOCK_CASE(9)
    LINX_BLOCK_CASE(10)
    LINX_BLOCK_CASE(11)
    LINX_BLOCK_CASE(12)
#undef LINX_BLOCK_CASE
    default:
      f(std::integral_constant<int, 0>{});
  }
  static_assert(kLargestFixedBlock == 12, "withBlockSize lists every fixed size");
}

// Dense LDL^T of the n x n column-major matrix a in place (L below the diagonal, D on it), without
// pivoting: the callers order every node so that its pivots are definite. Rows from `first_row`
// on are constraint rows: each pivot gets a shift of 1e-13 of its reference diagonal (the diagonal
// once the body part is eliminated), and a pivot that is nothing but regularization counts as
// redundant. cfm[j - first_row] is row j's cfm. first_row is 6 for a body's node, 0 for a group's.
template <int Size, int first_row>
int factorDense(double* a, int n_any, const double* cfm) {
  const int n = Size > 0 ? Size : n_any;
  int redundant = 0;
  for (int j = 0; j < n; ++j) {
    double d = a[j + j * n];
    const int body_part = std::min(j, first_row);
    for (int k = 0; k < body_part; ++k) d -= a[j + k * n] * a[j + k * n] * a[k + k * n];
    const double reference = d;
    for (int k = body_part; k < j; ++k) d -= a[j + k * n] * a[j + k * n] * a[k + k * n];
    if (j >= first_row) {
      const double c = cfm[j - first_row];
      const double shift = 1e-13 * std::max(reference, 1e-300);
      if (isRedundantPivot(d, reference, c, shift)) ++redundant;
      d += shift;
    }
    a[j + j * n] = d;
    eliminateBelow(a, n, j);
  }
  return redundant;
}

// X = A^-1 X for the m columns of the n x m column-major X: the same operations as m calls of
// solveLdlt, a column at a time so that a fixed n unrolls each solve.
template <int Size>
void solveDenseColumns(const double* a, int n_any, double* x, int m) {
  const int n = Size > 0 ? Size : n_any;
  for (int c = 0; c < m; ++c) solveLdlt(a, n, x + c * n);
}

// D(parent) -= H^T X for H and X n x m (column-major); dp is m x m and kept symmetric.
template <int Size>
void subtractSchur(const double* h, const double* x, int n_any, int m, double* dp) {
  const int n = Size > 0 ? Size : n_any;
  for (int c = 0; c < m; ++c) {
    for (int r = c; r < m; ++r) {
      double s = 0.0;
      for (int t = 0; t < n; ++t) s += h[t + r * n] * x[t + c * n];
      dp[r + c * m] -= s;
      if (r != c) dp[c + r * m] -= s;
    }
  }
}

// z(parent) -= X^T z(node) (forward), or z(node) -= X z(parent) (backward); X is n x m.
template <int Size>
void subtractTransposed(const double* x, int n_any, int m, const double* z, double* zp) {
  const int n = Size > 0 ? Size : n_any;
  for (int c = 0; c < m; ++c) {
    double s = 0.0;
    for (int t = 0; t < n; ++t) s += x[t + c * n] * z[t];
    zp[c] -= s;
  }
}
template <int Size>
void subtractProduct(const double* x, int n_any, int m, const double* zp, double* z) {
  const int n = Size > 0 ? Size : n_any;
  if constexpr (Size > 0) {  // the sums side by side, each in the same order as below
    double s[Size] = {};
    for (int c = 0; c < m; ++c)
      for (int t = 0; t < Size; ++t) s[t] += x[t + c * Size] * zp[c];
    for (int t = 0; t < Size; ++t) z[t] -= s[t];
  } else {
    for (int t = 0; t < n; ++t) {
      double s = 0.0;
      for (int c = 0; c < m; ++c) s += x[t + c * n] * zp[c];
      z[t] -= s;
    }
  }
}

template <int Size>
void solveBlock(const double* a, int n_any, double* x) {
  solveLdlt(a, Size > 0 ? Size : n_any, x);
}

bool movable(const SolverBody& b) {
  return b.inv_mass > 0.0;
}

}  // namespace

bool TreeFactorization::analyse(const Problem& p) {
  const std::size_t n = p.rows.size();
  // A row coupling two joints closes a loop through their bodies: the general path's.
  if (std::any_of(p.rows.begin(), p.rows.end(), [](const Row& r) { return r.coupled(); })) {
    analysed_ = false;
    return false;
  }
  const auto endOf = [&](int body) {
    return body >= 0 && movable(p.bodies[static_cast<std::size_t>(body)]) ? body : -1;
  };
  // The analysis depends on the rows' movable ends alone: a mechanism's rows come the same from
  // one step to the next, and their analysis with them.
  bool same = analysed_ && ends_.size() == n && analysed_bodies_ == p.bodies.size();
  for (std::size_t k = 0; k < n && same; ++k)
    same = ends_[k] == std::pair{endOf(p.rows[k].body_a), endOf(p.rows[k].body_b)};
  if (same) return true;
  analysed_ = false;
  ends_.resize(n);
  for (std::size_t k = 0; k < n; ++k) ends_[k] = {endOf(p.rows[k].body_a), endOf(p.rows[k].body_b)};
  analysed_bodies_ = p.bodies.size();
  nodes_.clear();
  body_node_.assign(p.bodies.size(), -1);
  const auto bodyNode = [&](int body) {
    int& node = body_node_[static_cast<std::size_t>(body)];
    if (node < 0) {
      node = static_cast<int>(nodes_.size());
      nodes_.push_back(Node{});
      nodes_.back().body = body;
    }
    return node;
  };

  // Rows to one movable body join its node; rows between two go to the group of that pair.
  std::vector<int>& row_node = row_node_;
  row_node.assign(n, -1);
  pairs_.clear();
  for (std::size_t k = 0; k < n; ++k) {
    const int a = endOf(p.rows[k].body_a), b = endOf(p.rows[k].body_b);
    if (a < 0 && b < 0) return false;  // couples nothing that moves
    if (a < 0 || b < 0 || a == b) {
      row_node[k] = bodyNode(a >= 0 ? a : b);
      if (a == b) return false;  // a row between a body and itself: left to the general path
    } else {
      bodyNode(a);
      bodyNode(b);
      const auto lo = static_cast<std::uint64_t>(std::min(a, b));
      const auto hi = static_cast<std::uint64_t>(std::max(a, b));
      const int slot = static_cast<int>(pairs_.size());
      pairs_.push_back({(lo << 32) | hi, slot});
      row_node[k] = -2 - slot;
    }
  }
  // Each body pair becomes a group node. Sorting (pair, position) keeps it deterministic without
  // a hash map.
  std::vector<std::pair<std::uint64_t, int>>& pairs = pairs_;
  std::sort(pairs.begin(), pairs.end());
  std::vector<int>& group_of = group_of_;
  group_of.assign(pairs.size(), -1);
  for (std::size_t i = 0; i < pairs.size(); ++i) {
    if (i == 0 || pairs[i].first != pairs[i - 1].first) {
      Node g;
      g.body = -1;
      nodes_.push_back(g);
    }
    group_of[static_cast<std::size_t>(pairs[i].second)] = static_cast<int>(nodes_.size()) - 1;
  }
  for (std::size_t k = 0; k < n; ++k) {
    if (row_node[k] <= -2) row_node[k] = group_of[static_cast<std::size_t>(-2 - row_node[k])];
  }

  // Rows by node (counting sort, so rows keep their order within a node).
  const std::size_t count = nodes_.size();
  for (Node& node : nodes_) node.row_begin = node.row_end = 0;
  for (std::size_t k = 0; k < n; ++k) ++nodes_[static_cast<std::size_t>(row_node[k])].row_end;
  int start = 0;
  for (Node& node : nodes_) {
    const int c = node.row_end;
    node.row_begin = node.row_end = start;
    start += c;
  }
  rows_.resize(n);
  for (std::size_t k = 0; k < n; ++k) {
    Node& node = nodes_[static_cast<std::size_t>(row_node[k])];
    rows_[static_cast<std::size_t>(node.row_end++)] = static_cast<int>(k);
  }

  // A group's two ends; the bodies and groups must form a forest (union-find over the bodies).
  dsu_.resize(count);
  for (std::size_t i = 0; i < count; ++i) dsu_[i] = static_cast<int>(i);
  const auto find = [&](int x) {
    while (dsu_[static_cast<std::size_t>(x)] != x) {
      dsu_[static_cast<std::size_t>(x)] =
          dsu_[static_cast<std::size_t>(dsu_[static_cast<std::size_t>(x)])];
      x = dsu_[static_cast<std::size_t>(x)];
    }
    return x;
  };
  adjacency_.resize(count);
  for (auto& list : adjacency_) list.clear();
  for (std::size_t g = 0; g < count; ++g) {
    Node& node = nodes_[g];
    if (node.body >= 0) continue;
    const Row& r =
        p.rows[static_cast<std::size_t>(rows_[static_cast<std::size_t>(node.row_begin)])];
    const int a = body_node_[static_cast<std::size_t>(r.body_a)];
    const int b = body_node_[static_cast<std::size_t>(r.body_b)];
    const int ra = find(a), rb = find(b);
    if (ra == rb) return false;  // a loop
    dsu_[static_cast<std::size_t>(ra)] = rb;
    adjacency_[g] = {a, b};
    adjacency_[static_cast<std::size_t>(a)].push_back(static_cast<int>(g));
    adjacency_[static_cast<std::size_t>(b)].push_back(static_cast<int>(g));
  }

  // Depth-first from a body of each tree; the reverse of the visiting order has every node
  // before its parent. A tree held by the world is rooted at its one body with world rows, so that
  // every group's subtree floats free and its pivots stay well conditioned. A tree held by the
  // world at two bodies closes a loop through the world: that is left to the general path.
  order_.clear();
  std::vector<std::uint8_t>& seen = seen_;
  seen.assign(count, 0);
  const auto grounded = [&](std::size_t i) {
    return nodes_[i].body >= 0 && nodes_[i].row_end > nodes_[i].row_begin;
  };
  for (int pass = 0; pass < 2; ++pass)
    for (std::size_t root = 0; root < count; ++root) {
      if (seen[root] || nodes_[root].body < 0 || (pass == 0 && !grounded(root))) continue;
      seen[root] = 1;
      nodes_[root].parent = -1;
      stack_.assign(1, static_cast<int>(root));
      while (!stack_.empty()) {
        const int i = stack_.back();
        stack_.pop_back();
        if (i != static_cast<int>(root) && grounded(static_cast<std::size_t>(i))) return false;
        order_.push_back(i);
        for (const int j : adjacency_[static_cast<std::size_t>(i)]) {
          if (seen[static_cast<std::size_t>(j)]) continue;
          seen[static_cast<std::size_t>(j)] = 1;
          nodes_[static_cast<std::size_t>(j)].parent = i;
          stack_.push_back(j);
        }
      }
    }
  std::reverse(order_.begin(), order_.end());
  for (Node& node : nodes_) {
    node.parent_body =
        node.body < 0 && node.parent >= 0 ? nodes_[static_cast<std::size_t>(node.parent)].body : -1;
  }
  analysed_ = true;
  return true;
}

int TreeFactorization::factorize(const Problem& p, std::span<const std::uint8_t> free) {
  // Free rows per node, sizes and storage offsets.
  free_rows_.clear();
  free_begin_.resize(nodes_.size() + 1);
  std::size_t d_size = 0, z_size = 0;
  for (std::size_t i = 0; i < nodes_.size(); ++i) {
    Node& node = nodes_[i];
    free_begin_[i] = static_cast<int>(free_rows_.size());
    for (int r = node.row_begin; r < node.row_end; ++r) {
      const int k = rows_[static_cast<std::size_t>(r)];
      if (free[static_cast<std::size_t>(k)]) free_rows_.push_back(k);
    }
    node.size = (node.body >= 0 ? 6 : 0) + static_cast<int>(free_rows_.size()) - free_begin_[i];
    node.d = d_size;
    node.z = z_size;
    d_size += static_cast<std::size_t>(node.size * node.size);
    z_size += static_cast<std::size_t>(node.size);
  }
  free_begin_[nodes_.size()] = static_cast<int>(free_rows_.size());
  std::size_t l_size = 0;
  for (Node& node : nodes_) {
    node.l = l_size;
    if (node.parent >= 0)
      l_size +=
          static_cast<std::size_t>(node.size * nodes_[static_cast<std::size_t>(node.parent)].size);
  }
  d_.assign(d_size, 0.0);
  l_.resize(l_size);
  z_.resize(z_size);
  std::vector<double>& cfm = cfm_;

  // The row block of row k towards body `body`: J (1 x 6) and W = M^-1 J^T.
  const auto jacobian = [&](int k, int body) -> const Vec6& {
    const Row& r = p.rows[static_cast<std::size_t>(k)];
    return r.body_a == body ? r.Ja : r.Jb;
  };

  // Initial blocks: -M for a body, with its world rows J (and J^T) and cfm; cfm for a group.
  for (std::size_t i = 0; i < nodes_.size(); ++i) {
    const Node& node = nodes_[i];
    double* d = d_.data() + node.d;
    const int n = node.size;
    const int first = node.body >= 0 ? 6 : 0;
    if (node.body >= 0) {
      const SolverBody& b = p.bodies[static_cast<std::size_t>(node.body)];
      const Mat3 inertia = b.inv_inertia.inverse();
      for (int a = 0; a < 3; ++a) d[a + a * n] = -1.0 / b.inv_mass;
      for (int a = 0; a < 3; ++a)
        for (int c = 0; c < 3; ++c) d[(3 + a) + (3 + c) * n] = -inertia(a, c);
    }
    for (int f = free_begin_[i]; f < free_begin_[i + 1]; ++f) {
      const int k = free_rows_[static_cast<std::size_t>(f)];
      const int j = first + f - free_begin_[i];
      d[j + j * n] = p.rows[static_cast<std::size_t>(k)].cfm;
      if (node.body >= 0) {
        const Vec6& jac = jacobian(k, node.body);
        for (int c = 0; c < 6; ++c) d[j + c * n] = d[c + j * n] = jac[c];
      }
    }
  }

  int redundant = 0;
  std::vector<double>& h = h_;  // H(this, parent), this size x parent size
  for (const int i : order_) {
    Node& node = nodes_[static_cast<std::size_t>(i)];
    const int n = node.size;
    const int first = node.body >= 0 ? 6 : 0;
    cfm.clear();
    for (int f = free_begin_[static_cast<std::size_t>(i)];
         f < free_begin_[static_cast<std::size_t>(i) + 1]; ++f)
      cfm.push_back(p.rows[static_cast<std::size_t>(free_rows_[static_cast<std::size_t>(f)])].cfm);
    withBlockSize(n, [&](auto size) {
      double* d = d_.data() + node.d;
      redundant += first == 6 ? factorDense<size(), 6>(d, n, cfm.data())
                              : factorDense<size(), 0>(d, n, cfm.data());
    });
    if (node.parent < 0) continue;

    Node& parent = nodes_[static_cast<std::size_t>(node.parent)];
    const int m = parent.size;
    // H(this, parent): a body's 6 unknowns against its parent group's rows (J^T), or a group's rows
    // against its parent body's 6 unknowns (J).
    double* x = l_.data() + node.l;  // becomes X = D^-1 H (n x m), i.e. L(parent, this)^T
    std::fill(x, x + static_cast<std::size_t>(n * m), 0.0);
    if (node.body >= 0) {
      const int pi = node.parent;
      for (int f = free_begin_[static_cast<std::size_t>(pi)];
           f < free_begin_[static_cast<std::size_t>(pi) + 1]; ++f) {
        const int col = f - free_begin_[static_cast<std::size_t>(pi)];
        const Vec6& jac = jacobian(free_rows_[static_cast<std::size_t>(f)], node.body);
        for (int c = 0; c < 6; ++c) x[c + col * n] = jac[c];
      }
    } else {
      for (int f = free_begin_[static_cast<std::size_t>(i)];
           f < free_begin_[static_cast<std::size_t>(i) + 1]; ++f) {
        const int row = f - free_begin_[static_cast<std::size_t>(i)];
        const Vec6& jac = jacobian(free_rows_[static_cast<std::size_t>(f)], node.parent_body);
        for (int c = 0; c < 6; ++c) x[row + c * n] = jac[c];
      }
    }
    h.assign(x, x + static_cast<std::size_t>(n * m));
    // X = D^-1 H, then D(parent) -= H^T X.
    withBlockSize(n, [&](auto size) {
      solveDenseColumns<size()>(d_.data() + node.d, n, x, m);
      subtractSchur<size()>(h.data(), x, n, m, d_.data() + parent.d);
    });
  }
  return redundant;
}

void TreeFactorization::solve(std::span<double> x) {
  std::fill(z_.begin(), z_.end(), 0.0);
  for (std::size_t i = 0; i < nodes_.size(); ++i) {
    const Node& node = nodes_[i];
    const int first = node.body >= 0 ? 6 : 0;
    for (int f = free_begin_[i]; f < free_begin_[i + 1]; ++f)
      z_[node.z + static_cast<std::size_t>(first + f - free_begin_[i])] =
          x[static_cast<std::size_t>(free_rows_[static_cast<std::size_t>(f)])];
  }
  // Forward: z(parent) -= L(parent, i) z(i) = X^T z(i), leaves first.
  for (const int i : order_) {
    const Node& node = nodes_[static_cast<std::size_t>(i)];
    if (node.parent < 0) continue;
    const Node& parent = nodes_[static_cast<std::size_t>(node.parent)];
    withBlockSize(node.size, [&](auto size) {
      subtractTransposed<size()>(l_.data() + node.l, node.size, parent.size, z_.data() + node.z,
                                 z_.data() + parent.z);
    });
  }
  // Diagonal blocks, then backward: z(i) -= X z(parent), roots first.
  for (const Node& node : nodes_)
    withBlockSize(node.size, [&](auto size) {
      solveBlock<size()>(d_.data() + node.d, node.size, z_.data() + node.z);
    });
  for (auto it = order_.rbegin(); it != order_.rend(); ++it) {
    const Node& node = nodes_[static_cast<std::size_t>(*it)];
    if (node.parent < 0) continue;
    const Node& parent = nodes_[static_cast<std::size_t>(node.parent)];
    withBlockSize(node.size, [&](auto size) {
      subtractProduct<size()>(l_.data() + node.l, node.size, parent.size, z_.data() + parent.z,
                              z_.data() + node.z);
    });
  }
  std::fill(x.begin(), x.end(), 0.0);
  for (std::size_t i = 0; i < nodes_.size(); ++i) {
    const Node& node = nodes_[i];
    const int first = node.body >= 0 ? 6 : 0;
    for (int f = free_begin_[i]; f < free_begin_[i + 1]; ++f)
      x[static_cast<std::size_t>(free_rows_[static_cast<std::size_t>(f)])] =
          z_[node.z + static_cast<std::size_t>(first + f - free_begin_[i])];
  }
}

}  // namespace linx::solver
