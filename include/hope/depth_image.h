// The RGB-D input path (paper §2.1): a depth image and pinhole intrinsics become an organized
// cloud in the camera optical frame (x right, y down, z forward).
#pragma once

#include <string>

#include <pcl/point_cloud.h>
#include <pcl/point_types.h>
#include <opencv2/core.hpp>

namespace hope {

struct PinholeIntrinsics {
  double fx = 0, fy = 0, cx = 0, cy = 0;
  // TUM RGB-D freiburg1 (depth registered to RGB).
  static PinholeIntrinsics tumFreiburg1() { return {517.3, 516.5, 318.6, 255.3}; }
  // Throws std::invalid_argument unless fx, fy > 0 and all are finite.
  void validate() const;
  // validate(), and throws std::invalid_argument when these intrinsics cannot be the camera of
  // a width × height image: the principal point outside the image, or a focal length under
  // 1/1000 of the image's size (a view of over 179.9°, every point thrown far off) or over 1000
  // times it (the image under 1 mm wide at 1 m). Intrinsics for another resolution, or a typo
  // such as 1e-300, otherwise turn every frame into non-finite or meaningless points.
  void validateFor(int width, int height) const;
};

// `depth` is CV_16UC1 (raw units, `depth_scale` units per metre: TUM uses 5000, OpenNI 1000)
// or CV_32FC1 (metres; `depth_scale` ignored). Zero, negative and non-finite depths become
// NaN points, so the cloud stays organized (width × height). Throws std::invalid_argument for
// other image types, an empty image, intrinsics that do not fit the image (validateFor) or a
// non-positive depth_scale.
pcl::PointCloud<pcl::PointXYZ> depthToCloud(const cv::Mat& depth, const PinholeIntrinsics& k,
                                            double depth_scale);

// Same, coloured from an 8-bit BGR (or grey) image of the same size registered to the depth.
pcl::PointCloud<pcl::PointXYZRGB> depthToColoredCloud(const cv::Mat& depth, const cv::Mat& bgr,
                                                      const PinholeIntrinsics& k,
                                                      double depth_scale);

}  // namespace hope
