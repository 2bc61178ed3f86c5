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
  const HeightAbovePlane height_above(floor, local_origin);
  std::vector<std::uint32_t> out;
  for (std::size_t i = 0; i < points.size(); ++i) {
    const Eigen::Vector3f p = points[i];
    if (!p.allFinite()) continue;
    const double above = height_above(p);
    if (above > min_height && above <= max_height) out.push_back(static_cast<std::uint32_t>(i));
  }
  return out;
}

}  // namespace hope
