#include "hope/surface_map.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include <Eigen/Cholesky>

#include "hope/convex_hull.h"
#include "hope/grid_cell_key.h"
#include "hope/plane_outline.h"

namespace hope {

void validate(const SurfaceMapOptions& options) {
  auto require = [](bool ok, const std::string& what) {
    if (!ok) throw std::invalid_argument("surface map: " + what);
  };
  require(options.cell >= 0.001 && options.cell <= 10,
          "cell = " + std::to_string(options.cell) + " is out of range [0.001, 10] m");
  require(options.max_height_change > 0 && options.max_height_change <= 10,
          "max_height_change = " + std::to_string(options.max_height_change) +
              " is out of range (0, 10] m");
  require(options.max_extension_height_change > 0 &&
              options.max_extension_height_change <= options.max_height_change,
          "max_extension_height_change = " + std::to_string(options.max_extension_height_change) +
              " is out of range (0, max_height_change]");
  require(options.min_overlap_share >= 0 && options.min_overlap_share <= 1,
          "min_overlap_share = " + std::to_string(options.min_overlap_share) +
              " is out of range [0, 1]");
  require(options.max_entries >= 1 && options.max_entries <= 1000000,
          "max_entries = " + std::to_string(options.max_entries) + " is out of range [1, 1000000]");
  require(
      options.tilt_error_deg >= 0 && options.tilt_error_deg <= 45,
      "tilt_error_deg = " + std::to_string(options.tilt_error_deg) + " is out of range [0, 45]");
  require(options.height_error >= 0 && options.height_error <= 10,
          "height_error = " + std::to_string(options.height_error) + " is out of range [0, 10] m");
  require(options.forget_after_frames >= 0 && options.forget_after_frames <= 1000000,
          "forget_after_frames = " + std::to_string(options.forget_after_frames) +
              " is out of range [0, 1000000]");
  require(options.emptied_share > 0 && options.emptied_share <= 1,
          "emptied_share = " + std::to_string(options.emptied_share) + " is out of range (0, 1]");
}

SurfaceMapOptions surfaceMapOptionsFor(const Params& params) {
  SurfaceMapOptions options;
  options.cell = params.r_xy;
  options.max_extension_height_change = std::min(params.r_z, options.max_height_change);
  return options;
}

namespace {

// What a height difference of max_extension_height_change costs an entry claiming a plane,
// in shares of the plane's cells (see the primary's choice in update()).
constexpr double kHeightPenalty = 0.25;

// A plane farther out than this from the frame's origin is not mapped (±100 km at 5 cm cells
// stays far inside the keys' 32 bits).
constexpr double kMaxCoordinate = 1e5;

// Where the line at height y crosses the rings' edges, sorted: inside between the 1st and
// 2nd, 3rd and 4th, ... (even-odd).
void crossingsAt(const std::vector<std::vector<Eigen::Vector3d>>& rings, double y,
                 std::vector<double>& crossings) {
  crossings.clear();
  for (const auto& ring : rings) {
    for (std::size_t k = 0, prev = ring.size() - 1; k < ring.size(); prev = k++) {
      const Eigen::Vector3d &a = ring[k], &b = ring[prev];
      if ((a.y() > y) != (b.y() > y)) {
        crossings.push_back(a.x() + (y - a.y()) / (b.y() - a.y()) * (b.x() - a.x()));
      }
    }
  }
  std::sort(crossings.begin(), crossings.end());
}

// The cells the plane covers: its outline (holes left open, even-odd over all rings), or its
// hull when it has no outline, filled row by row. A cell is covered when the middle half of its
// square (the centre and the four corners of the square half its size) lies inside: an
// outline is traced around the extraction's r_xy cells and overshoots the points by up to a
// cell, so a cell whose centre alone lies inside would grow every entry by the overshoot of
// every view (the union of many noisy rims). On the kitchen sequence: the table's and the far
// floor's extent against the union of their points 93.4 % and 85.9 % IoU by the centre alone,
// 95.2 % and 90.1 % so. A plane too narrow to cover any cell so keeps the cells its outline
// holds the centre of (`middle_half` false).
std::vector<std::uint64_t> cellsOf(const HorizontalPlane& plane, double cell,
                                   bool middle_half = true) {
  std::vector<std::uint64_t> cells;
  std::vector<std::vector<Eigen::Vector3d>> rings = plane.outline;
  if (rings.empty() && plane.hull.size() >= 3) rings.push_back(plane.hull);
  if (rings.empty()) return cells;
  for (double v : plane.bbox) {
    if (!(std::fabs(v) < kMaxCoordinate)) return cells;
  }
  auto inside = [](const std::vector<double>& crossings, double x) {
    return (std::upper_bound(crossings.begin(), crossings.end(), x) - crossings.begin()) % 2 == 1;
  };
  const std::int64_t iy0 = static_cast<std::int64_t>(std::floor(plane.bbox[1] / cell));
  const std::int64_t iy1 = static_cast<std::int64_t>(std::floor(plane.bbox[3] / cell));
  std::vector<double> middle, low, high;
  for (std::int64_t iy = iy0; iy <= iy1; ++iy) {
    const double y = (static_cast<double>(iy) + 0.5) * cell;
    crossingsAt(rings, y, middle);
    if (middle_half) {
      crossingsAt(rings, y - cell / 4, low);
      crossingsAt(rings, y + cell / 4, high);
    }
    for (std::size_t k = 0; k + 1 < middle.size(); k += 2) {
      // Cells whose centre lies between the two crossings.
      const auto from = static_cast<std::int64_t>(std::ceil(middle[k] / cell - 0.5));
      const auto to = static_cast<std::int64_t>(std::floor(middle[k + 1] / cell - 0.5));
      for (std::int64_t ix = from; ix <= to; ++ix) {
        const double x0 = (static_cast<double>(ix) + 0.25) * cell;
        const double x1 = (static_cast<double>(ix) + 0.75) * cell;
        if (!middle_half ||
            (inside(low, x0) && inside(low, x1) && inside(high, x0) && inside(high, x1))) {
          cells.push_back(cellKey(ix, iy));
        }
      }
    }
  }
  return cells.empty() && middle_half ? cellsOf(plane, cell, false) : cells;
}

// The box of a set of cells, inclusive.
struct CellBox {
  std::int64_t x0 = std::numeric_limits<std::int64_t>::max(), y0 = x0, x1 = -x0, y1 = -x0;
  // It overlaps or touches (8-neighbourhood) the box [bx0, bx1] × [by0, by1].
  bool touches(std::int64_t bx0, std::int64_t by0, std::int64_t bx1, std::int64_t by1) const {
    return x0 <= bx1 + 1 && bx0 <= x1 + 1 && y0 <= by1 + 1 && by0 <= y1 + 1;
  }
};

CellBox boxOf(const std::vector<std::uint64_t>& cells) {
  CellBox box;
  for (std::uint64_t c : cells) {
    box.x0 = std::min(box.x0, cellX(c)), box.x1 = std::max(box.x1, cellX(c));
    box.y0 = std::min(box.y0, cellY(c)), box.y1 = std::max(box.y1, cellY(c));
  }
  return box;
}

}  // namespace

SurfaceMap::SurfaceMap(const SurfaceMapOptions& options) : options_(options) { validate(options_); }

void SurfaceMap::reset() { entries_.clear(); }

void SurfaceMap::reset(const SurfaceMapOptions& options) {
  validate(options);
  options_ = options;
  entries_.clear();
}

void SurfaceMap::observe(Entry& entry, const HorizontalPlane& plane, double height,
                         const std::vector<std::uint64_t>& cells, double stamp) {
  // Weighted by the observed area: a glimpse of a table's corner moves its height less than a
  // full view does.
  const double w = std::max(plane.area, options_.cell * options_.cell);
  entry.weight += w;
  entry.height_sum += w * height;
  entry.normal_sum += w * plane.normal;
  entry.centroid_sum += w * plane.centroid;
  for (std::uint64_t c : cells) {
    if (!entry.cells.insert(c).second) continue;
    const std::int64_t x = cellX(c), y = cellY(c);
    if (entry.x1 < entry.x0) {
      entry.x0 = entry.x1 = x;
      entry.y0 = entry.y1 = y;
    } else {
      entry.x0 = std::min(entry.x0, x), entry.x1 = std::max(entry.x1, x);
      entry.y0 = std::min(entry.y0, y), entry.y1 = std::max(entry.y1, y);
    }
  }
  if (entry.last_seen != stamp || entry.frames == 0) ++entry.frames;
  entry.last_seen = stamp;
  entry.last_frame = updates_;
  entry.last = plane;
}

void SurfaceMap::absorb(Entry& into, Entry& from) {
  into.weight += from.weight;
  into.height_sum += from.height_sum;
  into.normal_sum += from.normal_sum;
  into.centroid_sum += from.centroid_sum;
  into.cells.insert(from.cells.begin(), from.cells.end());
  if (from.x1 >= from.x0) {
    if (into.x1 < into.x0) {
      into.x0 = from.x0, into.x1 = from.x1, into.y0 = from.y0, into.y1 = from.y1;
    } else {
      into.x0 = std::min(into.x0, from.x0), into.x1 = std::max(into.x1, from.x1);
      into.y0 = std::min(into.y0, from.y0), into.y1 = std::max(into.y1, from.y1);
    }
  }
  into.frames = std::max(into.frames, from.frames);
  into.first_seen = std::min(into.first_seen, from.first_seen);
  into.last_seen = std::max(into.last_seen, from.last_seen);
  into.last_frame = std::max(into.last_frame, from.last_frame);
}

// A pose's error moves every surface of a frame in height: its height error by as much
// everywhere, its tilt error θ by d·tan θ at a horizontal distance d from the sensor (on
// kitchen_dev's poses one counter read 6 cm lower 20 s after it was first mapped, beyond
// max_height_change, and took a new id). The surfaces seen again measure it: each plane most of
// whose cells an entry holds, within max_height_change of its height, is that entry, and the
// difference of their heights is the frame's error there, e(x, y) = a + b·(x − x_s) +
// c·(y − y_s) about the sensor at (x_s, y_s); a plane that two entries hold most of measures
// nothing. The estimate is the most probable under the pose's error as prior (height_error for
// a, tan tilt_error_deg for b and c) and each difference known to half
// max_extension_height_change (r_z / 2, the extraction's height quantum), fitted twice: the
// second time without the differences the first fit leaves above max_extension_height_change
// (a book mistaken for the table under it). With no surface seen again, no correction.
std::vector<double> SurfaceMap::heightsInMap(
    const std::vector<HorizontalPlane>& planes,
    const std::vector<std::vector<std::uint64_t>>& plane_cells,
    const std::optional<Eigen::Vector3d>& viewpoint) const {
  std::vector<double> heights(planes.size());
  for (std::size_t k = 0; k < planes.size(); ++k) heights[k] = planes[k].height;
  if (!(options_.height_error > 0) && !(options_.tilt_error_deg > 0)) return heights;
  constexpr double kMostOfItsCells = 0.5;
  Eigen::Vector2d sensor = Eigen::Vector2d::Zero();
  if (viewpoint) {
    sensor = viewpoint->head<2>();
  } else if (!planes.empty()) {
    for (const HorizontalPlane& plane : planes) sensor += plane.centroid.head<2>();
    sensor /= static_cast<double>(planes.size());
  }
  // A difference's row in the fit: 1, Δx, Δy.
  const auto fitRow = [&](const HorizontalPlane& plane) {
    return Eigen::Vector3d(1.0, plane.centroid.x() - sensor.x(), plane.centroid.y() - sensor.y());
  };
  struct Difference {
    Eigen::Vector3d at;
    double height;
  };
  std::vector<Difference> differences;
  for (std::size_t k = 0; k < planes.size(); ++k) {
    const std::vector<std::uint64_t>& cells = plane_cells[k];
    if (cells.empty()) continue;
    const CellBox box = boxOf(cells);
    double difference = 0;
    int holders = 0;
    for (const Entry& entry : entries_) {
      const double gap = planes[k].height - entry.height();
      if (std::fabs(gap) > options_.max_height_change ||
          !box.touches(entry.x0, entry.y0, entry.x1, entry.y1)) {
        continue;
      }
      std::size_t common = 0;
      for (std::uint64_t c : cells) common += entry.cells.count(c);
      if (static_cast<double>(common) >= kMostOfItsCells * static_cast<double>(cells.size())) {
        ++holders;
        difference = gap;
      }
    }
    // A plane two entries hold most of (a step blended with the one below it) measures nothing.
    if (holders == 1) differences.push_back({fitRow(planes[k]), difference});
  }
  if (differences.empty()) return heights;
  const double sigma = options_.max_extension_height_change / 2;
  const double tilt = std::tan(options_.tilt_error_deg * M_PI / 180.0);
  const Eigen::Vector3d prior(options_.height_error, tilt, tilt);
  Eigen::Vector3d error = Eigen::Vector3d::Zero();
  for (int pass = 0; pass < 2; ++pass) {
    Eigen::Matrix3d normal = Eigen::Matrix3d::Zero();
    for (int i = 0; i < 3; ++i) {
      // A zero prior holds that part of the error at zero.
      normal(i, i) = prior(i) > 0 ? 1.0 / (prior(i) * prior(i)) : 1e12 / (sigma * sigma);
    }
    Eigen::Vector3d rhs = Eigen::Vector3d::Zero();
    for (const Difference& d : differences) {
      if (pass == 1 &&
          std::fabs(d.height - d.at.dot(error)) > options_.max_extension_height_change) {
        continue;
      }
      normal += d.at * d.at.transpose() / (sigma * sigma);
      rhs += d.at * d.height / (sigma * sigma);
    }
    error = normal.ldlt().solve(rhs);
  }
  for (std::size_t k = 0; k < planes.size(); ++k) heights[k] -= fitRow(planes[k]).dot(error);
  return heights;
}

std::vector<TrackEvent> SurfaceMap::update(std::vector<HorizontalPlane>& planes, double stamp,
                                           const std::optional<Eigen::Vector3d>& viewpoint) {
  std::vector<TrackEvent> events;
  ++updates_;
  // The ids of entries not seen in the last forget_after_frames frames end before this frame
  // is matched: seen in frame f, unseen in f+1 .. f+N, an entry has a new id in f+N+1
  // (id_accuracy.py joins two planes at most N = 30 frames apart). The entry keeps its extent:
  // seen again, it is recognised from all it was seen as, not from its first partial view
  // (kitchen_dev at a 3-frame horizon: 95.3 % IDF1 against 90.7 % with the entry removed,
  // docs/quality.md).
  if (options_.forget_after_frames > 0) {
    for (Entry& entry : entries_) {
      if (entry.dormant() || updates_ - entry.last_frame <= options_.forget_after_frames) continue;
      events.push_back({TrackEvent::Kind::kEnded, entry.id});
      entry.id = next_id_++;  // announced (kNew) when it is seen again
      entry.frames = 0;       // dormant
    }
  }
  const double cell = options_.cell;
  // Larger planes first: a floor or a table claims its entry before a fragment of it does.
  std::vector<std::size_t> order(planes.size());
  for (std::size_t k = 0; k < order.size(); ++k) order[k] = k;
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t a, std::size_t b) { return planes[a].area > planes[b].area; });
  std::vector<std::vector<std::uint64_t>> plane_cells(planes.size());
  for (std::size_t k = 0; k < planes.size(); ++k) plane_cells[k] = cellsOf(planes[k], cell);
  // Each plane's height in the map's frame: as measured, less the frame's height error that
  // the surfaces seen again show (see heightErrors).
  const std::vector<double> map_height = heightsInMap(planes, plane_cells, viewpoint);
  std::vector<std::uint8_t> seen(entries_.size(), 0);
  for (std::size_t k : order) {
    HorizontalPlane& plane = planes[k];
    const std::vector<std::uint64_t>& cells = plane_cells[k];
    const double height = map_height[k];
    if (cells.empty()) {
      // No outline, no hull, or out of range: the plane keeps a fresh id the map does not hold.
      plane.id = next_id_++;
      plane.age = 1;
      plane.last_seen = stamp;
      events.push_back({TrackEvent::Kind::kNew, plane.id});
      continue;
    }
    const CellBox box = boxOf(cells);
    // The entries at this height whose cells overlap or touch the plane's (8-neighbourhood).
    std::vector<std::size_t> matches;
    std::vector<std::uint8_t> overlapping(entries_.size(), 0);
    std::vector<std::size_t> common_cells(entries_.size(), 0);
    for (std::size_t e = 0; e < entries_.size(); ++e) {
      const Entry& entry = entries_[e];
      if (entry.weight == 0 ||  // merged into another this frame
          std::fabs(entry.height() - height) > options_.max_height_change ||
          !box.touches(entry.x0, entry.y0, entry.x1, entry.y1)) {
        continue;
      }
      // Seen again where it was seen before: within max_height_change (a pose's error). Only
      // beside it (a new part of it coming into view): within max_extension_height_change, so
      // that a book lying in the hole it makes in a table's extent stays a surface of its own.
      const bool extension_height =
          std::fabs(entry.height() - height) <= options_.max_extension_height_change;
      std::size_t common = 0;
      bool touches = false;
      for (std::size_t i = 0; i < cells.size(); ++i) {
        common += entry.cells.count(cells[i]);
        const std::int64_t cx = cellX(cells[i]), cy = cellY(cells[i]);
        for (std::int64_t dy = -1; dy <= 1 && extension_height && !touches; ++dy) {
          for (std::int64_t dx = -1; dx <= 1 && !touches; ++dx) {
            touches = entry.cells.count(cellKey(cx + dx, cy + dy)) > 0;
          }
        }
      }
      // Seen again: a share of the smaller of the two in common (a sliver in common is a
      // neighbour's edge, not the same surface).
      const bool overlaps =
          common > 0 && static_cast<double>(common) >=
                            options_.min_overlap_share *
                                static_cast<double>(std::min(cells.size(), entry.cells.size()));
      // An entry another plane of this frame took is not this one's: a frame's planes keep
      // distinct ids (a fragment the extraction left apart becomes an entry of its own).
      if ((overlaps || touches) && !seen[e]) matches.push_back(e);
      overlapping[e] = overlaps;
      common_cells[e] = common;
    }
    if (matches.empty()) {
      Entry entry;
      entry.id = next_id_++;
      entry.first_seen = stamp;
      observe(entry, plane, height, cells, stamp);
      entries_.push_back(std::move(entry));
      seen.push_back(1);
      events.push_back({TrackEvent::Kind::kNew, entries_.back().id});
      plane.id = entries_.back().id;
      plane.age = 1;
      plane.last_seen = stamp;
      continue;
    }
    // The plane is the entry it overlaps that explains it best: the share of the plane's cells
    // the entry holds, less a quarter for every max_extension_height_change (r_z) between their
    // heights; overlapping none, the entry nearest in height it continues. Not the nearest in
    // height alone: a surface's height drifts by centimetres with the pose and the range it is
    // seen at (a far shelf of the kitchen sequence read 5 cm apart over 20 frames), and a
    // fragment the extraction once left beside it, a little lower, would take the surface's
    // id from then on. Not the most cells alone: a plane the extraction blended from several
    // faces of an object 2 cm apart would take every face's id. Kitchen sequence (IDF1 per
    // observation): nearest height 75.6 %, most cells 80.4 %, this 79.9 %; the synthetic
    // sequences' paper's accuracy: 99.39 %, 99.04 %, 99.50 % (scripts/map_kitchen.sh,
    // scripts/evaluate_tracking.sh).
    auto height_gap = [&](std::size_t e) { return std::fabs(entries_[e].height() - height); };
    auto explains = [&](std::size_t e) {
      return static_cast<double>(common_cells[e]) / static_cast<double>(cells.size()) -
             kHeightPenalty * height_gap(e) / options_.max_extension_height_change;
    };
    const std::size_t primary =
        *std::min_element(matches.begin(), matches.end(), [&](std::size_t a, std::size_t b) {
          if (overlapping[a] != overlapping[b]) return overlapping[a] > overlapping[b];
          return overlapping[a] ? explains(a) > explains(b) : height_gap(a) < height_gap(b);
        });
    // The entries it overlaps at that entry's height (within max_extension_height_change) are
    // one surface with it, which it shows: the one seen in the most frames subsumes the others
    // (the oldest on a tie; ids rise with age), so that the fewest observations change their
    // id (kitchen_dev: a shelf's two halves mapped apart, 3 and 14 frames each, merged into the
    // older and 14 of its observations read as a switch). Entries it merely touches, or
    // overlaps at another height (a book on the table, 5 cm up), stay apart.
    std::vector<std::size_t> group = {primary};
    for (std::size_t e : matches) {
      if (e != primary && overlapping[e] &&
          std::fabs(entries_[e].height() - entries_[primary].height()) <=
              options_.max_extension_height_change) {
        group.push_back(e);
      }
    }
    const std::size_t chosen =
        *std::min_element(group.begin(), group.end(), [&](std::size_t a, std::size_t b) {
          if (entries_[a].frames != entries_[b].frames) {
            return entries_[a].frames > entries_[b].frames;
          }
          return entries_[a].id < entries_[b].id;
        });
    Entry& target = entries_[chosen];
    for (std::size_t e : group) {
      if (e == chosen) continue;
      absorb(target, entries_[e]);
      // A dormant entry's new id was never given to a plane: nothing to say.
      if (!entries_[e].dormant()) {
        events.push_back({TrackEvent::Kind::kMerged, entries_[e].id, target.id});
      }
      entries_[e].weight = 0;  // removed below
    }
    // Seen again after its id ended: its new id starts here. (A dormant entry is chosen only
    // with dormant ones, the others having frames.)
    if (target.dormant()) {
      target.first_seen = stamp;
      events.push_back({TrackEvent::Kind::kNew, target.id});
    }
    observe(target, plane, height, cells, stamp);
    seen[chosen] = 1;
    plane.id = target.id;
    plane.age = target.frames;
    plane.last_seen = stamp;
  }
  // Entries not seen whose space was seen empty: a sensor above the entry saw a lower surface
  // through the cells the entry occupies (a box lifted off the table, the table now seen where
  // its top was).
  if (viewpoint) {
    for (std::size_t e = 0; e < entries_.size(); ++e) {
      Entry& entry = entries_[e];
      if (seen[e] || entry.weight == 0) continue;
      const double h = entry.height();
      if (viewpoint->z() <= h + options_.max_height_change) continue;  // looking from below
      std::unordered_set<std::uint64_t> through;
      for (std::size_t k = 0; k < planes.size(); ++k) {
        const double lower = planes[k].height;
        if (lower >= h - options_.max_height_change) continue;
        // Where the ray from the sensor to a cell of the lower plane crosses the entry's height.
        const double t = (viewpoint->z() - h) / (viewpoint->z() - lower);
        // The lower plane's box, seen at the entry's height, must meet the entry's box: most
        // pairs are far apart, and this keeps a frame's cost from growing with the map.
        const double bx0 = viewpoint->x() + t * (planes[k].bbox[0] - viewpoint->x());
        const double by0 = viewpoint->y() + t * (planes[k].bbox[1] - viewpoint->y());
        const double bx1 = viewpoint->x() + t * (planes[k].bbox[2] - viewpoint->x());
        const double by1 = viewpoint->y() + t * (planes[k].bbox[3] - viewpoint->y());
        if (bx1 < entry.x0 * cell || bx0 > (entry.x1 + 1) * cell || by1 < entry.y0 * cell ||
            by0 > (entry.y1 + 1) * cell) {
          continue;
        }
        for (std::uint64_t c : plane_cells[k]) {
          const double x = viewpoint->x() + t * ((cellX(c) + 0.5) * cell - viewpoint->x());
          const double y = viewpoint->y() + t * ((cellY(c) + 0.5) * cell - viewpoint->y());
          const auto ix = static_cast<std::int64_t>(std::floor(x / cell));
          const auto iy = static_cast<std::int64_t>(std::floor(y / cell));
          if (ix < entry.x0 || ix > entry.x1 || iy < entry.y0 || iy > entry.y1) continue;
          const std::uint64_t key = cellKey(ix, iy);
          if (entry.cells.count(key)) through.insert(key);
        }
      }
      if (through.empty()) continue;  // the usual case: nothing seen through it
      // Only the entry's inner cells count: along its rim a cell is partly the surface below
      // (the table around a book), and the rays to it pass the rim at the entry's height.
      std::size_t inner = 0, inner_through = 0;
      for (std::uint64_t c : entry.cells) {
        bool rim = false;
        for (std::int64_t dy = -1; dy <= 1 && !rim; ++dy) {
          for (std::int64_t dx = -1; dx <= 1 && !rim; ++dx) {
            rim = !entry.cells.count(cellKey(cellX(c) + dx, cellY(c) + dy));
          }
        }
        if (rim) continue;
        ++inner;
        inner_through += through.count(c);
      }
      if (inner > 0 && static_cast<double>(inner_through) >=
                           options_.emptied_share * static_cast<double>(inner)) {
        // A dormant entry's id was never given (its last one ended already).
        if (!entry.dormant()) events.push_back({TrackEvent::Kind::kEnded, entry.id});
        entry.weight = 0;
      }
    }
  }
  entries_.erase(std::remove_if(entries_.begin(), entries_.end(),
                                [](const Entry& entry) { return entry.weight == 0; }),
                 entries_.end());
  // Bounded memory: the entries seen longest ago go first.
  while (entries_.size() > options_.max_entries) {
    auto oldest =
        std::min_element(entries_.begin(), entries_.end(),
                         [](const Entry& a, const Entry& b) { return a.last_seen < b.last_seen; });
    if (!oldest->dormant()) events.push_back({TrackEvent::Kind::kEnded, oldest->id});
    entries_.erase(oldest);
  }
  return events;
}

std::vector<HorizontalPlane> SurfaceMap::surfaces() const {
  std::vector<HorizontalPlane> out;
  out.reserve(entries_.size());
  for (const Entry& entry : entries_) {
    HorizontalPlane p = entry.last;
    p.id = entry.id;
    p.height = entry.height();
    if (entry.normal_sum.norm() > 0) p.normal = entry.normal_sum.normalized();
    p.tilt = std::acos(std::min(1.0, std::fabs(p.normal.z())));
    p.centroid = entry.centroid_sum / entry.weight;
    p.area = static_cast<double>(entry.cells.size()) * options_.cell * options_.cell;
    p.bbox = {entry.x0 * options_.cell, entry.y0 * options_.cell, (entry.x1 + 1) * options_.cell,
              (entry.y1 + 1) * options_.cell};
    std::vector<std::pair<std::int64_t, std::int64_t>> cells;
    cells.reserve(entry.cells.size());
    for (std::uint64_t c : entry.cells) cells.emplace_back(cellX(c), cellY(c));
    p.outline.clear();
    std::vector<Eigen::Vector2d> corners;
    for (const auto& ring : traceOutline(std::move(cells), Eigen::Vector2d::Zero(), options_.cell,
                                         options_.cell / 2)) {
      std::vector<Eigen::Vector3d> ring3;
      for (const Eigen::Vector2d& q : ring) {
        ring3.emplace_back(q.x(), q.y(), p.height);
        corners.push_back(q);
      }
      p.outline.push_back(std::move(ring3));
    }
    p.hull.clear();
    for (const Eigen::Vector2d& q : convexHull2D(std::move(corners))) {
      p.hull.emplace_back(q.x(), q.y(), p.height);
    }
    p.age = entry.frames;
    p.last_seen = entry.last_seen;
    p.split_from = -1;
    out.push_back(std::move(p));
  }
  return out;
}

}  // namespace hope
