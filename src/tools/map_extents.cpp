#include "hope/tools/map_extents.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>

#include "hope/grid_cell_key.h"
#include "hope/plane_outline.h"

namespace hope::tools {

namespace {

// The footprint of a point set on the grid: its cells closed (dilated, then eroded, over the
// 8 neighbours), so the gaps between a far floor's sparse rows are filled and its border is
// where the points end, not a cell beyond.
std::unordered_set<std::uint64_t> closed(const std::unordered_set<std::uint64_t>& cells) {
  std::unordered_set<std::uint64_t> dilated;
  for (std::uint64_t c : cells) {
    for (std::int64_t dy = -1; dy <= 1; ++dy) {
      for (std::int64_t dx = -1; dx <= 1; ++dx)
        dilated.insert(cellKey(cellX(c) + dx, cellY(c) + dy));
    }
  }
  std::unordered_set<std::uint64_t> out;
  for (std::uint64_t c : dilated) {
    bool inner = true;
    for (std::int64_t dy = -1; dy <= 1 && inner; ++dy) {
      for (std::int64_t dx = -1; dx <= 1 && inner; ++dx) {
        inner = dilated.count(cellKey(cellX(c) + dx, cellY(c) + dy)) > 0;
      }
    }
    if (inner) out.insert(c);
  }
  return out;
}

}  // namespace

MapExtentCheck::MapExtentCheck(double cell) : cell_(cell) {}

void MapExtentCheck::addFrame(const Result& result, const AlignedPoints& aligned,
                              const std::vector<TrackEvent>& events) {
  for (const TrackEvent& event : events) {
    auto it = seen_.find(event.id);
    if (it == seen_.end()) continue;
    if (event.kind == TrackEvent::Kind::kMerged) {
      seen_[event.other_id].insert(it->second.begin(), it->second.end());
      seen_.erase(event.id);
    } else if (event.kind == TrackEvent::Kind::kEnded) {
      seen_.erase(it);
    }
  }
  const std::size_t n = std::min(result.point_labels.size(), aligned.size());
  for (std::size_t i = 0; i < n; ++i) {
    const std::int32_t label = result.point_labels[i];
    if (label < 0 || static_cast<std::size_t>(label) >= result.planes.size()) continue;
    const Eigen::Vector3d p = aligned[i].cast<double>() + result.local_origin;
    if (!p.allFinite()) continue;
    seen_[result.planes[label].id].insert(
        cellKey(static_cast<std::int64_t>(std::floor(p.x() / cell_)),
                static_cast<std::int64_t>(std::floor(p.y() / cell_))));
  }
}

std::vector<MapExtent> MapExtentCheck::compare(const std::vector<HorizontalPlane>& surfaces) const {
  std::vector<MapExtent> out;
  const double cell_area = cell_ * cell_;
  for (const HorizontalPlane& s : surfaces) {
    MapExtent e;
    e.id = s.id;
    e.height = s.height;
    e.frames = s.age;
    const auto found = seen_.find(s.id);
    const std::unordered_set<std::uint64_t> seen =
        found == seen_.end() ? std::unordered_set<std::uint64_t>() : closed(found->second);
    const std::size_t seen_cells = seen.size();
    std::size_t map_cells = 0, both = 0;
    const auto x0 = static_cast<std::int64_t>(std::floor(s.bbox[0] / cell_));
    const auto x1 = static_cast<std::int64_t>(std::floor(s.bbox[2] / cell_));
    const auto y0 = static_cast<std::int64_t>(std::floor(s.bbox[1] / cell_));
    const auto y1 = static_cast<std::int64_t>(std::floor(s.bbox[3] / cell_));
    for (std::int64_t iy = y0; iy <= y1; ++iy) {
      for (std::int64_t ix = x0; ix <= x1; ++ix) {
        if (!outlineContains(s, (static_cast<double>(ix) + 0.5) * cell_,
                             (static_cast<double>(iy) + 0.5) * cell_)) {
          continue;
        }
        ++map_cells;
        if (seen.count(cellKey(ix, iy))) ++both;
      }
    }
    e.map_area = static_cast<double>(map_cells) * cell_area;
    e.seen_area = static_cast<double>(seen_cells) * cell_area;
    const std::size_t either = map_cells + seen_cells - both;
    e.iou = either ? static_cast<double>(both) / static_cast<double>(either) : 0.0;
    out.push_back(e);
  }
  std::sort(out.begin(), out.end(),
            [](const MapExtent& a, const MapExtent& b) { return a.seen_area > b.seen_area; });
  return out;
}

std::string formatMapExtents(const std::vector<MapExtent>& extents, std::size_t rows) {
  std::ostringstream out;
  out << "| map id | height (m) | frames seen | map outline (m²) | union of its points (m²) | "
         "area ratio | IoU in xy |\n|---:|---:|---:|---:|---:|---:|---:|\n";
  char line[200];
  for (std::size_t k = 0; k < extents.size() && k < rows; ++k) {
    const MapExtent& e = extents[k];
    std::snprintf(line, sizeof(line), "| %d | %.3f | %d | %.3f | %.3f | %.2f | %.1f %% |\n", e.id,
                  e.height, e.frames, e.map_area, e.seen_area,
                  e.seen_area > 0 ? e.map_area / e.seen_area : 0.0, 100.0 * e.iou);
    out << line;
  }
  return out.str();
}

}  // namespace hope::tools
