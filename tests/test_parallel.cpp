// The loops of src/parallel/: every index visited exactly once on any thread count, and an
// exception thrown on a worker thread reaches the caller instead of ending the program.
#include "parallel/parallel_for.hpp"

#include <gtest/gtest.h>

#include <stdexcept>
#include <vector>

namespace linx::parallel {
namespace {

TEST(Parallel, EveryIndexOnceForAnyThreadCount) {
  for (const int threads : {1, 2, 3, 8}) {
    std::vector<int> hits(10000, 0);
    forEach(static_cast<std::ptrdiff_t>(hits.size()), threads, 16,
            [&](std::ptrdiff_t i) { ++hits[static_cast<std::size_t>(i)]; });
    std::vector<int> tasks(37, 0);
    forEachTask(static_cast<std::ptrdiff_t>(tasks.size()), threads,
                [&](std::ptrdiff_t t) { ++tasks[static_cast<std::size_t>(t)]; });
    EXPECT_EQ(hits, std::vector<int>(hits.size(), 1)) << threads << " threads";
    EXPECT_EQ(tasks, std::vector<int>(tasks.size(), 1)) << threads << " threads";
  }
}

TEST(Parallel, AnExceptionOnAWorkerReachesTheCaller) {
  for (const int threads : {1, 2, 4}) {
    EXPECT_THROW(forEach(1000, threads, 16,
                         [](std::ptrdiff_t i) {
                           if (i == 777) throw std::runtime_error("row 777");
                         }),
                 std::runtime_error);
    EXPECT_THROW(forEachTask(9, threads,
                             [](std::ptrdiff_t t) {
                               if (t % 4 == 3) throw std::length_error("task");
                             }),
                 std::length_error);
  }
}

TEST(Parallel, ZeroMeansOneThreadPerHardwareThread) {
  EXPECT_EQ(resolveThreads(3), 3);
  EXPECT_GE(resolveThreads(0), 1);
}

}  // namespace
}  // namespace linx::parallel
