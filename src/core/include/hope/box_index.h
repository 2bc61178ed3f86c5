// A spatial hash of level boxes: an xy box [x_min, y_min, x_max, y_max] at a height. The boxes
// near a query box, in xy and in height, are found without comparing it with every box, so
// matching n planes against n tracks costs about n, not n² (the tracker's gating).
#pragma once

#include <array>
#include <cstdint>
#include <vector>

namespace hope {

class BoxIndex {
 public:
  using Box = std::array<double, 4>;

  // Indexes boxes (xy extent and height) in cells of `cell` metres across and `height_cell`
  // metres high (both > 0), reusing the memory of the last call. A box covering more than a
  // few dozen cells (a floor) is kept in a short list that every query visits; a box that is
  // not finite (or beyond 10^12 cells) is never visited.
  void rebuild(const std::vector<Box>& boxes, const std::vector<double>& heights, double cell,
               double height_cell);

  // Calls visit(i) once for every box i that may lie within `margin` of `query` in xy and
  // within `height_margin` of `height` (a superset: the caller applies its exact test).
  template <class Visit>
  void forEachNear(const Box& query, double height, double margin, double height_margin,
                   Visit visit) const {
    ++query_;
    for (int i : large_) visitOnce(i, visit);
    Span s;
    if (!span(query, height, margin, height_margin, s)) return;  // not finite: nothing passes
    if (double(s.x1 - s.x0 + 1) * double(s.y1 - s.y0 + 1) * double(s.z1 - s.z0 + 1) >
        double(slot_boxes_.size())) {
      for (int i : slot_boxes_) visitOnce(i, visit);  // a huge query: walk everything once
      return;
    }
    for (std::int64_t z = s.z0; z <= s.z1; ++z)
      for (std::int64_t x = s.x0; x <= s.x1; ++x)
        for (std::int64_t y = s.y0; y <= s.y1; ++y) {
          const std::size_t slot = slotOf(x, y, z);
          for (std::uint32_t k = slot_start_[slot]; k < slot_start_[slot + 1]; ++k) {
            visitOnce(slot_boxes_[k], visit);
          }
        }
  }

 private:
  struct Span {
    std::int64_t x0, y0, z0, x1, y1, z1;
  };
  template <class Visit>
  void visitOnce(int i, Visit& visit) const {
    if (seen_[i] == query_) return;
    seen_[i] = query_;
    visit(i);
  }
  // Cells hash into a table of slots (a power of two); cells that share a slot only add
  // candidates, which the caller's exact test rejects.
  std::size_t slotOf(std::int64_t x, std::int64_t y, std::int64_t z) const {
    const std::uint64_t h = static_cast<std::uint64_t>(x) * 73856093u ^
                            static_cast<std::uint64_t>(y) * 19349663u ^
                            static_cast<std::uint64_t>(z) * 83492791u;
    return static_cast<std::size_t>((h ^ (h >> 29)) & mask_);
  }
  // The cells a box grown by the margins covers; false when it is not finite, inverted or
  // beyond 10^12 cells.
  bool span(const Box& box, double height, double margin, double height_margin, Span& s) const;

  double per_cell_ = 1.0, per_height_cell_ = 1.0;  // inverse cell sizes
  std::uint64_t mask_ = 0;
  std::vector<std::uint32_t> slot_start_;  // boxes of slot k: slot_boxes_[start[k], start[k+1])
  std::vector<int> slot_boxes_;
  std::vector<int> large_;
  std::vector<Span> spans_;                  // scratch for rebuild
  mutable std::vector<std::uint32_t> seen_;  // query stamp per box: each visited once
  mutable std::uint32_t query_ = 0;
};

}  // namespace hope
