// Convex hulls of a plane's points (paper §2.4 describes each plane by its hull). The plain
// hull is Andrew's monotone chain after an Akl–Toussaint cut; the description's hull also
// knows which grid cell each point lies in, and drops whole cells that lie inside a polygon of
// extreme points before it looks at a single point of them.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include <Eigen/Core>

namespace hope {

// Convex hull (Andrew's monotone chain), counter-clockwise, without repeated endpoint. Fewer
// than three distinct points come back as they are (deduplicated).
std::vector<Eigen::Vector2d> convexHull2D(std::vector<Eigen::Vector2d> points);
// The same without allocating: reorders and overwrites points[0..n) (scratch) and writes the
// hull to `hull`, which must have room for 2n + 1 points. Returns the hull's size.
std::size_t convexHullInPlace(Eigen::Vector2d* points, std::size_t n, Eigen::Vector2d* hull);

// Points known by the square cell of side `side` each lies in (a grid column), and for each
// cell a point inside the hull of the cell's own points (their mean, say).
struct CellPoints {
  double side = 0;
  std::vector<Eigen::Vector2d> points;
  std::vector<std::uint32_t> cell_of_point;  // per point: an index into the per-cell arrays
  std::vector<Eigen::Vector2d> cell_min;     // per cell: its lower-left corner
  std::vector<Eigen::Vector2d> cell_inner;   // per cell: a point inside its points' hull
};

// The convex hull of cells.points, vertex for vertex the one convexHull2D returns. A point
// lies in [cell_min, cell_min + side]² of its cell up to rounding (a grid's points do). The
// points extreme in kHullDirections directions span a polygon inside the hull; cells entirely
// inside it are dropped whole, and the points of the others are tested only against the
// polygon's edges their cell crosses. Only the few points left near the rim are sorted.
// cells.points is used as scratch (reordered, overwritten or moved from). With
// `points_sorted`, also says how many points were left for the sort (all of them when the
// shortcut did not apply).
std::vector<Eigen::Vector2d> convexHullOfCellPoints(CellPoints& cells,
                                                    std::size_t* points_sorted = nullptr);

constexpr int kHullDirections = 32;

}  // namespace hope
