#include "solver/tree_factorization.hpp"

#include "solver/dense_ldlt.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

namespace linx::solver {

namespace {

// Dense LDL^T of the n x n column-major matrix a in place (L below the diagonal, D on it), without
// pivoting: the callers order every node so that its pivots are definite. Rows from `first_row`
// on are constraint rows: each pivot gets a shift of 1e-13 of its reference diagonal (the diagonal
// once the body part is eliminated), and a pivot that is nothing but regularization counts as
// redundant. cfm[j - first_row] is row j's cfm.
int factorDense(double* a, int n, int first_row, const double* cfm) {
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
      if (d <= 1e-8 * (reference - c) + 10.0 * (c + shift)) ++redundant;
      d += shift;
    }
    a[j + j * n] = d;
    for (int i = j + 1; i < n; ++i) {
      double v = a[i + j * n];
      for (int k = 0; k < j; ++k) v -= a[i + k * n] * a[j + k * n] * a[k + k * n];
      a[i + j * n] = v / d;
    }
  }
  return redundant;
}

// X = A^-1 X for the m columns of the n x m column-major X at once: the same operations as m calls
// of solveLdlt, with the columns innermost so that they run side by side.
void solveDenseColumns(const double* a, int n, double* x, int m) {
  for (int j = 0; j < n; ++j) {
    for (int k = 0; k < j; ++k) {
      const double l = a[j + k * n];
      for (int c = 0; c < m; ++c) x[j + c * n] -= l * x[k + c * n];
    }
  }
  for (int j = 0; j < n; ++j) {
    const double d = a[j + j * n];
    for (int c = 0; c < m; ++c) x[j + c * n] /= d;
  }
  for (int j = n - 1; j >= 0; --j) {
    for (int i = j + 1; i < n; ++i) {
      const double l = a[i + j * n];
      for (int c = 0; c < m; ++c) x[j + c * n] -= l * x[i + c * n];
    }
  }
}

bool movable(const SolverBody& b) {
  return b.inv_mass > 0.0;
}

}  // namespace

bool TreeFactorization::analyse(const Problem& p) {
  const std::size_t n = p.rows.size();
  nodes_.clear();
  body_node_.assign(p.bodies.size(), -1);
  const auto endOf = [&](int body) {
    return body >= 0 && movable(p.bodies[static_cast<std::size_t>(body)]) ? body : -1;
  };
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
    redundant += factorDense(d_.data() + node.d, n, first, cfm.data());
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
    solveDenseColumns(d_.data() + node.d, n, x, m);
    // D(parent) -= H^T X (only the lower part is read later; the full block is kept symmetric).
    double* dp = d_.data() + parent.d;
    for (int c = 0; c < m; ++c) {
      for (int r = c; r < m; ++r) {
        double s = 0.0;
        for (int t = 0; t < n; ++t) s += h[static_cast<std::size_t>(t + r * n)] * x[t + c * n];
        dp[r + c * m] -= s;
        if (r != c) dp[c + r * m] -= s;
      }
    }
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
    const double* xm = l_.data() + node.l;
    for (int c = 0; c < parent.size; ++c) {
      double s = 0.0;
      for (int t = 0; t < node.size; ++t)
        s += xm[t + c * node.size] * z_[node.z + static_cast<std::size_t>(t)];
      z_[parent.z + static_cast<std::size_t>(c)] -= s;
    }
  }
  // Diagonal blocks, then backward: z(i) -= X z(parent), roots first.
  for (const Node& node : nodes_) solveLdlt(d_.data() + node.d, node.size, z_.data() + node.z);
  for (auto it = order_.rbegin(); it != order_.rend(); ++it) {
    const Node& node = nodes_[static_cast<std::size_t>(*it)];
    if (node.parent < 0) continue;
    const Node& parent = nodes_[static_cast<std::size_t>(node.parent)];
    const double* xm = l_.data() + node.l;
    for (int t = 0; t < node.size; ++t) {
      double s = 0.0;
      for (int c = 0; c < parent.size; ++c)
        s += xm[t + c * node.size] * z_[parent.z + static_cast<std::size_t>(c)];
      z_[node.z + static_cast<std::size_t>(t)] -= s;
    }
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
