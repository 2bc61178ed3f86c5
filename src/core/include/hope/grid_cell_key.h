// A cell (ix, iy) of an xy grid as one 64-bit key: 32 bits each, offset so that negative
// indices fit (|index| < 2^31). The surface map keeps its extents in such keys; the tools that
// compare footprints on a grid use the same.
#pragma once

#include <cstdint>

namespace hope {

inline constexpr std::int64_t kCellKeyOffset = std::int64_t{1} << 31;

inline std::uint64_t cellKey(std::int64_t ix, std::int64_t iy) {
  return (static_cast<std::uint64_t>(ix + kCellKeyOffset) << 32) |
         static_cast<std::uint64_t>(iy + kCellKeyOffset);
}
inline std::int64_t cellX(std::uint64_t key) {
  return static_cast<std::int64_t>(key >> 32) - kCellKeyOffset;
}
inline std::int64_t cellY(std::uint64_t key) {
  return static_cast<std::int64_t>(key & 0xffffffffu) - kCellKeyOffset;
}

}  // namespace hope
