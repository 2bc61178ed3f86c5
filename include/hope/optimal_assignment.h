// Minimum-cost one-to-one assignment (the Hungarian method), for plane tracking.
#pragma once

#include <vector>

#include <Eigen/Core>

namespace hope {

// Pairs rows with columns so that the sum of `cost(row, col)` over the pairs is minimal,
// pairing min(rows, cols) of them. Returns, for each row, its column or -1. Costs must be
// finite; forbid a pair by giving it a cost above any acceptable one and discarding such
// pairs afterwards. O(n² m) for n = min(rows, cols), m = max(rows, cols).
std::vector<int> solveAssignment(const Eigen::MatrixXd& cost);

}  // namespace hope
