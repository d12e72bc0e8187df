// Sweep and prune over a coarse grid of columns; see broadphase.hpp for the scheme and its cost.
#include "collision/broadphase.hpp"

#include "parallel/parallel_for.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <limits>

namespace linx::collision {

namespace {

/// Boxes from which the columns are swept by several threads.
constexpr std::size_t kParallelBoxes = 2048;

/// Sort key on the sweep axis: NaN goes last (as +infinity) so the ordering stays strict-weak.
double sweepKey(double x) {
  return std::isnan(x) ? std::numeric_limits<double>::infinity() : x;
}

bool keyLess(double a_min, int a_index, double b_min, int b_index) {
  return a_min < b_min || (a_min == b_min && a_index < b_index);
}

}  // namespace

void SweepAndPrune::sweepCell(int cell, std::vector<std::pair<int, int>>& out,
                              std::size_t& tests_out) const {
  const int a = axis_;
  const int b = cell_axis_[0];
  const int c = cell_axis_[1];
  const int end = cell_begin_[cell + 1];
  std::size_t tests = 0;
  for (int k = cell_begin_[cell]; k < end; ++k) {
    const Aabb& box_k = entries_[k].box;
    const double hi = box_k.max[a];
    for (int m = k + 1; m < end && !(entries_[m].box.min[a] > hi); ++m) {
      const Aabb& box_m = entries_[m].box;
      ++tests;
      if (!box_k.overlaps(box_m)) continue;
      // Report the pair only in the column holding the start of its overlap: exactly once.
      const int cb = cellOf(0, std::max(box_k.min[b], box_m.min[b]));
      const int cc = cellOf(1, std::max(box_k.min[c], box_m.min[c]));
      if (cb * cell_count_[1] + cc != cell) continue;
      const int i = entries_[k].index;
      const int j = entries_[m].index;
      out.emplace_back(std::min(i, j), std::max(i, j));
    }
  }
  tests_out += tests;
}

void SweepAndPrune::update(std::span<const Aabb> boxes, int threads) {
  pairs_.clear();
  tests_ = 0;
  const int previous_axis = axis_;
  const bool same_count = keys_.size() == boxes.size();
  chooseAxes(boxes);
  sortKeys(boxes, same_count && axis_ == previous_axis);
  if (boxes.size() < 2) return;
  buildCells(boxes, threads);

  // Sweep each column: entries are in increasing lower bound along the sweep axis, so box m can
  // overlap box k (m after k) only while its lower bound is <= k's upper bound. Many columns are
  // cut into consecutive runs that threads sweep apart; sortPairs then orders the pairs the same
  // way for any number of threads.
  const int cells = cell_count_[0] * cell_count_[1];
  const std::size_t chunks =
      threads > 1 && boxes.size() >= kParallelBoxes ? 16 * static_cast<std::size_t>(threads) : 1;
  if (chunk_pairs_.size() < chunks) chunk_pairs_.resize(chunks);
  chunk_tests_.assign(chunks, {0});
  parallel::forEachTask(static_cast<std::ptrdiff_t>(chunks), threads, [&](std::ptrdiff_t chunk) {
    const auto c = static_cast<std::size_t>(chunk);
    chunk_pairs_[c].value.clear();
    const int first = static_cast<int>(static_cast<std::size_t>(cells) * c / chunks);
    const int last = static_cast<int>(static_cast<std::size_t>(cells) * (c + 1) / chunks);
    for (int cell = first; cell < last; ++cell)
      sweepCell(cell, chunk_pairs_[c].value, chunk_tests_[c].value);
  });
  if (chunks == 1)
    pairs_.swap(chunk_pairs_[0].value);  // pairs_ was cleared: no copy
  else
    for (std::size_t c = 0; c < chunks; ++c)
      pairs_.insert(pairs_.end(), chunk_pairs_[c].value.begin(), chunk_pairs_[c].value.end());
  for (const auto& tests : chunk_tests_) tests_ += tests.value;
  sortPairs(static_cast<int>(boxes.size()));
}

void SweepAndPrune::sortPairs(int n) {
  // Counting sort on the first index, then each box's few partners sorted: O(n + pairs), where a
  // comparison sort of the million pairs of a large pile took a tenth of its step.
  pair_start_.assign(static_cast<std::size_t>(n) + 1, 0);
  for (const auto& [i, j] : pairs_) ++pair_start_[static_cast<std::size_t>(i) + 1];
  for (int i = 0; i < n; ++i) pair_start_[i + 1] += pair_start_[i];
  sorted_.resize(pairs_.size());
  for (const auto& pair : pairs_) sorted_[pair_start_[pair.first]++] = pair;
  // pair_start_[i] now ends box i's run, which begins where box i - 1's ends.
  int begin = 0;
  for (int i = 0; i < n; ++i) {
    const int end = pair_start_[i];
    std::sort(sorted_.begin() + begin, sorted_.begin() + end);
    begin = end;
  }
  pairs_.swap(sorted_);
}

void SweepAndPrune::chooseAxes(std::span<const Aabb> boxes) {
  // Mean and variance of the finite box centres, and mean finite extent, per axis.
  Vec3 sum = Vec3::Zero();
  Vec3 extent_sum = Vec3::Zero();
  Vec3 lo = Vec3::Constant(std::numeric_limits<double>::infinity());
  Vec3 hi = -lo;
  double finite = 0.0;
  for (const Aabb& box : boxes) {
    const Vec3 centre = box.centre();
    const Vec3 extent = box.extent();
    if (!centre.allFinite() || !extent.allFinite()) continue;
    sum += centre;
    extent_sum += extent;
    lo = lo.cwiseMin(centre);
    hi = hi.cwiseMax(centre);
    finite += 1.0;
  }
  if (axis_ < 0) axis_ = 0;
  cell_axis_ = {(axis_ + 1) % 3, (axis_ + 2) % 3};
  setCellCounts(1, 1);
  if (finite < 2.0) return;
  const Vec3 mean = sum / finite;
  Vec3 var = Vec3::Zero();
  for (const Aabb& box : boxes) {
    const Vec3 centre = box.centre();
    if (!centre.allFinite() || !box.extent().allFinite()) continue;
    var += (centre - mean).cwiseAbs2();
  }

  // Largest variance separates the boxes best; keep the current axis unless clearly beaten.
  int best = 0;
  var.maxCoeff(&best);
  if (!(var[axis_] >= 0.8 * var[best])) axis_ = best;
  int b = (axis_ + 1) % 3;
  int c = (axis_ + 2) % 3;
  if (var[c] > var[b]) std::swap(b, c);
  cell_axis_ = {b, c};

  // Columns about two mean box widths wide: a box lies in ~(1.5)^2 columns on average, and a
  // column holds a bounded number of boxes at constant density, so the sweep is ~O(n).
  const Vec3 mean_extent = extent_sum / finite;
  std::array<double, 2> count{1.0, 1.0};
  for (int q = 0; q < 2; ++q) {
    const int axis = cell_axis_[q];
    const double width = 2.0 * mean_extent[axis];
    const double range = hi[axis] - lo[axis];
    if (width > 0.0 && range > 0.0) count[q] = std::min(std::floor(range / width) + 1.0, 1e6);
  }
  // At most about one column per box, so the column table never dominates.
  const double cap = std::max(1.0, static_cast<double>(boxes.size()));
  if (count[0] * count[1] > cap) {
    const double shrink = std::sqrt(cap / (count[0] * count[1]));
    count[0] = std::max(1.0, std::floor(count[0] * shrink));
    count[1] = std::max(1.0, std::floor(count[1] * shrink));
  }
  for (int q = 0; q < 2; ++q) {
    cell_origin_[q] = lo[cell_axis_[q]];
    cell_range_[q] = hi[cell_axis_[q]] - lo[cell_axis_[q]];
  }
  setCellCounts(static_cast<int>(count[0]), static_cast<int>(count[1]));
}

void SweepAndPrune::setCellCounts(int count_b, int count_c) {
  cell_count_ = {count_b, count_c};
  for (int q = 0; q < 2; ++q)
    cell_inv_width_[q] = cell_count_[q] > 1 ? cell_count_[q] / cell_range_[q] : 0.0;
}

void SweepAndPrune::sortKeys(std::span<const Aabb> boxes, bool coherent) {
  const int a = axis_;
  const int n = static_cast<int>(boxes.size());
  incremental_ = false;
  if (coherent) {
    // Insertion sort from the previous order: O(n + swaps). Give up past a budget of moves.
    for (Key& key : keys_) key.min = sweepKey(boxes[key.index].min[a]);
    std::size_t budget = 8 * keys_.size() + 1024;
    bool done = true;
    for (int k = 1; k < n && done; ++k) {
      const Key key = keys_[k];
      int m = k;
      while (m > 0 && keyLess(key.min, key.index, keys_[m - 1].min, keys_[m - 1].index)) {
        keys_[m] = keys_[m - 1];
        --m;
        if (--budget == 0) {
          done = false;
          break;
        }
      }
      keys_[m] = key;
    }
    incremental_ = done;
    if (done) return;
  } else {
    keys_.resize(boxes.size());
    for (int i = 0; i < n; ++i) keys_[i] = Key{sweepKey(boxes[i].min[a]), i};
  }
  std::sort(keys_.begin(), keys_.end(),
            [](const Key& x, const Key& y) { return keyLess(x.min, x.index, y.min, y.index); });
}

int SweepAndPrune::cellOf(int q, double x) const {
  const double t = (x - cell_origin_[q]) * cell_inv_width_[q];
  if (!(t > 0.0)) return 0;  // also NaN (e.g. infinity * 0 when there is one column)
  if (t >= cell_count_[q]) return cell_count_[q] - 1;
  return static_cast<int>(t);
}

void SweepAndPrune::buildCells(std::span<const Aabb> boxes, int threads) {
  // Counting sort of the boxes into columns, visiting them in sweep order so that every column
  // comes out already sorted along the sweep axis. Several threads each count and place a run of
  // the keys; a column takes the runs in order, so it comes out the same for any thread count.
  const int b = cell_axis_[0];
  const int c = cell_axis_[1];
  const std::size_t n = keys_.size();
  const std::size_t chunks = threads > 1 && n >= kParallelBoxes
                                 ? std::min<std::size_t>(static_cast<std::size_t>(threads), 8)
                                 : 1;
  const auto first = [&](std::size_t chunk) { return n * chunk / chunks; };
  ranges_.resize(n);
  chunk_entries_.assign(chunks, 0.0);
  // A few very large boxes among many small ones would be copied into very many columns: keep
  // the copies within a multiple of n by coarsening the grid (down to a single sweep if need be).
  const double max_entries = 8.0 * static_cast<double>(n) + 1024.0;
  for (;;) {
    parallel::forEach(static_cast<std::ptrdiff_t>(chunks), threads, 2, [&](std::ptrdiff_t ch) {
      const auto chunk = static_cast<std::size_t>(ch);
      double entries = 0.0;
      for (std::size_t k = first(chunk); k < first(chunk + 1); ++k) {
        const Aabb& box = boxes[static_cast<std::size_t>(keys_[k].index)];
        auto& r = ranges_[k];
        r = {cellOf(0, box.min[b]), cellOf(0, box.max[b]), cellOf(1, box.min[c]),
             cellOf(1, box.max[c])};
        entries += std::max(0, r[1] - r[0] + 1) * static_cast<double>(std::max(0, r[3] - r[2] + 1));
      }
      chunk_entries_[chunk] = entries;
    });
    double entries = 0.0;
    for (const double e : chunk_entries_) entries += e;
    if (cell_count_[0] * cell_count_[1] == 1 || entries <= max_entries) break;
    setCellCounts((cell_count_[0] + 1) / 2, (cell_count_[1] + 1) / 2);
  }
  const auto cells = static_cast<std::size_t>(cell_count_[0] * cell_count_[1]);
  const auto columns = static_cast<std::size_t>(cell_count_[1]);
  chunk_fill_.assign(chunks * cells, 0);
  const auto visit = [&](std::size_t chunk, auto&& f) {
    int* fill = chunk_fill_.data() + chunk * cells;
    for (std::size_t k = first(chunk); k < first(chunk + 1); ++k) {
      const auto& r = ranges_[k];
      for (int i = r[0]; i <= r[1]; ++i)
        for (int j = r[2]; j <= r[3]; ++j) f(k, fill[static_cast<std::size_t>(i) * columns + j]);
    }
  };
  parallel::forEach(static_cast<std::ptrdiff_t>(chunks), threads, 2, [&](std::ptrdiff_t ch) {
    visit(static_cast<std::size_t>(ch), [](std::size_t, int& count) { ++count; });
  });
  // Column-major, run-minor prefix sum: each run's count becomes its write cursor.
  cell_begin_.resize(cells + 1);
  int total = 0;
  for (std::size_t cell = 0; cell < cells; ++cell) {
    cell_begin_[cell] = total;
    for (std::size_t chunk = 0; chunk < chunks; ++chunk) {
      int& fill = chunk_fill_[chunk * cells + cell];
      const int count = fill;
      fill = total;
      total += count;
    }
  }
  cell_begin_[cells] = total;
  entries_.resize(static_cast<std::size_t>(total));
  parallel::forEach(static_cast<std::ptrdiff_t>(chunks), threads, 2, [&](std::ptrdiff_t ch) {
    visit(static_cast<std::size_t>(ch), [&](std::size_t k, int& cursor) {
      const int index = keys_[k].index;
      entries_[static_cast<std::size_t>(cursor++)] = {boxes[static_cast<std::size_t>(index)],
                                                      index};
    });
  });
}

}  // namespace linx::collision
