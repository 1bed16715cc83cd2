// Global assignment against brute force, with forbidden pairs and rectangular matrices.
#include <gtest/gtest.h>

#include <algorithm>
#include <numeric>
#include <random>

#include "scene_graph_tracker/tracking/assignment.hpp"

namespace sgt {
namespace {

TEST(Assignment, GlobalBeatsGreedy) {
  // Greedy takes (0,0)=1 and must then pay (1,1)=10; the optimum pays 2 + 2.
  Eigen::MatrixXd c(2, 2);
  c << 1, 2, 2, 10;
  EXPECT_EQ(assignMinCost(c, 100), (std::vector<int>{1, 0}));
}

TEST(Assignment, ForbiddenPairsStayUnassigned) {
  Eigen::MatrixXd c(3, 2);
  c << 1, 100, 100, 100, 100, 3;
  EXPECT_EQ(assignMinCost(c, 50), (std::vector<int>{0, -1, 1}));
}

TEST(Assignment, MatchesBruteForceOnRandomMatrices) {
  std::mt19937 rng(4);
  std::uniform_real_distribution<double> u(0, 10);
  for (int trial = 0; trial < 200; ++trial) {
    const int rows = 1 + trial % 5, cols = 1 + (trial / 5) % 5;
    Eigen::MatrixXd c(rows, cols);
    for (int r = 0; r < rows; ++r)
      for (int k = 0; k < cols; ++k) c(r, k) = u(rng) < 2 ? 1e9 : u(rng);
    const auto got = assignMinCost(c, 1e6);
    // Brute force: every injective partial map rows -> cols; maximise the number of pairs, then
    // minimise the cost (what the padding with a large cost achieves).
    std::vector<int> cols_perm(std::max(rows, cols));
    std::iota(cols_perm.begin(), cols_perm.end(), 0);
    int best_n = -1;
    double best_cost = 0;
    do {
      int n = 0;
      double total = 0;
      for (int r = 0; r < rows; ++r)
        if (cols_perm[r] < cols && c(r, cols_perm[r]) < 1e6) ++n, total += c(r, cols_perm[r]);
      if (n > best_n || (n == best_n && total < best_cost - 1e-9)) best_n = n, best_cost = total;
    } while (std::next_permutation(cols_perm.begin(), cols_perm.end()));
    int n = 0;
    double total = 0;
    for (int r = 0; r < rows; ++r)
      if (got[r] >= 0) ++n, total += c(r, got[r]);
    EXPECT_EQ(n, best_n) << trial;
    EXPECT_NEAR(total, best_cost, 1e-9) << trial;
  }
}

}  // namespace
}  // namespace sgt
