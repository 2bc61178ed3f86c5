#include "hope/optimal_assignment.h"

#include <limits>
#include <stdexcept>

namespace hope {

namespace {

// Shortest augmenting paths with row/column potentials, for rows <= cols. Index 0 is a
// sentinel, so rows and columns are 1-based inside.
std::vector<int> assignRowsToColumns(const Eigen::MatrixXd& cost) {
  const int n = static_cast<int>(cost.rows());
  const int m = static_cast<int>(cost.cols());
  const double kInf = std::numeric_limits<double>::infinity();
  std::vector<double> row_potential(n + 1, 0.0), col_potential(m + 1, 0.0);
  std::vector<int> row_of_col(m + 1, 0), previous_col(m + 1, 0);
  std::vector<double> min_slack(m + 1);
  std::vector<char> visited(m + 1);
  for (int row = 1; row <= n; ++row) {
    row_of_col[0] = row;
    int col = 0;
    std::fill(min_slack.begin(), min_slack.end(), kInf);
    std::fill(visited.begin(), visited.end(), 0);
    do {
      visited[col] = 1;
      const int r = row_of_col[col];
      double delta = kInf;
      int next = 0;
      for (int c = 1; c <= m; ++c) {
        if (visited[c]) continue;
        const double slack = cost(r - 1, c - 1) - row_potential[r] - col_potential[c];
        if (slack < min_slack[c]) {
          min_slack[c] = slack;
          previous_col[c] = col;
        }
        if (min_slack[c] < delta) {
          delta = min_slack[c];
          next = c;
        }
      }
      for (int c = 0; c <= m; ++c) {
        if (visited[c]) {
          row_potential[row_of_col[c]] += delta;
          col_potential[c] -= delta;
        } else {
          min_slack[c] -= delta;
        }
      }
      col = next;
    } while (row_of_col[col] != 0);
    do {  // augment along the path back to the sentinel
      const int prev = previous_col[col];
      row_of_col[col] = row_of_col[prev];
      col = prev;
    } while (col != 0);
  }
  std::vector<int> col_of_row(n, -1);
  for (int c = 1; c <= m; ++c) {
    if (row_of_col[c] > 0) col_of_row[row_of_col[c] - 1] = c - 1;
  }
  return col_of_row;
}

}  // namespace

std::vector<int> solveAssignment(const Eigen::MatrixXd& cost) {
  if (!cost.allFinite()) throw std::invalid_argument("solveAssignment: costs must be finite");
  if (cost.rows() == 0 || cost.cols() == 0) return std::vector<int>(cost.rows(), -1);
  if (cost.rows() <= cost.cols()) return assignRowsToColumns(cost);
  const std::vector<int> row_of_col = assignRowsToColumns(cost.transpose());
  std::vector<int> col_of_row(cost.rows(), -1);
  for (std::size_t c = 0; c < row_of_col.size(); ++c) {
    if (row_of_col[c] >= 0) col_of_row[row_of_col[c]] = static_cast<int>(c);
  }
  return col_of_row;
}

}  // namespace hope
