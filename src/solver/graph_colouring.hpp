// Graph colouring of constraints by the bodies they move (Box2D v3's constraint graph): no two
// constraints of one colour move the same body, so a colour's constraints can be solved in any
// order, split over threads, with the same result to the bit. First fit over at most 64 colours
// (a bit each in a body's mask); a constraint that finds none goes to the overflow set, solved
// after the colours on one thread. The colouring depends on the constraints' order alone.
#pragma once

#include <bit>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace linx::solver {

class GraphColouring {
 public:
  static constexpr int kColours = 64;
  /// The overflow set's number, past the colours.
  static constexpr int kOverflow = kColours;

  /// Forgets every colour taken, for `bodies` bodies.
  void reset(std::size_t bodies) { used_.assign(bodies, 0); }

  /// The lowest colour from `first` on that neither end has taken yet (an end < 0 is one that
  /// does not count: absent, static or kinematic), now taken by both; kOverflow when none is free.
  int take(int a, int b, int first = 0) {
    std::uint64_t taken = (std::uint64_t{1} << first) - 1;
    if (a >= 0) taken |= used_[static_cast<std::size_t>(a)];
    if (b >= 0) taken |= used_[static_cast<std::size_t>(b)];
    const int colour = std::countr_one(taken);  // 64 when every colour is taken
    if (colour == kOverflow) return kOverflow;
    const std::uint64_t bit = std::uint64_t{1} << colour;
    if (a >= 0) used_[static_cast<std::size_t>(a)] |= bit;
    if (b >= 0) used_[static_cast<std::size_t>(b)] |= bit;
    return colour;
  }

 private:
  std::vector<std::uint64_t> used_;  // per body: the colours of its constraints
};

}  // namespace linx::solver
