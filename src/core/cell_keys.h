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

// The stage's largest scratch vectors (a few MB each on a 640 × 480 frame) are kept by the
// thread from one frame to the next (thread_local, cleared on use): freed, the allocator handed
// their pages back to the system and the next frame faulted every 4 KiB of them in again, about
// half the objects stage's time on the TUM frame in a process running hope alone on this
// project's virtual machine (docs/performance.md#objects). The callers' buffers that sortByKey
// swaps with are kept too.

// Sorts (key, point) entries by key, points in their order among equal keys (they come in
// point order): the order std::sort of the pairs gives, by stable passes of 11 bits. The counts
// of every digit come from one look at the entries, and a digit that all entries share (the
// high bits of keys near one another) costs no pass. Small tables (2,048 counts a digit, not
// 16 bits' 65,536) keep a pass over a few thousand cells from being one over its table.
inline void sortByKey(std::vector<std::pair<std::uint64_t, std::uint32_t>>& entries) {
  constexpr int kBits = 11;
  constexpr int kDigits = (64 + kBits - 1) / kBits;
  constexpr std::uint64_t kMask = (std::uint64_t{1} << kBits) - 1;
  std::vector<std::uint32_t> count(static_cast<std::size_t>(kDigits) << kBits, 0);
  for (const auto& e : entries) {
    for (int d = 0; d < kDigits; ++d)
      ++count[(static_cast<std::size_t>(d) << kBits) + ((e.first >> (d * kBits)) & kMask)];
  }
  // Kept by the thread from call to call (see above).
  thread_local std::vector<std::pair<std::uint64_t, std::uint32_t>> sorted;
  for (int d = 0; d < kDigits; ++d) {
    std::uint32_t* digit = count.data() + (static_cast<std::size_t>(d) << kBits);
    if (entries.empty() ||
        digit[(entries.front().first >> (d * kBits)) & kMask] == entries.size()) {
      continue;  // one digit for all: this pass would change nothing
    }
    std::uint32_t next = 0;
    for (std::uint64_t v = 0; v <= kMask; ++v) next += std::exchange(digit[v], next);
    sorted.resize(entries.size());
    for (const auto& e : entries) sorted[digit[(e.first >> (d * kBits)) & kMask]++] = e;
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
