// The graph colouring shared by PGS and the soft step (solver/graph_colouring.hpp): what makes a
// colour's constraints safe to solve side by side is that no two of them move the same body.
// Checked on random constraint graphs against that definition, and first fit against a graph
// whose colouring is known: a body in k constraints needs k colours, a star needs all 64 and
// overflows beyond.
#include "solver/graph_colouring.hpp"

#include <gtest/gtest.h>

#include <random>
#include <set>
#include <utility>
#include <vector>

namespace linx::solver {
namespace {

TEST(GraphColouring, NoTwoConstraintsOfAColourShareABody) {
  std::mt19937 random(7);
  for (const int bodies : {10, 200, 5000}) {
    std::uniform_int_distribution<int> body(-1, bodies - 1);  // -1: an end that does not count
    std::vector<std::pair<int, int>> edges(static_cast<std::size_t>(bodies) * 3);
    for (auto& e : edges) {
      e = {body(random), body(random)};
      if (e.first == e.second) e.second = -1;  // a constraint's two ends are two bodies
    }
    GraphColouring colouring;
    colouring.reset(static_cast<std::size_t>(bodies));
    std::vector<std::set<int>> of_colour(GraphColouring::kColours);
    int overflow = 0;
    for (const auto& [a, b] : edges) {
      const int c = colouring.take(a, b);
      if (c == GraphColouring::kOverflow) {
        ++overflow;
        continue;
      }
      ASSERT_GE(c, 0);
      ASSERT_LT(c, GraphColouring::kColours);
      std::set<int>& used = of_colour[static_cast<std::size_t>(c)];
      for (const int end : {a, b}) {
        if (end < 0) continue;
        EXPECT_FALSE(used.count(end)) << "body " << end << " twice in colour " << c;
        used.insert(end);
      }
    }
    // A random graph of 3 constraints per body (6 ends) has no body near 64 constraints.
    EXPECT_EQ(overflow, 0) << bodies << " bodies";
  }
}

TEST(GraphColouring, FirstFitStartsWhereAskedAndOverflowsPastSixtyFour) {
  GraphColouring colouring;
  colouring.reset(100);
  // A star: body 0 in 70 constraints takes colours 0, 1, ..., 63, then the overflow set.
  for (int k = 0; k < 70; ++k) {
    const int c = colouring.take(0, k + 1 < 100 ? k + 1 : -1);
    EXPECT_EQ(c, k < 64 ? k : GraphColouring::kOverflow) << "constraint " << k;
  }
  // Disjoint bodies share colour 0; from `first` = 1 (the soft step's contacts with a static
  // end), colour 1; ends that do not count never block a colour.
  colouring.reset(10);
  EXPECT_EQ(colouring.take(1, 2), 0);
  EXPECT_EQ(colouring.take(3, 4), 0);
  EXPECT_EQ(colouring.take(5, -1, 1), 1);
  EXPECT_EQ(colouring.take(5, -1, 1), 2);
  EXPECT_EQ(colouring.take(-1, -1), 0);
  EXPECT_EQ(colouring.take(2, 5), 3);  // body 2 has colour 0, body 5 colours 1 and 2
}

}  // namespace
}  // namespace linx::solver
