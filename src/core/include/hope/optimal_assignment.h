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

// A pair that may be made, with its cost.
struct CandidatePair {
  int row;
  int col;
  double cost;
};

struct SparseAssignment {
  std::vector<int> col_of_row;  // for each row, its column or -1
  double total_cost = 0;        // the pairs' costs plus `unpaired` per row and column left out
};

// Above this many rows + columns in one connected component, pairs are made greedily.
constexpr int kMaxExactComponent = 128;

// Pairs rows with columns among `pairs` only, where leaving a row or a column unpaired costs
// `unpaired` each: a pair is made only when it costs less than 2 · unpaired (pairs that cost
// more are ignored), so poor pairs are never forced. Solved optimally (Hungarian method) per
// connected component of the pairs: rows and columns that share no pair never compete, so
// with a spread-out scene components are small and the time grows with the number of pairs.
// A component larger than `max_exact` rows + columns (hundreds of fragments competing for one
// place) is paired greedily, cheapest pair first, which bounds the time.
SparseAssignment assignWithUnpairedCost(std::vector<CandidatePair> pairs, int rows, int cols,
                                        double unpaired, int max_exact = kMaxExactComponent);

}  // namespace hope
