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

// The input indices of the points more than `min_height` and at most `max_height` above the
// floor plane under them (its fitted plane, so a floor tilted within the extraction's slope
// limit is followed), in input order. `points` as Extractor::alignedPoints() gives them,
// relative to `local_origin`; non-finite points are never obstacles.
std::vector<std::uint32_t> obstaclePoints(const AlignedPoints& points,
                                          const Eigen::Vector3d& local_origin,
                                          const HorizontalPlane& floor, double min_height,
                                          double max_height);

}  // namespace hope
