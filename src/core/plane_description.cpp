#include "hope/plane_description.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>

#include <Eigen/Eigenvalues>

#include "hope/plane_outline.h"
#include "parallel.h"

namespace hope {

namespace {

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
  // points are inside their plane's hull and within its bbox. Each plane numbers its rim voxels
  // (rim_slot), the cells of its hull's CellPoints.
  std::vector<std::int32_t> rim_owner(grid.numVoxels(), -1);
  std::vector<std::uint32_t> rim_slot(grid.numVoxels());
  std::vector<std::vector<std::uint32_t>> rims(num_planes);
  parallel::forEach(num_planes, threads, [&](std::size_t k) {
    if (members[k]->empty()) return;
    const InteriorTest interior(grid, *members[k]);
    for (std::uint32_t v : *members[k]) {
      if (interior(grid.cellX(v), grid.cellY(v))) continue;
      rim_owner[v] = static_cast<std::int32_t>(k);
      rim_slot[v] = static_cast<std::uint32_t>(rims[k].size());
      rims[k].push_back(v);
    }
  });
  // One read of the points' voxels for all planes: each share of the points collects its hull
  // candidates per plane (every point of a rim voxel: a vertex need not be a voxel's extreme
  // in x or y, one at a cell's corner can stick out diagonally).
  constexpr int kMaxShares = 64;
  struct Candidates {
    std::vector<Eigen::Vector2d> points;
    std::vector<std::uint32_t> slots;  // each point's rim voxel, as rim_slot numbers it
  };
  // Kept across calls, one set per calling thread (two extractors on two threads never share
  // one): a frame's candidates go into the capacity the last frame left instead of growing from
  // nothing, at the price of holding that much (the largest frame's rim points) between calls.
  // The parallel loops reach the caller's set through the pointer: inside them the name of a
  // thread_local would mean each worker's own.
  thread_local std::vector<Candidates> kept_candidates[kMaxShares];
  std::vector<Candidates>* const candidates = kept_candidates;
  const VoxelGrid::PointVoxels point_voxel = grid.pointVoxels();
  const int shares = parallel::forShares(
      point_voxel.size(), std::min(threads, kMaxShares), std::size_t{1} << 15,
      [&](int share, std::size_t begin, std::size_t end) {
        std::vector<Candidates>& mine = candidates[share];
        if (mine.size() < num_planes) mine.resize(num_planes);
        for (std::size_t k = 0; k < num_planes; ++k) {
          mine[k].points.clear();
          mine[k].slots.clear();
        }
        // Locals, not captures: the stores into the labels (int32_t) could otherwise alias
        // every table read here, which the compiler would then reload for each point.
        const VoxelGrid::PointVoxels voxels = point_voxel;
        const std::int32_t* owner = rim_owner.data();
        std::int32_t* labels = labelling.point_labels;
        const std::int32_t* voxel_label = labels ? labelling.voxel_label->data() : nullptr;
        for (std::size_t i = begin; i < end; ++i) {
          const std::int32_t v = voxels[i];
          if (labels) labels[i] = v < 0 ? -1 : voxel_label[v];
          if (v < 0) continue;
          const std::int32_t k = owner[v];
          if (k < 0) continue;
          float xy[2];  // the hull and the bbox need x and y only
          std::memcpy(xy, aligned.data + i * aligned.stride, sizeof(xy));
          Candidates& own = mine[static_cast<std::size_t>(k)];
          own.points.emplace_back(xy[0], xy[1]);
          own.slots.push_back(rim_slot[static_cast<std::size_t>(v)]);
        }
      });
  parallel::forEach(num_planes, threads, [&](std::size_t k) {
    HorizontalPlane& plane = *planes[k];
    if (members[k]->empty()) return;
    CellPoints rim;
    rim.side = grid.rXY();
    rim.points.swap(candidates[0][k].points);
    rim.cell_of_point.swap(candidates[0][k].slots);
    for (int s = 1; s < shares; ++s) {
      const Candidates& more = candidates[s][k];
      rim.points.insert(rim.points.end(), more.points.begin(), more.points.end());
      rim.cell_of_point.insert(rim.cell_of_point.end(), more.slots.begin(), more.slots.end());
    }
    Eigen::Vector2d lo(HUGE_VAL, HUGE_VAL), hi(-HUGE_VAL, -HUGE_VAL);
    for (const Eigen::Vector2d& q : rim.points) {
      lo = lo.cwiseMin(q);
      hi = hi.cwiseMax(q);
    }
    plane.bbox = {lo.x(), lo.y(), hi.x(), hi.y()};
    // Each rim voxel's column and the mean of its points, which lies inside their hull.
    for (std::uint32_t v : rims[k]) {
      rim.cell_min.emplace_back(grid.cellMinX(grid.cellX(v)), grid.cellMinY(grid.cellY(v)));
      rim.cell_inner.emplace_back(grid.centroid(v).x(), grid.centroid(v).y());
    }
    plane.hull.clear();
    for (const Eigen::Vector2d& h : convexHullOfCellPoints(rim)) {
      plane.hull.emplace_back(h.x(), h.y(), plane.height);
    }
    // Back into the kept set, whose capacity the next call fills.
    candidates[0][k].points.swap(rim.points);
    candidates[0][k].slots.swap(rim.cell_of_point);
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
