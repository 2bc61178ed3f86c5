// How well the surface map's extents hold what was seen of each surface (issue: "the map's
// outline of the floor and the table against the union of all frames' points on them"): per
// map entry, the xy footprint of every point any frame gave its id, on a fine grid, against
// the entry's outline on the same grid. hope_extract --map-extents writes it.
#pragma once

#include <cstdint>
#include <string>
#include <unordered_map>
#include <unordered_set>
#include <vector>

#include "hope/extractor.h"
#include "hope/plane_tracker.h"
#include "hope/points_view.h"

namespace hope::tools {

struct MapExtent {
  int id = 0;
  double height = 0;
  int frames = 0;        // frames the entry was seen in
  double map_area = 0;   // m², its outline on the grid
  double seen_area = 0;  // m², the union of its points' footprints on the grid
  double iou = 0;        // of the two, in xy
};

class MapExtentCheck {
 public:
  // `cell`: the grid both footprints are compared on, metres. 2 cm: fine against the map's
  // r_xy cells, coarse enough that the union of VGA points at a few metres has no holes.
  explicit MapExtentCheck(double cell = 0.02);
  // After the map's update of a frame: `result.planes` carry the map's ids, `events` what the
  // update did (a merged id's points go to the id that subsumed it; an ended entry's are
  // dropped). Needs result.point_labels.
  void addFrame(const Result& result, const AlignedPoints& aligned,
                const std::vector<TrackEvent>& events);
  // One line per entry of `surfaces` (SurfaceMap::surfaces()), largest first.
  std::vector<MapExtent> compare(const std::vector<HorizontalPlane>& surfaces) const;

 private:
  double cell_;
  std::unordered_map<int, std::unordered_set<std::uint64_t>> seen_;
};

// The Markdown table of `extents` (at most `rows` of them), with a header line.
std::string formatMapExtents(const std::vector<MapExtent>& extents, std::size_t rows);

}  // namespace hope::tools
