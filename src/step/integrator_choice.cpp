#include "step/integrator_choice.hpp"

#include "world/state_archive.hpp"

#include <algorithm>

namespace linx::step {

int IntegratorChoice::keepTrying(const Islands& islands, std::vector<std::uint8_t>& accurate) {
  const std::size_t n = accurate.size();
  wait_.resize(n, 0);
  backoff_.resize(n, 0);
  for (std::int32_t& w : wait_) w = std::max(0, w - 1);
  // An island waits as long as its longest-waiting body: bodies that tried apart and now share
  // an island try again together.
  island_wait_.assign(static_cast<std::size_t>(islands.count()), 0);
  island_limit_.assign(static_cast<std::size_t>(islands.count()), 1.0);
  for (std::size_t i = 0; i < n; ++i) {
    const int island = islands.islandOf(static_cast<int>(i));
    if (accurate[i] && island >= 0) {
      const auto k = static_cast<std::size_t>(island);
      island_wait_[k] = std::max(island_wait_[k], wait_[i]);
      if (backoff_[i] > 0) island_limit_[k] = kReturnMargin;
    }
  }
  int count = 0;
  for (std::size_t i = 0; i < n; ++i) {
    if (!accurate[i]) continue;
    const int island = islands.islandOf(static_cast<int>(i));
    if (island_wait_[static_cast<std::size_t>(island)] > 0)
      accurate[i] = 0;
    else
      ++count;
  }
  return count;
}

void IntegratorChoice::record(std::span<const std::uint8_t> tried,
                              std::span<const std::uint8_t> kept) {
  for (std::size_t i = 0; i < tried.size() && i < wait_.size(); ++i) {
    if (!tried[i]) continue;
    if (kept[i]) {
      backoff_[i] = 0;
      wait_[i] = 0;
    } else {
      backoff_[i] = backoff_[i] == 0 ? kFirstWait : std::min(2 * backoff_[i], kLongestWait);
      wait_[i] = backoff_[i];
    }
  }
}

void IntegratorChoice::persist(state::Archive& archive) {
  archive.fields(wait_, backoff_);
  if (!archive.loading()) return;
  // The waits this class writes lie within [0, kLongestWait]; others are a damaged state.
  const auto within = [](std::int32_t w) { return w >= 0 && w <= kLongestWait; };
  if (!std::all_of(wait_.begin(), wait_.end(), within) ||
      !std::all_of(backoff_.begin(), backoff_.end(), within))
    throw state::StateError("integrator waits out of range");
}

}  // namespace linx::step
