#include "hope/plane_description.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Eigenvalues>

#include "hope/plane_outline.h"

namespace hope {

namespace {

double cross(const Eigen::Vector2d& o, const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  return (a.x() - o.x()) * (b.y() - o.y()) - (a.y() - o.y()) * (b.x() - o.x());
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

std::size_t convexHullInPlace(Eigen::Vector2d* points, std::size_t n, Eigen::Vector2d* hull) {
  auto less = [](const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
    return a.x() < b.x() || (a.x() == b.x() && a.y() < b.y());
  };
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

HorizontalPlane describePlane(const VoxelGrid& grid, const std::vector<Eigen::Vector3f>& aligned,
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
  // The hull of all points equals the hull of each voxel's xy-extreme points, which are far
  // fewer: up to four per voxel.
  std::vector<Eigen::Vector2d> hull_candidates;
  if (detail == Detail::kFull) hull_candidates.reserve(4 * members.size());
  std::vector<std::uint64_t> columns;
  columns.reserve(members.size());
  std::size_t count = 0;

  for (std::uint32_t v : members) {
    columns.push_back(grid.column(v));
    const std::uint32_t* begin = grid.pointsBegin(v);
    const std::uint32_t* end = grid.pointsEnd(v);
    const double weight = static_cast<double>(end - begin);
    const Eigen::Vector3d d = grid.centroid(v).cast<double>() - ref;
    sum += weight * d;
    outer.noalias() += weight * d * d.transpose();
    count += static_cast<std::size_t>(end - begin);
    if (detail == Detail::kVoxels) {
      const double x0 = grid.cellMinX(grid.cellX(v)), y0 = grid.cellMinY(grid.cellY(v));
      lo = lo.cwiseMin(Eigen::Vector2d(x0, y0));
      hi = hi.cwiseMax(Eigen::Vector2d(x0 + grid.rXY(), y0 + grid.rXY()));
      continue;
    }
    // Indices of the min x, max x, min y, max y points, with their coordinates cached.
    std::uint32_t extreme[4] = {*begin, *begin, *begin, *begin};
    const Eigen::Vector3f& first = aligned[*begin];
    float min_x = first.x(), max_x = first.x(), min_y = first.y(), max_y = first.y();
    for (const std::uint32_t* it = begin + 1; it != end; ++it) {
      const Eigen::Vector3f& p = aligned[*it];
      if (p.x() < min_x) {
        min_x = p.x();
        extreme[0] = *it;
      }
      if (p.x() > max_x) {
        max_x = p.x();
        extreme[1] = *it;
      }
      if (p.y() < min_y) {
        min_y = p.y();
        extreme[2] = *it;
      }
      if (p.y() > max_y) {
        max_y = p.y();
        extreme[3] = *it;
      }
    }
    for (const std::uint32_t e : extreme) {
      const Eigen::Vector3f& p = aligned[e];
      hull_candidates.emplace_back(p.x(), p.y());
      lo = lo.cwiseMin(Eigen::Vector2d(p.x(), p.y()));
      hi = hi.cwiseMax(Eigen::Vector2d(p.x(), p.y()));
    }
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

  std::sort(columns.begin(), columns.end());
  const auto distinct = std::unique(columns.begin(), columns.end()) - columns.begin();
  plane.area = static_cast<double>(distinct) * grid.rXY() * grid.rXY();

  if (detail == Detail::kVoxels) return plane;
  for (const Eigen::Vector2d& h : convexHull2D(std::move(hull_candidates))) {
    plane.hull.emplace_back(h.x(), h.y(), plane.height);
  }
  std::vector<std::pair<std::int64_t, std::int64_t>> cells;
  cells.reserve(members.size());
  for (std::uint32_t v : members) cells.emplace_back(grid.cellX(v), grid.cellY(v));
  // Within three quarters of a cell: a staircase along a diagonal edge becomes one line.
  const auto rings =
      traceOutline(std::move(cells), Eigen::Vector2d(grid.cellMinX(0), grid.cellMinY(0)),
                   grid.rXY(), 0.75 * grid.rXY());
  for (const auto& ring : rings) {
    plane.outline.emplace_back();
    for (const Eigen::Vector2d& q : ring)
      plane.outline.back().emplace_back(q.x(), q.y(), plane.height);
  }
  return plane;
}

}  // namespace hope
