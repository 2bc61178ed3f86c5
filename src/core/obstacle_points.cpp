#include "hope/obstacle_points.h"

#include <cmath>

namespace hope {

std::optional<std::size_t> findFloor(const std::vector<HorizontalPlane>& planes) {
  std::optional<std::size_t> floor;
  for (std::size_t i = 0; i < planes.size(); ++i) {
    const HorizontalPlane& p = planes[i];
    if (p.facing == Facing::kDown || p.area < kFloorMinArea) continue;
    if (!floor || p.height < planes[*floor].height) floor = i;
  }
  return floor;
}

std::vector<std::uint32_t> obstaclePoints(const AlignedPoints& points,
                                          const Eigen::Vector3d& local_origin,
                                          const HorizontalPlane& floor, double min_height,
                                          double max_height) {
  // The floor's fitted plane n · (p − c) = 0, in the aligned points' frame: its height under a
  // point is c_z − (n_x (x − c_x) + n_y (y − c_y)) / n_z (n_z > 0: the normal points up).
  const Eigen::Vector3d c = floor.centroid - local_origin;
  const Eigen::Vector3d& n = floor.normal;
  const double gx = -n.x() / n.z(), gy = -n.y() / n.z();
  std::vector<std::uint32_t> out;
  for (std::size_t i = 0; i < points.size(); ++i) {
    const Eigen::Vector3f p = points[i];
    if (!p.allFinite()) continue;
    const double under = c.z() + gx * (p.x() - c.x()) + gy * (p.y() - c.y());
    const double above = p.z() - under;
    if (above > min_height && above <= max_height) out.push_back(static_cast<std::uint32_t>(i));
  }
  return out;
}

}  // namespace hope
