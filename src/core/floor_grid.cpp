#include "hope/floor_grid.h"

#include "hope/obstacle_points.h"

#include <algorithm>
#include <cmath>

namespace hope {

FloorGrid floorGrid(const AlignedPoints& points, const Eigen::Vector3d& local_origin,
                    const HorizontalPlane& floor, const Eigen::Vector2d& centre,
                    double floor_tolerance, double min_height, double max_height, double resolution,
                    std::vector<std::uint32_t>* obstacles) {
  FloorGrid grid;
  grid.resolution = resolution;
  grid.floor_height = floor.height;
  const HeightAbovePlane height_above(floor, local_origin);
  // One pass into the whole window around the centre (1 MB at most), cropped to the cells seen
  // at the end: no list of hits.
  const long half = kFloorGridMaxCells / 2, side = 2 * half + 1;
  const long first_x = static_cast<long>(std::floor(centre.x() / resolution)) - half;
  const long first_y = static_cast<long>(std::floor(centre.y() / resolution)) - half;
  // The window's first cell in the aligned points' frame (local_origin taken off), so that a
  // point's cell is one multiply per axis: cells stay multiples of the resolution absolutely.
  const double inverse = 1.0 / resolution;
  const double start_x = first_x * resolution - local_origin.x();
  const double start_y = first_y * resolution - local_origin.y();
  std::vector<std::int8_t> window(static_cast<std::size_t>(side * side), FloorGrid::kUnseen);
  long min_x = side, min_y = side, max_x = -1, max_y = -1;
  for (std::size_t i = 0; i < points.size(); ++i) {
    const Eigen::Vector3f p = points[i];
    if (!p.allFinite()) continue;
    const double above = height_above(p);
    const bool occupied = above > min_height && above <= max_height;
    if (occupied && obstacles) obstacles->push_back(static_cast<std::uint32_t>(i));
    if (!occupied && std::abs(above) > floor_tolerance) continue;
    const double fx = (p.x() - start_x) * inverse, fy = (p.y() - start_y) * inverse;
    if (!(fx >= 0 && fy >= 0 && fx < side && fy < side)) continue;
    // Truncation is the floor here (both are non-negative), without a libm call per point.
    const long x = static_cast<long>(fx), y = static_cast<long>(fy);
    std::int8_t& cell = window[static_cast<std::size_t>(y * side + x)];
    // Something standing in a cell outweighs the floor seen around it.
    if (occupied) {
      cell = FloorGrid::kOccupied;
    } else if (cell == FloorGrid::kUnseen) {
      cell = FloorGrid::kFree;
    }
    min_x = std::min(min_x, x), max_x = std::max(max_x, x);
    min_y = std::min(min_y, y), max_y = std::max(max_y, y);
  }
  if (max_x < 0) return grid;
  grid.width = static_cast<int>(max_x - min_x + 1);
  grid.height = static_cast<int>(max_y - min_y + 1);
  grid.origin =
      Eigen::Vector2d(static_cast<double>(first_x + min_x), static_cast<double>(first_y + min_y)) *
      resolution;
  grid.cells.resize(static_cast<std::size_t>(grid.width) * grid.height);
  for (long y = min_y; y <= max_y; ++y) {
    std::copy_n(window.begin() + (y * side + min_x), grid.width,
                grid.cells.begin() + (y - min_y) * grid.width);
  }
  return grid;
}

void accumulate(FloorMap& map, const FloorGrid& seen, const Eigen::Vector2d& centre) {
  if (seen.width == 0) return;
  FloorGrid& into = map.grid;
  const double r = seen.resolution;
  // Absolute cell indices of each grid's first cell (the origins are multiples of r).
  const long into_x = std::lround(into.origin.x() / r), into_y = std::lround(into.origin.y() / r);
  const long seen_x = std::lround(seen.origin.x() / r), seen_y = std::lround(seen.origin.y() / r);
  const bool fresh = into.width == 0 || into.resolution != r;
  long min_x = fresh ? seen_x : std::min(into_x, seen_x);
  long min_y = fresh ? seen_y : std::min(into_y, seen_y);
  long max_x =
      (fresh ? seen_x + seen.width : std::max(into_x + into.width, seen_x + seen.width)) - 1;
  long max_y =
      (fresh ? seen_y + seen.height : std::max(into_y + into.height, seen_y + seen.height)) - 1;
  const long half = kFloorGridMaxCells / 2;
  const long centre_x = static_cast<long>(std::floor(centre.x() / r));
  const long centre_y = static_cast<long>(std::floor(centre.y() / r));
  min_x = std::max(min_x, centre_x - half), max_x = std::min(max_x, centre_x + half);
  min_y = std::max(min_y, centre_y - half), max_y = std::min(max_y, centre_y + half);
  FloorMap out;
  out.grid.resolution = r;
  out.grid.floor_height = seen.floor_height;
  if (max_x >= min_x && max_y >= min_y) {
    out.grid.width = static_cast<int>(max_x - min_x + 1);
    out.grid.height = static_cast<int>(max_y - min_y + 1);
    out.grid.origin = Eigen::Vector2d(static_cast<double>(min_x), static_cast<double>(min_y)) * r;
  }
  const std::size_t cells = static_cast<std::size_t>(out.grid.width) * out.grid.height;
  out.grid.cells.assign(cells, FloorGrid::kUnseen);
  out.free_looks.assign(cells, 0);
  // The out cell of `grid`'s cell (x, y), or -1 outside.
  const auto index = [&](long first_x, long first_y, int x, int y) -> long {
    const long ox = first_x + x - min_x, oy = first_y + y - min_y;
    if (ox < 0 || oy < 0 || ox >= out.grid.width || oy >= out.grid.height) return -1;
    return oy * out.grid.width + ox;
  };
  if (!fresh) {
    for (int y = 0; y < into.height; ++y) {
      for (int x = 0; x < into.width; ++x) {
        const long o = index(into_x, into_y, x, y);
        if (o < 0) continue;
        const std::size_t i = static_cast<std::size_t>(y) * into.width + x;
        out.grid.cells[o] = into.cells[i];
        out.free_looks[o] = map.free_looks[i];
      }
    }
  }
  for (int y = 0; y < seen.height; ++y) {
    for (int x = 0; x < seen.width; ++x) {
      const long o = index(seen_x, seen_y, x, y);
      const std::int8_t look = seen.cells[static_cast<std::size_t>(y) * seen.width + x];
      if (o < 0 || look == FloorGrid::kUnseen) continue;
      std::int8_t& cell = out.grid.cells[o];
      std::uint8_t& free_looks = out.free_looks[o];
      if (look == FloorGrid::kOccupied) {
        cell = FloorGrid::kOccupied;
        free_looks = 0;
      } else if (cell != FloorGrid::kOccupied || ++free_looks >= kFreeLooksToClear) {
        cell = FloorGrid::kFree;
        free_looks = 0;
      }
    }
  }
  map = std::move(out);
}

}  // namespace hope
