// Warm start of the joint rows: each row starts from the impulse its key had at the end of the
// previous step. Joint rows come out of assembly in the same order step after step (until a
// limit turns on or off, or a joint is added), so keys are matched by position first and, past
// the first mismatch, through a sorted copy of the previous keys. Nothing allocates once the
// buffers have grown to the number of joint rows: a hash map of keys allocated a node per row
// per step (5,000 per step on a 1000-link chain). Keys are unique among a step's joint rows (a
// joint's id and the row's slot): with a repeated key, a row would get the impulse of the row at
// its own position, or, past a mismatch, of the last stored row with that key.
#pragma once

#include <linx/row.hpp>

#include <cstdint>
#include <span>
#include <utility>
#include <vector>

namespace linx::state {
class Archive;
}

namespace linx::step {

class JointWarmStart {
 public:
  /// lambda[k] = the impulse stored for rows[k].key, or 0 when the key was not stored.
  void load(std::span<const Row> rows, std::span<double> lambda);
  /// Keeps the impulses of these rows for the next load (replacing what was kept).
  void store(std::span<const Row> rows, std::span<const double> lambda);
  /// Zeroes what was kept for joint `joint`'s rows (key (joint + 1) << 8 | slot): a removed
  /// joint's slot, which a new joint may take before the next store.
  void forget(std::size_t joint);

  /// Reads or writes what carries to the next step (World::saveState).
  void persist(state::Archive& archive);

 private:
  std::vector<std::uint64_t> keys_;  // the stored rows' keys, in their order
  std::vector<double> lambda_;
  std::vector<std::pair<std::uint64_t, int>> sorted_;  // (key, position), built on a mismatch
  bool sorted_ready_ = false;
};

}  // namespace linx::step
