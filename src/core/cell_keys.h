// Helpers for the stages that group points on a grid of cells by sorting their keys
// (standing_objects.cpp, crease_splitting.cpp): internal to the core.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <numeric>
#include <utility>
#include <vector>

namespace hope {

// Sorts (key, point) entries by key, points in their order among equal keys (they come in
// point order): the order std::sort of the pairs gives, by four passes of 16 bits.
inline void sortByKey(std::vector<std::pair<std::uint64_t, std::uint32_t>>& entries) {
  std::vector<std::pair<std::uint64_t, std::uint32_t>> sorted(entries.size());
  std::vector<std::size_t> start(65537);
  for (int shift = 0; shift < 64; shift += 16) {
    std::fill(start.begin(), start.end(), 0);
    for (const auto& e : entries) ++start[((e.first >> shift) & 0xffff) + 1];
    if (start[((entries.empty() ? 0 : entries.front().first >> shift) & 0xffff) + 1] ==
        entries.size()) {
      continue;  // one digit for all: this pass would change nothing
    }
    for (std::size_t d = 1; d < start.size(); ++d) start[d] += start[d - 1];
    for (const auto& e : entries) sorted[start[(e.first >> shift) & 0xffff]++] = e;
    entries.swap(sorted);
  }
}

struct UnionFind {
  std::vector<std::uint32_t> parent;
  explicit UnionFind(std::size_t n) : parent(n) { std::iota(parent.begin(), parent.end(), 0u); }
  std::uint32_t find(std::uint32_t a) {
    while (parent[a] != a) a = parent[a] = parent[parent[a]];
    return a;
  }
  void join(std::uint32_t a, std::uint32_t b) {
    a = find(a), b = find(b);
    if (a != b) parent[std::max(a, b)] = std::min(a, b);
  }
};

}  // namespace hope
