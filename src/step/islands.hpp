// Simulation islands: the groups of movable bodies that interact through the links of a step
// (joints, contacts). Islands are independent problems: each can be solved on its own, and each
// can fall asleep or be woken as a whole.
//
// A link joins two bodies; an end that is -1 (the world) or a non-movable (static) body does not
// connect anything, so a static ground shared by two stacks leaves them two islands. A movable body
// without links is an island of its own. Non-movable bodies belong to no island.
//
// Numbering is deterministic: islands are ordered by their smallest body index, bodies within an
// island ascend, and so do the links of an island. The result depends only on the input, not on
// the order in which union-find happens to join its sets.
#pragma once

#include <cstdint>
#include <span>
#include <utility>
#include <vector>

namespace linx::state {
class Archive;
}

namespace linx::step {

/// Counting sort of items 0..n-1 by their island (island_of[k], -1 skipped): the items of island i
/// are list[start[i]..start[i+1]), ascending. `start` gets count + 1 entries.
void bucketByIsland(std::span<const int> island_of, int count, std::vector<int>& start,
                    std::vector<int>& list);

class Islands {
 public:
  /// Groups bodies 0..body_count-1. movable[i] != 0 marks body i movable (movable.size() must be
  /// body_count); each link is a pair of body indices, either of which may be -1 (the world).
  /// Union-find with path compression and union by size: O((bodies + links) alpha).
  /// Reuses its buffers: no allocation once they have grown to the problem's size.
  /// Throws std::invalid_argument on a size mismatch or a body index out of range.
  void build(int body_count, std::span<const std::uint8_t> movable,
             std::span<const std::pair<int, int>> links);

  /// Number of islands.
  int count() const { return count_; }
  /// Number of bodies and links given to the last build.
  int bodyCount() const { return static_cast<int>(island_of_.size()); }
  int linkCount() const { return static_cast<int>(link_island_.size()); }

  /// Bodies of an island, ascending body indices.
  std::span<const int> bodies(int island) const { return slice(body_list_, body_start_, island); }
  /// Indices into the build's `links` of the links in an island, ascending. A link belongs to the
  /// island of its movable end(s); a link with no movable end belongs to no island.
  std::span<const int> links(int island) const { return slice(link_list_, link_start_, island); }
  /// Island of a body, -1 for a non-movable body.
  int islandOf(int body) const { return island_of_[static_cast<std::size_t>(body)]; }
  /// Island of a link, -1 for a link with no movable end.
  int islandOfLink(int link) const { return link_island_[static_cast<std::size_t>(link)]; }

  /// Reads or writes the last build's islands (World::saveState): what the step after a
  /// restore, and the queries between steps, read before the next build.
  void persist(state::Archive& archive);

 private:
  static std::span<const int> slice(const std::vector<int>& list, const std::vector<int>& start,
                                    int island) {
    const auto b = static_cast<std::size_t>(start[static_cast<std::size_t>(island)]);
    const auto e = static_cast<std::size_t>(start[static_cast<std::size_t>(island) + 1]);
    return std::span<const int>(list).subspan(b, e - b);
  }
  int find(int body);
  void unite(int a, int b);

  int count_ = 0;
  // union-find
  std::vector<int> parent_, size_;
  // results: island of each body and link; CSR lists of each island's bodies and links
  std::vector<int> island_of_, link_island_;
  std::vector<int> body_start_, body_list_;
  std::vector<int> link_start_, link_list_;
};

}  // namespace linx::step
