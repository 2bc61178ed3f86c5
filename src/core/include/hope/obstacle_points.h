// Obstacles: the points standing between two heights above the floor under them, what a
// costmap's obstacle layer or an octomap takes (Patchwork++'s non-ground cloud, with the floor
// HoPE found instead of a ground fit).
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include <Eigen/Core>

#include "hope/plane.h"
#include "hope/points_view.h"

namespace hope {

// A patch of floor at least half a metre square: a smaller level surface low in the view is a
// step, a box top or a tread, not the floor a robot stands on.
constexpr double kFloorMinArea = 0.25;

// The floor: the lowest plane seen from above (facing up, or unknown when the sensor's
// position is) whose area is at least kFloorMinArea, or none.
std::optional<std::size_t> findFloor(const std::vector<HorizontalPlane>& planes);

// How far a point is above a plane's fitted surface under it (the floor's for obstacles and
// the grid, a support's for the objects' feet): the plane n · (p − c) = 0, whose height under
// (x, y) is c_z − (n_x (x − c_x) + n_y (y − c_y)) / n_z, so a plane tilted within the
// extraction's slope limit is followed. Points as Extractor::alignedPoints() gives them,
// relative to local_origin.
class HeightAbovePlane {
 public:
  HeightAbovePlane(const HorizontalPlane& plane, const Eigen::Vector3d& local_origin)
      : c_(plane.centroid - local_origin),
        gx_(-plane.normal.x() / plane.normal.z()),
        gy_(-plane.normal.y() / plane.normal.z()) {}
  double operator()(const Eigen::Vector3f& p) const {
    return p.z() - (c_.z() + gx_ * (p.x() - c_.x()) + gy_ * (p.y() - c_.y()));
  }

 private:
  Eigen::Vector3d c_;
  double gx_, gy_;
};

// The input indices of the points more than `min_height` and at most `max_height` above the
// floor plane under them (HeightAbovePlane), in input order. `points` as Extractor::alignedPoints()
// gives them, relative to `local_origin`; non-finite points are never obstacles.
std::vector<std::uint32_t> obstaclePoints(const AlignedPoints& points,
                                          const Eigen::Vector3d& local_origin,
                                          const HorizontalPlane& floor, double min_height,
                                          double max_height);

}  // namespace hope
