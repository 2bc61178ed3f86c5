#include "hope/plane_description.h"

#include <algorithm>
#include <cmath>
#include <cstdint>

#include <Eigen/Eigenvalues>

#include "hope/plane_outline.h"
#include "parallel.h"

namespace hope {

namespace {

double cross(const Eigen::Vector2d& o, const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  return (a.x() - o.x()) * (b.y() - o.y()) - (a.y() - o.y()) * (b.x() - o.x());
}

// Whether a voxel's cell lies strictly inside the convex hull of the other cells' points: true
// when the plane has cells in all four diagonal quadrants around it (up-left, up-right,
// down-left, down-right: columns and rows strictly beyond the cell's). Then every point p of
// the cell has plane points in all four open quadrants around it, and a line through p with
// all of them on one side would leave one quadrant empty; so p is inside the hull, and no
// point of the cell is a hull vertex or a bbox extreme. On a large plane this leaves the hull
// a small share of the candidates, exactly.
class InteriorTest {
 public:
  InteriorTest() = default;
  InteriorTest(const VoxelGrid& grid, const std::vector<std::uint32_t>& members) {
    std::int64_t y_lo = INT64_MAX, y_hi = INT64_MIN;
    for (std::uint32_t v : members) {
      y_lo = std::min<std::int64_t>(y_lo, grid.cellY(v));
      y_hi = std::max<std::int64_t>(y_hi, grid.cellY(v));
    }
    y0_ = y_lo;
    const std::size_t rows = static_cast<std::size_t>(y_hi - y_lo + 1);
    // Per row: the smallest and largest column of the plane (none: max / min sentinels).
    std::vector<std::int64_t> row_min(rows, INT64_MAX), row_max(rows, INT64_MIN);
    for (std::uint32_t v : members) {
      const std::size_t r = static_cast<std::size_t>(grid.cellY(v) - y0_);
      row_min[r] = std::min<std::int64_t>(row_min[r], grid.cellX(v));
      row_max[r] = std::max<std::int64_t>(row_max[r], grid.cellX(v));
    }
    // The same over all rows above (suffix) and below (prefix) each row.
    above_min_.assign(rows + 1, INT64_MAX);
    above_max_.assign(rows + 1, INT64_MIN);
    below_min_.assign(rows + 1, INT64_MAX);
    below_max_.assign(rows + 1, INT64_MIN);
    for (std::size_t r = rows; r-- > 0;) {
      above_min_[r] = std::min(above_min_[r + 1], row_min[r]);
      above_max_[r] = std::max(above_max_[r + 1], row_max[r]);
    }
    for (std::size_t r = 0; r < rows; ++r) {
      below_min_[r + 1] = std::min(below_min_[r], row_min[r]);
      below_max_[r + 1] = std::max(below_max_[r], row_max[r]);
    }
  }
  bool operator()(std::int64_t cx, std::int64_t cy) const {
    if (above_min_.empty()) return false;
    const std::size_t r = static_cast<std::size_t>(cy - y0_);
    // Rows strictly above: r + 1 onwards; strictly below: rows 0 .. r - 1 (below_*[r]).
    return above_min_[r + 1] < cx && above_max_[r + 1] > cx && below_min_[r] < cx &&
           below_max_[r] > cx;
  }

 private:
  std::int64_t y0_ = 0;
  std::vector<std::int64_t> above_min_, above_max_, below_min_, below_max_;
};

// The number of grid columns that `members` occupy. Each column is marked through its first
// voxel (a column's voxels are contiguous) in a scratch array of the thread's, left clean for
// the next call: no sort of the members' columns.
std::size_t distinctColumns(const VoxelGrid& grid, const std::vector<std::uint32_t>& members) {
  thread_local std::vector<std::uint8_t> column_seen;
  if (column_seen.size() < grid.numVoxels()) column_seen.resize(grid.numVoxels(), 0);
  auto firstOfColumn = [&](std::uint32_t v) {
    return grid.columnVoxels(grid.cellX(v), grid.cellY(v)).first;
  };
  std::size_t distinct = 0;
  for (std::uint32_t v : members) {
    std::uint8_t& seen = column_seen[firstOfColumn(v)];
    distinct += seen ? 0 : 1;
    seen = 1;
  }
  for (std::uint32_t v : members) column_seen[firstOfColumn(v)] = 0;
  return distinct;
}

}  // namespace

const char* toString(Facing facing) {
  switch (facing) {
    case Facing::kUp:
      return "up";
    case Facing::kDown:
      return "down";
    case Facing::kUnknown:
      break;
  }
  return "unknown";
}

namespace {

// Akl–Toussaint: the points extreme in eight directions (x, y and both diagonals, both ways)
// span an octagon inside the hull, and a point strictly inside it cannot be a hull vertex.
// One pass drops those points, so that the O(n log n) sort sees only the few near the rim; the
// hull is the same, vertex for vertex. Returns the number of points kept at the front.
std::size_t dropPointsInsideExtremeOctagon(Eigen::Vector2d* points, std::size_t n) {
  // Directions at -90°, -45°, 0°, 45°, 90°, 135°, 180°, 225° (their extreme points follow one
  // another counter-clockwise around the hull), scored without multiplications: -y, x - y, x,
  // x + y, y, y - x, -x, -x - y.
  std::size_t extreme[8] = {0, 0, 0, 0, 0, 0, 0, 0};
  double best[8];
  for (int k = 0; k < 8; ++k) best[k] = -HUGE_VAL;
  for (std::size_t i = 0; i < n; ++i) {
    const double x = points[i].x(), y = points[i].y();
    const double score[8] = {-y, x - y, x, x + y, y, y - x, -x, -x - y};
    for (int k = 0; k < 8; ++k) {
      if (score[k] > best[k]) best[k] = score[k], extreme[k] = i;
    }
  }
  Eigen::Vector2d octagon[8];
  std::size_t corners = 0;
  for (int k = 0; k < 8; ++k) {
    const Eigen::Vector2d& p = points[extreme[k]];
    if (corners == 0 || p != octagon[corners - 1]) octagon[corners++] = p;
  }
  while (corners > 1 && octagon[corners - 1] == octagon[0]) --corners;
  if (corners < 3) return n;
  auto strictlyInside = [&](const Eigen::Vector2d& p, double margin) {
    for (std::size_t k = 0; k < corners; ++k) {
      if (!(cross(octagon[k], octagon[(k + 1) % corners], p) > margin)) return false;
    }
    return true;
  };
  // Most points lie well inside: a box inside the octagon settles them with four comparisons.
  // The box spanned by the innermost coordinates of the extreme points on each side touches the
  // octagon (a rectangle's corners are its vertices), so it is shrunk about its centre until
  // its corners lie inside by a margin far above the rounding of the edge tests: a point inside
  // it then passes every edge test too (the tests are linear in the point), and the points
  // kept are the same as with the edge tests alone.
  auto coordinate = [&](int k, int axis) { return points[extreme[k]](axis); };
  const double left = std::max({coordinate(5, 0), coordinate(6, 0), coordinate(7, 0)});
  const double right = std::min({coordinate(1, 0), coordinate(2, 0), coordinate(3, 0)});
  const double bottom = std::max({coordinate(7, 1), coordinate(0, 1), coordinate(1, 1)});
  const double top = std::min({coordinate(3, 1), coordinate(4, 1), coordinate(5, 1)});
  const double extent = (best[2] + best[6]) + (best[4] + best[0]);  // width + height
  const double margin = 1e-6 * extent * extent;
  double x0 = 0, x1 = 0, y0 = 0, y1 = 0;
  bool use_box = false;
  for (const double shrink : {0.98, 0.9, 0.7}) {
    if (!(left < right && bottom < top)) break;
    const double cx = 0.5 * (left + right), cy = 0.5 * (bottom + top);
    const double hx = 0.5 * shrink * (right - left), hy = 0.5 * shrink * (top - bottom);
    x0 = cx - hx, x1 = cx + hx, y0 = cy - hy, y1 = cy + hy;
    use_box = true;
    for (int corner = 0; corner < 4 && use_box; ++corner) {
      use_box = strictlyInside(Eigen::Vector2d(corner & 1 ? x1 : x0, corner & 2 ? y1 : y0), margin);
    }
    if (use_box) break;
  }
  std::size_t kept = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const Eigen::Vector2d p = points[i];
    if (use_box && p.x() > x0 && p.x() < x1 && p.y() > y0 && p.y() < y1) continue;
    if (!strictlyInside(p, 0.0)) points[kept++] = p;
  }
  return kept;
}

}  // namespace

std::size_t convexHullInPlace(Eigen::Vector2d* points, std::size_t n, Eigen::Vector2d* hull) {
  auto less = [](const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
    return a.x() < b.x() || (a.x() == b.x() && a.y() < b.y());
  };
  // Below a few dozen points the sort is cheaper than the extra pass.
  if (n > 64) n = dropPointsInsideExtremeOctagon(points, n);
  std::sort(points, points + n, less);
  n = static_cast<std::size_t>(std::unique(points, points + n) - points);
  if (n < 3) {
    std::copy(points, points + n, hull);
    return n;
  }
  std::size_t k = 0;
  for (std::size_t i = 0; i < n; ++i) {  // lower chain
    while (k >= 2 && cross(hull[k - 2], hull[k - 1], points[i]) <= 0) --k;
    hull[k++] = points[i];
  }
  for (std::size_t i = n - 1, lower = k + 1; i-- > 0;) {  // upper chain
    while (k >= lower && cross(hull[k - 2], hull[k - 1], points[i]) <= 0) --k;
    hull[k++] = points[i];
  }
  return k - 1;  // the last point repeats the first
}

std::vector<Eigen::Vector2d> convexHull2D(std::vector<Eigen::Vector2d> points) {
  std::vector<Eigen::Vector2d> hull(2 * points.size() + 1);
  hull.resize(convexHullInPlace(points.data(), points.size(), hull.data()));
  return hull;
}

HorizontalPlane describePlane(const VoxelGrid& grid, const AlignedPoints& aligned,
                              const std::vector<std::uint32_t>& members, Detail detail) {
  HorizontalPlane plane;
  plane.num_voxels = members.size();
  if (members.empty()) return plane;

  // Offsets from a reference point keep the second moments well conditioned. The normal is
  // fitted to the voxel centroids weighted by their point counts: the same plane as a fit to
  // every point when the points inside each voxel are flat, at a fraction of the cost.
  const Eigen::Vector3d ref = grid.centroid(members.front()).cast<double>();
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  Eigen::Matrix3d outer = Eigen::Matrix3d::Zero();
  Eigen::Vector2d lo(HUGE_VAL, HUGE_VAL), hi(-HUGE_VAL, -HUGE_VAL);
  std::size_t count = 0;
  for (std::uint32_t v : members) {
    const double weight = static_cast<double>(grid.numPointsIn(v));
    const Eigen::Vector3d d = grid.centroid(v).cast<double>() - ref;
    sum += weight * d;
    outer.noalias() += weight * d * d.transpose();
    count += grid.numPointsIn(v);
    // The occupied cells' box; Detail::kFull replaces it with the points' own.
    const double x0 = grid.cellMinX(grid.cellX(v)), y0 = grid.cellMinY(grid.cellY(v));
    lo = lo.cwiseMin(Eigen::Vector2d(x0, y0));
    hi = hi.cwiseMax(Eigen::Vector2d(x0 + grid.rXY(), y0 + grid.rXY()));
  }

  plane.num_points = count;
  const Eigen::Vector3d mean = sum / static_cast<double>(count);
  plane.centroid = ref + mean;
  plane.height = plane.centroid.z();
  plane.bbox = {lo.x(), lo.y(), hi.x(), hi.y()};

  const Eigen::Matrix3d covariance = outer / static_cast<double>(count) - mean * mean.transpose();
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(covariance);
  Eigen::Vector3d n = solver.eigenvectors().col(0);
  if (n.allFinite() && n.norm() > 0.5) {
    n.normalize();
    plane.normal = n.z() < 0 ? Eigen::Vector3d(-n) : n;
  }
  plane.tilt = std::acos(std::min(1.0, plane.normal.z()));

  plane.area = static_cast<double>(distinctColumns(grid, members)) * grid.rXY() * grid.rXY();

  if (detail == Detail::kFull) describeInFull(grid, aligned, {&members}, {&plane});
  return plane;
}

void describeInFull(const VoxelGrid& grid, const AlignedPoints& aligned,
                    const std::vector<const std::vector<std::uint32_t>*>& members,
                    const std::vector<HorizontalPlane*>& planes, int threads,
                    const PointLabelling& labelling) {
  const std::size_t num_planes = planes.size();
  if (num_planes == 0 && !labelling.point_labels) return;
  threads = parallel::resolve(threads);
  // The plane of each voxel at a plane's rim (see InteriorTest); -1 for the others, whose
  // points are inside their plane's hull and within its bbox.
  std::vector<std::int32_t> rim_owner(grid.numVoxels(), -1);
  parallel::forEach(num_planes, threads, [&](std::size_t k) {
    if (members[k]->empty()) return;
    const InteriorTest interior(grid, *members[k]);
    for (std::uint32_t v : *members[k]) {
      if (!interior(grid.cellX(v), grid.cellY(v))) rim_owner[v] = static_cast<std::int32_t>(k);
    }
  });
  // One read of the points' voxels for all planes: each share of the points collects its hull
  // candidates per plane (every point of a rim voxel: a vertex need not be a voxel's extreme
  // in x or y, one at a cell's corner can stick out diagonally).
  constexpr int kMaxShares = 64;
  std::vector<std::vector<Eigen::Vector2d>> candidates[kMaxShares];
  const std::vector<std::int32_t>& point_voxel = grid.pointVoxel();
  const int shares = parallel::forShares(
      point_voxel.size(), std::min(threads, kMaxShares), std::size_t{1} << 15,
      [&](int share, std::size_t begin, std::size_t end) {
        std::vector<std::vector<Eigen::Vector2d>>& mine = candidates[share];
        mine.assign(num_planes, {});
        std::int32_t* labels = labelling.point_labels;
        for (std::size_t i = begin; i < end; ++i) {
          const std::int32_t v = point_voxel[i];
          if (labels) {
            labels[i] = v < 0 ? -1 : (*labelling.voxel_label)[static_cast<std::size_t>(v)];
          }
          if (v < 0) continue;
          const std::int32_t k = rim_owner[static_cast<std::size_t>(v)];
          if (k < 0) continue;
          const Eigen::Vector3f p = aligned[i];
          mine[static_cast<std::size_t>(k)].emplace_back(p.x(), p.y());
        }
      });
  parallel::forEach(num_planes, threads, [&](std::size_t k) {
    HorizontalPlane& plane = *planes[k];
    if (members[k]->empty()) return;
    std::vector<Eigen::Vector2d> points = std::move(candidates[0][k]);
    for (int s = 1; s < shares; ++s) {
      points.insert(points.end(), candidates[s][k].begin(), candidates[s][k].end());
    }
    Eigen::Vector2d lo(HUGE_VAL, HUGE_VAL), hi(-HUGE_VAL, -HUGE_VAL);
    for (const Eigen::Vector2d& q : points) {
      lo = lo.cwiseMin(q);
      hi = hi.cwiseMax(q);
    }
    plane.bbox = {lo.x(), lo.y(), hi.x(), hi.y()};
    plane.hull.clear();
    for (const Eigen::Vector2d& h : convexHull2D(std::move(points))) {
      plane.hull.emplace_back(h.x(), h.y(), plane.height);
    }
    std::vector<std::pair<std::int64_t, std::int64_t>> cells;
    cells.reserve(members[k]->size());
    for (std::uint32_t v : *members[k]) cells.emplace_back(grid.cellX(v), grid.cellY(v));
    // Within three quarters of a cell: a staircase along a diagonal edge becomes one line.
    const auto rings =
        traceOutline(std::move(cells), Eigen::Vector2d(grid.cellMinX(0), grid.cellMinY(0)),
                     grid.rXY(), 0.75 * grid.rXY());
    plane.outline.clear();
    for (const auto& ring : rings) {
      plane.outline.emplace_back();
      for (const Eigen::Vector2d& q : ring)
        plane.outline.back().emplace_back(q.x(), q.y(), plane.height);
    }
  });
}

}  // namespace hope
