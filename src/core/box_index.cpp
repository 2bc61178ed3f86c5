#include "hope/box_index.h"

#include <cmath>

namespace hope {

namespace {
// A box spanning more cells than this is visited by every query instead of being entered in
// each of its cells: a 20 m floor in 0.4 m cells would otherwise fill 2,500 of them.
constexpr std::int64_t kMaxCellsPerBox = 64;
// Cell coordinates are kept far inside 64 bits (10^12 cells of 1 cm: 10^7 km).
constexpr double kMaxCellCoordinate = 1e12;
}  // namespace

void BoxIndex::rebuild(const std::vector<Box>& boxes, const std::vector<double>& heights,
                       double cell, double height_cell) {
  per_cell_ = 1.0 / (cell > 0 && std::isfinite(cell) ? cell : 1.0);
  per_height_cell_ = 1.0 / (height_cell > 0 && std::isfinite(height_cell) ? height_cell : 1.0);
  large_.clear();
  seen_.assign(boxes.size(), 0);
  query_ = 0;
  spans_.assign(boxes.size(), Span{0, 0, 0, -1, -1, -1});
  std::size_t entries = 0;
  for (std::size_t i = 0; i < boxes.size(); ++i) {
    Span& s = spans_[i];
    if (!span(boxes[i], heights[i], 0.0, 0.0, s)) continue;  // not finite: nowhere
    const std::int64_t cells = (s.x1 - s.x0 + 1) * (s.y1 - s.y0 + 1) * (s.z1 - s.z0 + 1);
    if (cells > kMaxCellsPerBox) {
      large_.push_back(static_cast<int>(i));
      s = Span{0, 0, 0, -1, -1, -1};
      continue;
    }
    entries += static_cast<std::size_t>(cells);
  }
  std::size_t slots = 64;
  while (slots < 2 * entries) slots *= 2;
  mask_ = slots - 1;
  // Counting sort of (slot, box) by slot.
  slot_start_.assign(slots + 1, 0);
  auto forEachCell = [&](const Span& s, auto f) {
    for (std::int64_t z = s.z0; z <= s.z1; ++z)
      for (std::int64_t x = s.x0; x <= s.x1; ++x)
        for (std::int64_t y = s.y0; y <= s.y1; ++y) f(slotOf(x, y, z));
  };
  for (const Span& s : spans_) forEachCell(s, [&](std::size_t slot) { ++slot_start_[slot + 1]; });
  for (std::size_t k = 0; k < slots; ++k) slot_start_[k + 1] += slot_start_[k];
  slot_boxes_.resize(entries);
  // Filling advances each slot's start to its end; a shift by one slot restores the starts.
  for (std::size_t i = 0; i < spans_.size(); ++i) {
    forEachCell(spans_[i],
                [&](std::size_t slot) { slot_boxes_[slot_start_[slot]++] = static_cast<int>(i); });
  }
  for (std::size_t k = slots; k > 0; --k) slot_start_[k] = slot_start_[k - 1];
  slot_start_[0] = 0;
}

bool BoxIndex::span(const Box& box, double height, double margin, double height_margin,
                    Span& s) const {
  const double v[6] = {std::floor((box[0] - margin) * per_cell_),
                       std::floor((box[1] - margin) * per_cell_),
                       std::floor((height - height_margin) * per_height_cell_),
                       std::floor((box[2] + margin) * per_cell_),
                       std::floor((box[3] + margin) * per_cell_),
                       std::floor((height + height_margin) * per_height_cell_)};
  for (double c : v) {
    if (!(std::fabs(c) <= kMaxCellCoordinate)) return false;
  }
  if (v[3] < v[0] || v[4] < v[1] || v[5] < v[2]) return false;
  s = {std::int64_t(v[0]), std::int64_t(v[1]), std::int64_t(v[2]),
       std::int64_t(v[3]), std::int64_t(v[4]), std::int64_t(v[5])};
  return true;
}

}  // namespace hope
