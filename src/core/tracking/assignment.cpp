#include "scene_graph_tracker/tracking/assignment.hpp"

#include <cmath>
#include <limits>

namespace sgt {

std::vector<int> assignMinCost(const Eigen::MatrixXd& cost, double forbidden) {
  const int rows = static_cast<int>(cost.rows()), cols = static_cast<int>(cost.cols());
  std::vector<int> out(rows, -1);
  if (rows == 0 || cols == 0) return out;
  // Square matrix: forbidden pairs and padding cost `big` (more than any real assignment set).
  const int n = std::max(rows, cols);
  double max_real = 0.0;
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < cols; ++c)
      if (std::isfinite(cost(r, c)) && cost(r, c) < forbidden)
        max_real = std::max(max_real, std::abs(cost(r, c)));
  const double big = (max_real + 1.0) * (n + 1);
  Eigen::MatrixXd a = Eigen::MatrixXd::Constant(n, n, big);
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < cols; ++c)
      if (std::isfinite(cost(r, c)) && cost(r, c) < forbidden) a(r, c) = cost(r, c);
  // Jonker-Volgenant style shortest augmenting paths with potentials (1-based).
  const double inf = std::numeric_limits<double>::infinity();
  std::vector<double> u(n + 1, 0.0), v(n + 1, 0.0);
  std::vector<int> p(n + 1, 0), way(n + 1, 0);
  for (int i = 1; i <= n; ++i) {
    p[0] = i;
    int j0 = 0;
    std::vector<double> minv(n + 1, inf);
    std::vector<char> used(n + 1, 0);
    do {
      used[j0] = 1;
      const int i0 = p[j0];
      double delta = inf;
      int j1 = 0;
      for (int j = 1; j <= n; ++j) {
        if (used[j]) continue;
        const double cur = a(i0 - 1, j - 1) - u[i0] - v[j];
        if (cur < minv[j]) minv[j] = cur, way[j] = j0;
        if (minv[j] < delta) delta = minv[j], j1 = j;
      }
      for (int j = 0; j <= n; ++j) {
        if (used[j])
          u[p[j]] += delta, v[j] -= delta;
        else
          minv[j] -= delta;
      }
      j0 = j1;
    } while (p[j0] != 0);
    do {
      const int j1 = way[j0];
      p[j0] = p[j1];
      j0 = j1;
    } while (j0 != 0);
  }
  for (int j = 1; j <= n; ++j) {
    const int r = p[j] - 1, c = j - 1;
    if (r < rows && c < cols && a(r, c) < big) out[r] = c;
  }
  return out;
}

}  // namespace sgt
