// Nearest neighbour plane matching (NNPM, paper §2.5, Eq 11–14): the paper's way of carrying
// plane ids from one frame to the next.
#pragma once

#include <vector>

#include <Eigen/Core>

#include "hope/plane.h"

namespace hope {

// (z_mean, x_min, y_min, x_max, y_max) of a plane in the reference frame.
using PlaneFeatures = Eigen::Matrix<double, 5, 1>;

PlaneFeatures planeFeatures(const HorizontalPlane& plane);

// Eq 11–14: each feature is normalized jointly over the previous and the current planes
// (shared mean and population standard deviation), in place. A feature with zero spread
// (e.g. one plane in each frame at the same height) carries no information and becomes 0
// rather than a division by zero.
void normalizeJointly(std::vector<PlaneFeatures>& previous, std::vector<PlaneFeatures>& current);

struct NearestNeighborMatch {
  int previous = -1;      // index into the previous planes, -1 when it must get a new id
  double distance = 0.0;  // L2 distance in the normalized feature space
};

// For each current plane, its one nearest previous plane in the normalized feature space,
// found with FLANN (OpenCV's cv::flann, as the authors did). When several current planes
// pick the same previous plane, the closest keeps it and the others get -1 (new ids); ties
// go to the earlier current plane.
std::vector<NearestNeighborMatch> matchNearestNeighbors(
    const std::vector<HorizontalPlane>& previous, const std::vector<HorizontalPlane>& current);

}  // namespace hope
