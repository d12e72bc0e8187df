// Suggesting the intended name for a misspelt one: a scene's field or body, a flag.
#pragma once

#include <cstddef>
#include <string_view>

namespace linx::io {

/// Levenshtein distance: the fewest insertions, deletions and substitutions from a to b.
std::size_t editDistance(std::string_view a, std::string_view b);

/// The one of `names` closest to `name`, at most two edits away; empty when none is.
template <typename Names>
std::string_view closestName(std::string_view name, const Names& names) {
  std::string_view best;
  std::size_t best_distance = 3;
  for (std::string_view candidate : names) {
    const std::size_t d = editDistance(name, candidate);
    if (d < best_distance) {
      best = candidate;
      best_distance = d;
    }
  }
  return best;
}

}  // namespace linx::io
