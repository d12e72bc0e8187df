// The loops of src/parallel/: every index visited exactly once on any thread count, phases one
// after another, and an exception thrown on a worker thread reaches the caller instead of ending
// the program.
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

// Phases of uneven sizes (some below the grain, run by one thread of the team): every item once,
// and no item of a phase before every item of the phases before it (each item records how many
// items had finished when it started, which must be at least the sizes of the earlier phases).
TEST(Parallel, PhasesOneAfterAnotherEveryItemOnce) {
  const std::vector<std::ptrdiff_t> sizes = {300, 5, 0, 120, 1, 64, 700};
  for (const int threads : {1, 2, 3}) {
    std::vector<std::vector<int>> hits(sizes.size());
    std::vector<std::vector<long>> started(sizes.size());
    for (std::size_t p = 0; p < sizes.size(); ++p) {
      hits[p].assign(static_cast<std::size_t>(sizes[p]), 0);
      started[p].assign(static_cast<std::size_t>(sizes[p]), -1);
    }
    long done = 0;
    forEachInPhases(
        static_cast<int>(sizes.size()), threads, 32,
        [&](int p) { return sizes[static_cast<std::size_t>(p)]; },
        [&](int p, std::ptrdiff_t i) {
          long before = 0;
#pragma omp atomic read
          before = done;
          started[static_cast<std::size_t>(p)][static_cast<std::size_t>(i)] = before;
          ++hits[static_cast<std::size_t>(p)][static_cast<std::size_t>(i)];
#pragma omp atomic
          ++done;
        });
    long earlier = 0;
    for (std::size_t p = 0; p < sizes.size(); ++p) {
      EXPECT_EQ(hits[p], std::vector<int>(hits[p].size(), 1)) << threads << " threads, phase " << p;
      for (const long s : started[p]) EXPECT_GE(s, earlier) << threads << " threads, phase " << p;
      earlier += sizes[p];
    }
    EXPECT_EQ(done, earlier);
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
    EXPECT_THROW(forEachInPhases(
                     3, threads, 16, [](int) { return std::ptrdiff_t{100}; },
                     [](int p, std::ptrdiff_t i) {
                       if (p == 1 && i == 50) throw std::out_of_range("phase 1");
                     }),
                 std::out_of_range);
  }
}

TEST(Parallel, ZeroMeansOneThreadPerHardwareThread) {
  EXPECT_EQ(resolveThreads(3), 3);
  EXPECT_GE(resolveThreads(0), 1);
}

}  // namespace
}  // namespace linx::parallel
