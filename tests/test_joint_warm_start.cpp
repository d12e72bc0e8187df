// The joint warm start must give each row the impulse its key had after the previous step, as a
// map from key to impulse would (the reference here), however the rows come and go or reorder.
#include "step/joint_warm_start.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <random>
#include <vector>

namespace {

std::vector<linx::Row> rowsWithKeys(const std::vector<std::uint64_t>& keys) {
  std::vector<linx::Row> rows(keys.size());
  for (std::size_t k = 0; k < keys.size(); ++k) rows[k].key = keys[k];
  return rows;
}

TEST(JointWarmStart, MatchesAMapOfKeysWhateverTheRowsDo) {
  std::mt19937 rng(7);
  linx::step::JointWarmStart warm;
  std::map<std::uint64_t, double> reference;  // what the previous step left, key by key
  std::vector<std::uint64_t> keys;
  for (std::uint64_t k = 0; k < 50; ++k) keys.push_back(1000 + 3 * k);
  for (int step = 0; step < 300; ++step) {
    // Now and then a limit row turns on or off, or the order changes (a joint added in between).
    const int change = static_cast<int>(rng() % 4);
    if (change == 1 && keys.size() > 1) keys.erase(keys.begin() + rng() % keys.size());
    if (change == 2) {  // keys are unique: a joint's rows have their own
      const std::uint64_t key = 5000 + rng() % 200;
      if (std::find(keys.begin(), keys.end(), key) == keys.end())
        keys.insert(keys.begin() + rng() % (keys.size() + 1), key);
    }
    if (change == 3) std::shuffle(keys.begin(), keys.end(), rng);
    const auto rows = rowsWithKeys(keys);

    std::vector<double> lambda(rows.size(), -1.0);
    warm.load(rows, lambda);
    for (std::size_t k = 0; k < rows.size(); ++k) {
      const auto it = reference.find(keys[k]);
      ASSERT_EQ(lambda[k], it == reference.end() ? 0.0 : it->second)
          << "step " << step << ", row " << k << ", key " << keys[k];
    }

    for (std::size_t k = 0; k < lambda.size(); ++k)
      lambda[k] = std::uniform_real_distribution<double>(-5.0, 5.0)(rng);
    warm.store(rows, lambda);
    reference.clear();
    for (std::size_t k = 0; k < rows.size(); ++k) reference[keys[k]] = lambda[k];
  }
}

TEST(JointWarmStart, RejectsMismatchedSizes) {
  linx::step::JointWarmStart warm;
  const auto rows = rowsWithKeys({1, 2, 3});
  std::vector<double> two(2);
  EXPECT_THROW(warm.load(rows, two), std::invalid_argument);
  EXPECT_THROW(warm.store(rows, two), std::invalid_argument);
}

}  // namespace
