// Broadphase: which pairs of world AABBs overlap, by sweep and prune (DESIGN.md section 6).
//
// Why it scales: the boxes are kept sorted by their lower bound along the sweep axis (the axis of
// largest variance of the box centres, so the sweep separates them best), and each box is only
// tested against the boxes whose lower bound lies inside its own interval on that axis. A single
// sweep over a volume filled at constant density still tests ~n^(5/3) pairs (on one axis a box
// overlaps a whole slab of the volume), so the other two axes are also cut into a coarse grid of
// columns about two mean box widths wide, and each column is swept on its own (a box crossing
// columns goes into each; a pair is reported only in the column holding the start of its overlap,
// so exactly once). The columns are filled in the global sweep order by a counting sort, so they
// need no sorting of their own: the sort is O(n log n) (O(n) when coherent), the sweep ~O(n).
// If a few huge boxes would be copied into too many columns (over 8n + 1024 copies in all), the
// grid is coarsened, down to a single sweep: slower in that case, never wrong.
//
// Coherence: the sorted order is kept between calls. When the count and the sweep axis are
// unchanged (bodies moved a little since the last step) it is repaired by insertion sort, which
// is O(n + swaps), i.e. near O(n); if the swaps exceed a budget, or the count or sweep axis
// changed, it falls back to std::sort, so the worst case stays O(n log n). The sweep axis has
// hysteresis so that it does not flip between two axes of nearly equal variance.
//
// Memory: every buffer is a member, reused; at a constant count an update allocates nothing after
// the first (unless the number of pairs or column entries exceeds all earlier ones).
#pragma once

#include <array>
#include <span>
#include <utility>
#include <vector>

#include "collision/aabb.hpp"
#include "parallel/task_output.hpp"

namespace linx::collision {

class SweepAndPrune {
 public:
  /// Find all overlapping pairs of boxes (indices into boxes). Boxes must not contain NaN to be
  /// reported (a box with NaN overlaps nothing); infinite bounds are allowed. The columns are
  /// swept by up to `threads` threads; the pairs are the same, in the same order, for any count.
  void update(std::span<const Aabb> boxes, int threads = 1);

  /// Each overlapping pair once, (i, j) with i < j, sorted lexicographically.
  const std::vector<std::pair<int, int>>& pairs() const { return pairs_; }

  /// The sweep axis (0, 1, 2) used by the last update.
  int sweepAxis() const { return axis_; }
  /// The two column axes and the number of columns along each, used by the last update.
  const std::array<int, 2>& cellAxes() const { return cell_axis_; }
  const std::array<int, 2>& cellCounts() const { return cell_count_; }
  /// Box-box overlap tests made by the last update's sweep: the work it did, a machine-independent
  /// measure of its cost (all pairs would be n (n - 1) / 2).
  std::size_t lastTests() const { return tests_; }
  /// True when the last update repaired the previous order by insertion sort (coherent path).
  bool lastUpdateIncremental() const { return incremental_; }

 private:
  struct Key {
    double min;  // lower bound on the sweep axis (NaN mapped to +infinity)
    int index;
  };
  struct Entry {  // a box copied into its column, in sweep order, for a cache-friendly scan
    Aabb box;
    int index;
  };

  void chooseAxes(std::span<const Aabb> boxes);
  void sortKeys(std::span<const Aabb> boxes, bool coherent);
  void buildCells(std::span<const Aabb> boxes, int threads);
  int cellOf(int q, double x) const;
  void setCellCounts(int count_b, int count_c);  // column index along cell axis q (monotone in x)
  void sortPairs(int n);
  void sweepCell(int cell, std::vector<std::pair<int, int>>& out, std::size_t& tests) const;

  std::vector<Key> keys_;
  std::vector<Entry> entries_;
  std::vector<int> cell_begin_;  // column s holds entries_[cell_begin_[s], cell_begin_[s + 1])
  std::vector<std::array<int, 4>> ranges_;  // per key: its first and last column on each axis
  std::vector<int> chunk_fill_;  // per run of keys and column: its count, then its write cursor
  std::vector<double> chunk_entries_;  // per run of keys: the column entries it makes
  std::vector<std::pair<int, int>> pairs_;
  std::vector<std::pair<int, int>> sorted_;  // sortPairs' output, swapped with pairs_
  std::vector<int> pair_start_;              // sortPairs' buckets, by first index
  std::vector<parallel::TaskOutput<std::vector<std::pair<int, int>>>> chunk_pairs_;  // per run
  std::vector<parallel::TaskOutput<std::size_t>> chunk_tests_;  // of columns swept
  int axis_ = -1;
  std::array<int, 2> cell_axis_{1, 2};
  std::array<int, 2> cell_count_{1, 1};
  std::array<double, 2> cell_origin_{0.0, 0.0};
  std::array<double, 2> cell_range_{0.0, 0.0};  // of the finite centres along each cell axis
  std::array<double, 2> cell_inv_width_{0.0, 0.0};
  bool incremental_ = false;
  std::size_t tests_ = 0;
};

}  // namespace linx::collision
