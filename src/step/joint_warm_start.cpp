#include "step/joint_warm_start.hpp"

#include "world/state_archive.hpp"

#include <algorithm>
#include <stdexcept>

namespace linx::step {

void JointWarmStart::load(std::span<const Row> rows, std::span<double> lambda) {
  if (lambda.size() != rows.size())
    throw std::invalid_argument("JointWarmStart::load: one impulse per row");
  for (std::size_t k = 0; k < rows.size(); ++k) {
    const std::uint64_t key = rows[k].key;
    if (k < keys_.size() && keys_[k] == key) {
      lambda[k] = lambda_[k];
      continue;
    }
    if (!sorted_ready_) {
      sorted_.resize(keys_.size());
      for (std::size_t j = 0; j < keys_.size(); ++j) sorted_[j] = {keys_[j], static_cast<int>(j)};
      std::sort(sorted_.begin(), sorted_.end());
      sorted_ready_ = true;
    }
    // The last stored row of this key, as a map that each store overwrote would give.
    const auto end = std::upper_bound(
        sorted_.begin(), sorted_.end(), key,
        [](std::uint64_t x, const std::pair<std::uint64_t, int>& e) { return x < e.first; });
    lambda[k] = end != sorted_.begin() && std::prev(end)->first == key
                    ? lambda_[static_cast<std::size_t>(std::prev(end)->second)]
                    : 0.0;
  }
}

void JointWarmStart::store(std::span<const Row> rows, std::span<const double> lambda) {
  if (lambda.size() < rows.size())
    throw std::invalid_argument("JointWarmStart::store: one impulse per row");
  keys_.resize(rows.size());
  lambda_.resize(rows.size());
  for (std::size_t k = 0; k < rows.size(); ++k) {
    keys_[k] = rows[k].key;
    lambda_[k] = lambda[k];
  }
  sorted_ready_ = false;
}

void JointWarmStart::forget(std::size_t joint) {
  for (std::size_t k = 0; k < keys_.size(); ++k)
    if ((keys_[k] >> 8) == joint + 1) lambda_[k] = 0.0;
}

void JointWarmStart::persist(state::Archive& a) {
  a.fields(keys_, lambda_, sorted_, sorted_ready_);
}

}  // namespace linx::step
