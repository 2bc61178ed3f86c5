#include "hope/optimal_assignment.h"

#include <algorithm>
#include <limits>
#include <numeric>
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

SparseAssignment assignWithUnpairedCost(std::vector<CandidatePair> pairs, int rows, int cols,
                                        double unpaired, int max_exact) {
  pairs.erase(std::remove_if(pairs.begin(), pairs.end(),
                             [&](const CandidatePair& p) { return !(p.cost < 2 * unpaired); }),
              pairs.end());
  // Connected components over rows (nodes 0..rows-1) and columns (rows..rows+cols-1).
  std::vector<int> parent(rows + cols);
  std::iota(parent.begin(), parent.end(), 0);
  auto root = [&](int i) {
    while (parent[i] != i) i = parent[i] = parent[parent[i]];
    return i;
  };
  for (const CandidatePair& p : pairs) parent[root(p.row)] = root(rows + p.col);
  std::vector<int> component(pairs.size());
  for (std::size_t k = 0; k < pairs.size(); ++k) component[k] = root(pairs[k].row);
  std::vector<std::size_t> order(pairs.size());
  std::iota(order.begin(), order.end(), std::size_t(0));
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    if (component[a] != component[b]) return component[a] < component[b];
    return pairs[a].row != pairs[b].row ? pairs[a].row < pairs[b].row : pairs[a].col < pairs[b].col;
  });

  SparseAssignment result;
  result.col_of_row.assign(rows, -1);
  std::vector<char> col_taken(cols, 0);
  std::vector<int> local_row(rows, -1), local_col(cols, -1);
  std::vector<int> rs, cs;
  for (std::size_t begin = 0; begin < order.size();) {
    std::size_t end = begin;
    while (end < order.size() && component[order[end]] == component[order[begin]]) ++end;
    rs.clear();
    cs.clear();
    for (std::size_t k = begin; k < end; ++k) {
      const CandidatePair& p = pairs[order[k]];
      if (local_row[p.row] < 0) local_row[p.row] = static_cast<int>(rs.size()), rs.push_back(p.row);
      if (local_col[p.col] < 0) local_col[p.col] = static_cast<int>(cs.size()), cs.push_back(p.col);
    }
    const int n = static_cast<int>(rs.size()), m = static_cast<int>(cs.size());
    if (end - begin == 1) {  // the common case: nothing competes
      result.col_of_row[rs[0]] = cs[0];
    } else if (n + m > max_exact) {
      std::vector<std::size_t> by_cost(order.begin() + begin, order.begin() + end);
      std::stable_sort(by_cost.begin(), by_cost.end(),
                       [&](std::size_t a, std::size_t b) { return pairs[a].cost < pairs[b].cost; });
      for (std::size_t k : by_cost) {
        const CandidatePair& p = pairs[k];
        if (result.col_of_row[p.row] >= 0 || col_taken[p.col]) continue;
        result.col_of_row[p.row] = p.col;
        col_taken[p.col] = 1;
      }
    } else {
      // [pairs | row unpaired] over [column unpaired | nothing]; absent pairs are forbidden.
      const double forbidden = 4 * unpaired + 1.0;
      Eigen::MatrixXd augmented = Eigen::MatrixXd::Constant(n + m, m + n, forbidden);
      for (std::size_t k = begin; k < end; ++k) {
        const CandidatePair& p = pairs[order[k]];
        augmented(local_row[p.row], local_col[p.col]) = p.cost;
      }
      for (int i = 0; i < n; ++i) augmented(i, m + i) = unpaired;
      for (int j = 0; j < m; ++j) augmented(n + j, j) = unpaired;
      augmented.bottomRightCorner(m, n).setZero();
      const std::vector<int> sub = solveAssignment(augmented);
      for (int i = 0; i < n; ++i) {
        if (sub[i] >= 0 && sub[i] < m && augmented(i, sub[i]) < 2 * unpaired) {
          result.col_of_row[rs[i]] = cs[sub[i]];
        }
      }
    }
    for (int r : rs) local_row[r] = -1;
    for (int c : cs) local_col[c] = -1;
    begin = end;
  }

  // The total, from the pairs made (each row's pair looked up among its candidates).
  result.total_cost = unpaired * static_cast<double>(rows + cols);
  for (const CandidatePair& p : pairs) {
    if (result.col_of_row[p.row] == p.col) result.total_cost += p.cost - 2 * unpaired;
  }
  return result;
}

}  // namespace hope
