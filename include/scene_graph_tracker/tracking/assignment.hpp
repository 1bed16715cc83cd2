// Globally optimal assignment (Hungarian / Kuhn-Munkres, O(n^3)) of rows to columns.
#pragma once

#include <Eigen/Core>
#include <vector>

namespace sgt {

// cost(r, c); entries >= `forbidden` (or not finite) are never assigned. Returns, per row, the
// assigned column or -1. Minimises the total cost of the assigned pairs.
std::vector<int> assignMinCost(const Eigen::MatrixXd& cost, double forbidden);

}  // namespace sgt
