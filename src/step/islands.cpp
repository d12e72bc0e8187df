#include "step/islands.hpp"

#include "world/state_archive.hpp"

#include <stdexcept>

namespace linx::step {

void bucketByIsland(std::span<const int> island_of, int count, std::vector<int>& start,
                    std::vector<int>& list) {
  start.assign(static_cast<std::size_t>(count) + 1, 0);
  int placed = 0;
  for (const int island : island_of)
    if (island >= 0) {
      ++start[static_cast<std::size_t>(island) + 1];
      ++placed;
    }
  for (std::size_t i = 1; i < start.size(); ++i) start[i] += start[i - 1];
  list.resize(static_cast<std::size_t>(placed));
  // start[i] is used as the insertion cursor of island i, then shifted back.
  for (std::size_t k = 0; k < island_of.size(); ++k) {
    const int island = island_of[k];
    if (island >= 0)
      list[static_cast<std::size_t>(start[static_cast<std::size_t>(island)]++)] =
          static_cast<int>(k);
  }
  for (std::size_t i = start.size() - 1; i > 0; --i) start[i] = start[i - 1];
  start[0] = 0;
}

int Islands::find(int body) {
  int root = body;
  while (parent_[static_cast<std::size_t>(root)] != root)
    root = parent_[static_cast<std::size_t>(root)];
  while (parent_[static_cast<std::size_t>(body)] != root) {  // path compression
    const int next = parent_[static_cast<std::size_t>(body)];
    parent_[static_cast<std::size_t>(body)] = root;
    body = next;
  }
  return root;
}

void Islands::unite(int a, int b) {
  a = find(a);
  b = find(b);
  if (a == b) return;
  if (size_[static_cast<std::size_t>(a)] < size_[static_cast<std::size_t>(b)]) std::swap(a, b);
  parent_[static_cast<std::size_t>(b)] = a;  // union by size
  size_[static_cast<std::size_t>(a)] += size_[static_cast<std::size_t>(b)];
}

void Islands::build(int body_count, std::span<const std::uint8_t> movable,
                    std::span<const std::pair<int, int>> links) {
  if (body_count < 0 || movable.size() != static_cast<std::size_t>(body_count))
    throw std::invalid_argument("Islands::build: movable must hold one flag per body");
  for (const auto& [a, b] : links)
    if (a < -1 || a >= body_count || b < -1 || b >= body_count)
      throw std::invalid_argument("Islands::build: link end out of range");
  const auto n = static_cast<std::size_t>(body_count);
  auto moves = [&](int body) { return body >= 0 && movable[static_cast<std::size_t>(body)] != 0; };

  parent_.resize(n);
  size_.assign(n, 1);
  for (std::size_t i = 0; i < n; ++i) parent_[i] = static_cast<int>(i);
  for (const auto& [a, b] : links)
    if (moves(a) && moves(b)) unite(a, b);

  // Number the islands in the order of their smallest body: the first body met of each set.
  // island_of_ first holds, at each root, the root's island (-1 until met).
  island_of_.assign(n, -1);
  count_ = 0;
  for (int i = 0; i < body_count; ++i) {
    if (!moves(i)) continue;
    const int root = find(i);
    int& island = island_of_[static_cast<std::size_t>(root)];
    if (island < 0) island = count_++;
    // A root r <= i already holds its island; write i's own entry only when i is not the root
    // (entries of roots > i are written when they are reached, after their root entry is set).
    if (root != i) island_of_[static_cast<std::size_t>(i)] = island;
  }

  link_island_.resize(links.size());
  for (std::size_t k = 0; k < links.size(); ++k) {
    const auto [a, b] = links[k];
    link_island_[k] = moves(a)   ? island_of_[static_cast<std::size_t>(a)]
                      : moves(b) ? island_of_[static_cast<std::size_t>(b)]
                                 : -1;
  }

  bucketByIsland(island_of_, count_, body_start_, body_list_);
  bucketByIsland(link_island_, count_, link_start_, link_list_);
}

void Islands::persist(state::Archive& a) {
  a.fields(count_, island_of_, link_island_, body_start_, body_list_, link_start_, link_list_);
}

}  // namespace linx::step
