// Pictures a person can judge at a glance.
#pragma once

#include <vector>

#include <pcl/point_cloud.h>
#include <pcl/point_types.h>
#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "hope/extractor.h"

namespace hope {
namespace tools {

// The Pascal VOC colour map entry `index` as BGR (index 0 is the black background, so plane
// id k uses index k + 1).
cv::Vec3b vocColor(int index);

// For an organized cloud: the image (its colour, or a grey depth rendering) with every plane's
// pixels tinted by its id and "id: height" written on it. For an unorganized cloud: a top-down
// view of the aligned points, planes tinted, hulls outlined and labelled.
cv::Mat renderOverlay(const pcl::PointCloud<pcl::PointXYZRGB>& cloud, bool has_color,
                      const std::vector<Eigen::Vector3f>& aligned, const Result& result);

}  // namespace tools
}  // namespace hope
