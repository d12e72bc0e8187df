// Slots of a world's bodies or joints: which are in use, each one's generation, and the free ones
// a new body or joint takes first. Removing frees a slot and moves it to its next generation, so
// an id kept past the removal (slot, generation) no longer matches and refers to nothing, even
// after the slot is taken again. Indices stay put: the step's arrays are indexed by slot.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace linx {

class Slots {
 public:
  /// The slot the next take() returns: the most recently freed one, else a new one (size()).
  int next() const { return free_.empty() ? size() : free_.back(); }
  /// Takes next() and returns it.
  int take() {
    const int slot = next();
    if (free_.empty()) {
      generation_.push_back(0);
      used_.push_back(1);
    } else {
      free_.pop_back();
      used_[static_cast<std::size_t>(slot)] = 1;
    }
    return slot;
  }
  /// Frees a slot in use: its generation moves on.
  void release(int slot) {
    used_[static_cast<std::size_t>(slot)] = 0;
    ++generation_[static_cast<std::size_t>(slot)];
    free_.push_back(slot);
  }
  int size() const { return static_cast<int>(used_.size()); }
  int count() const { return size() - static_cast<int>(free_.size()); }  ///< slots in use
  bool used(int slot) const {
    return slot >= 0 && slot < size() && used_[static_cast<std::size_t>(slot)] != 0;
  }
  std::uint32_t generation(int slot) const { return generation_[static_cast<std::size_t>(slot)]; }
  /// Whether (slot, generation) is a slot in use in that generation.
  bool matches(int slot, std::uint32_t generation) const {
    return used(slot) && generation_[static_cast<std::size_t>(slot)] == generation;
  }

 private:
  std::vector<std::uint32_t> generation_;
  std::vector<std::uint8_t> used_;
  std::vector<int> free_;
};

}  // namespace linx
