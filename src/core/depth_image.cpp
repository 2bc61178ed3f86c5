#include "hope/depth_image.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string>

#include <opencv2/imgproc.hpp>

namespace hope {

void PinholeIntrinsics::validate() const {
  if (!std::isfinite(fx) || !std::isfinite(fy) || !std::isfinite(cx) || !std::isfinite(cy) ||
      fx <= 0 || fy <= 0) {
    std::ostringstream msg;
    msg << "intrinsics (fx fy cx cy) = (" << fx << " " << fy << " " << cx << " " << cy
        << ") are invalid: fx and fy must be positive focal lengths in pixels, all finite";
    throw std::invalid_argument(msg.str());
  }
}

void PinholeIntrinsics::validateFor(int width, int height) const {
  validate();
  auto fail = [&](const std::string& why) {
    std::ostringstream msg;
    msg << "intrinsics (fx fy cx cy) = (" << fx << " " << fy << " " << cx << " " << cy
        << ") do not fit the " << width << " x " << height << " image: " << why
        << " (intrinsics for another resolution?)";
    throw std::invalid_argument(msg.str());
  };
  if (!(cx >= 0 && cx <= width && cy >= 0 && cy <= height)) {
    fail("the principal point is outside the image");
  }
  // At 1 m the image spans width / fx metres across.
  const double span_x = width / fx, span_y = height / fy;
  if (std::min(span_x, span_y) < 1e-3 || std::max(span_x, span_y) > 1e3) {
    std::ostringstream why;
    why << "at 1 m depth the image would span " << span_x << " x " << span_y
        << " m; a camera's spans between 0.001 and 1000 m";
    fail(why.str());
  }
}

namespace {

// Metres per raw depth unit, after checking the image.
double metresPerUnit(const cv::Mat& depth, double depth_scale) {
  if (depth.empty()) throw std::invalid_argument("depth image is empty");
  if (depth.type() == CV_32FC1) return 1.0;
  if (depth.type() != CV_16UC1) {
    std::ostringstream msg;
    static const char* const kDepthNames[] = {"8-bit unsigned", "8-bit signed",   "16-bit unsigned",
                                              "16-bit signed",  "32-bit integer", "32-bit float",
                                              "64-bit float",   "16-bit float"};
    msg << "depth image must be 16-bit unsigned (raw units) or 32-bit float (metres) with one "
           "channel; this one is "
        << kDepthNames[depth.depth()] << " with " << depth.channels() << " channel(s)";
    throw std::invalid_argument(msg.str());
  }
  if (!std::isfinite(depth_scale) || depth_scale <= 0) {
    std::ostringstream msg;
    msg << "depth scale " << depth_scale << " must be a positive number of raw units per metre "
        << "(TUM: 5000, OpenNI millimetres: 1000)";
    throw std::invalid_argument(msg.str());
  }
  return 1.0 / depth_scale;
}

// A depth scale that puts every depth of a 16-bit image under 1 mm or beyond 10 km (e.g. 1e300
// or 1e-300 units per metre) would give an empty cloud and a run with no planes and no reason.
void requirePlausibleDepths(const cv::Mat& depth, double unit, double depth_scale) {
  double nearest = 0, farthest = 0;
  cv::minMaxLoc(depth, nullptr, &farthest);
  if (farthest <= 0) return;  // nothing measured: an empty frame, not a wrong scale
  cv::Mat measured = depth.clone();
  measured.setTo(std::numeric_limits<std::uint16_t>::max(), depth == 0);
  cv::minMaxLoc(measured, &nearest, nullptr);
  if (farthest * unit < 1e-3 || nearest * unit > 1e4) {
    std::ostringstream msg;
    msg << "depth scale " << depth_scale << " puts this image's depths (raw " << nearest << " to "
        << farthest << ") at " << nearest * unit << " to " << farthest * unit
        << " m; it must be the raw units per metre (TUM: 5000, OpenNI millimetres: 1000)";
    throw std::invalid_argument(msg.str());
  }
}

template <class PointT, class Colorize>
pcl::PointCloud<PointT> backProject(const cv::Mat& depth, const PinholeIntrinsics& k,
                                    double depth_scale, Colorize colorize) {
  const double unit = metresPerUnit(depth, depth_scale);
  k.validateFor(depth.cols, depth.rows);
  if (depth.type() == CV_16UC1) requirePlausibleDepths(depth, unit, depth_scale);
  pcl::PointCloud<PointT> cloud(static_cast<std::uint32_t>(depth.cols),
                                static_cast<std::uint32_t>(depth.rows));
  cloud.is_dense = false;
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const bool is_float = depth.type() == CV_32FC1;
  for (int r = 0; r < depth.rows; ++r) {
    for (int c = 0; c < depth.cols; ++c) {
      // Indexed directly: PCL's at(c, r) throws for an image one row high (found by fuzzing).
      PointT& p = cloud.points[static_cast<std::size_t>(r) * depth.cols + c];
      colorize(p, r, c);
      const double z = is_float ? static_cast<double>(depth.at<float>(r, c))
                                : depth.at<std::uint16_t>(r, c) * unit;
      if (!(z > 0) || !std::isfinite(z)) {
        p.x = p.y = p.z = nan;
        continue;
      }
      p.x = static_cast<float>((c - k.cx) * z / k.fx);
      p.y = static_cast<float>((r - k.cy) * z / k.fy);
      p.z = static_cast<float>(z);
    }
  }
  return cloud;
}

}  // namespace

pcl::PointCloud<pcl::PointXYZ> depthToCloud(const cv::Mat& depth, const PinholeIntrinsics& k,
                                            double depth_scale) {
  return backProject<pcl::PointXYZ>(depth, k, depth_scale, [](pcl::PointXYZ&, int, int) {});
}

pcl::PointCloud<pcl::PointXYZRGB> depthToColoredCloud(const cv::Mat& depth, const cv::Mat& image,
                                                      const PinholeIntrinsics& k,
                                                      double depth_scale) {
  if (image.size() != depth.size()) {
    std::ostringstream msg;
    msg << "colour image is " << image.cols << "x" << image.rows << " but depth image is "
        << depth.cols << "x" << depth.rows << "; they must be registered pixel for pixel";
    throw std::invalid_argument(msg.str());
  }
  cv::Mat bgr;
  if (image.type() == CV_8UC3) {
    bgr = image;
  } else if (image.type() == CV_8UC1) {
    cv::cvtColor(image, bgr, cv::COLOR_GRAY2BGR);
  } else if (image.type() == CV_8UC4) {
    cv::cvtColor(image, bgr, cv::COLOR_BGRA2BGR);
  } else {
    throw std::invalid_argument("colour image must be 8-bit grey, BGR or BGRA");
  }
  return backProject<pcl::PointXYZRGB>(depth, k, depth_scale,
                                       [&bgr](pcl::PointXYZRGB& p, int r, int c) {
                                         const cv::Vec3b& px = bgr.at<cv::Vec3b>(r, c);
                                         p.b = px[0];
                                         p.g = px[1];
                                         p.r = px[2];
                                       });
}

}  // namespace hope
