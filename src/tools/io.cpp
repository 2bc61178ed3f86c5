#include "hope/tools/io.h"

#include <cerrno>
#include <cstring>

#include <fstream>
#include <sstream>
#include <stdexcept>

#include <pcl/io/pcd_io.h>
#include <opencv2/imgcodecs.hpp>

#include "hope/tools/cloud_file.h"

namespace hope {
namespace tools {

namespace {

// The same points, uniformly grey, keeping the organized shape: inputs without colour.
pcl::PointCloud<pcl::PointXYZRGB> withGreyColor(const pcl::PointCloud<pcl::PointXYZ>& xyz) {
  pcl::PointCloud<pcl::PointXYZRGB> out;
  out.resize(xyz.size());
  for (std::size_t i = 0; i < xyz.size(); ++i) {
    pcl::PointXYZRGB& p = out[i];
    p.x = xyz[i].x;
    p.y = xyz[i].y;
    p.z = xyz[i].z;
    p.r = p.g = p.b = 160;
  }
  out.width = xyz.width;
  out.height = xyz.height;
  out.is_dense = xyz.is_dense;
  return out;
}

}  // namespace

InputCloud loadCloud(const std::string& path, std::uint64_t max_points) {
  const CloudFileLayout layout = checkCloudFile(path, max_points);
  InputCloud input;
  input.cloud = readCloudFile(path, layout, input.has_color);
  return input;
}

InputCloud loadDepth(const std::string& depth_path, const std::string& rgb_path,
                     const PinholeIntrinsics& intrinsics, double depth_scale) {
  requireRegularFile(depth_path);
  const cv::Mat depth = cv::imread(depth_path, cv::IMREAD_ANYDEPTH | cv::IMREAD_GRAYSCALE);
  if (depth.empty()) throw std::runtime_error("'" + depth_path + "' is not a readable image");
  InputCloud input;
  if (!rgb_path.empty()) {
    requireRegularFile(rgb_path);
    const cv::Mat rgb = cv::imread(rgb_path, cv::IMREAD_COLOR);
    if (rgb.empty()) throw std::runtime_error("'" + rgb_path + "' is not a readable image");
    input.cloud = depthToColoredCloud(depth, rgb, intrinsics, depth_scale);
    input.has_color = true;
  } else {
    input.cloud = withGreyColor(depthToCloud(depth, intrinsics, depth_scale));
  }
  return input;
}

void writeLabels(const OutputFile& file, const pcl::PointCloud<pcl::PointXYZRGB>& cloud,
                 const std::vector<std::uint32_t>& labels) {
  pcl::PointCloud<pcl::PointXYZL> out;
  out.resize(cloud.size());
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    out[i].x = cloud[i].x;
    out[i].y = cloud[i].y;
    out[i].z = cloud[i].z;
    out[i].label = labels[i];
  }
  out.width = cloud.width;
  out.height = cloud.height;
  out.is_dense = cloud.is_dense;
  errno = 0;
  if (pcl::io::savePCDFileBinary(file.writePath(), out) < 0) throwCannotWrite(file.path());
}

void writeImage(const OutputFile& file, const cv::Mat& image) {
  errno = 0;
  bool written = false;
  try {
    written = cv::imwrite(file.writePath(), image);
  } catch (const cv::Exception&) {  // e.g. an extension OpenCV has no encoder for
  }
  if (!written) throwCannotWrite(file.path());
}

std::vector<double> parseNumbers(const std::string& text, std::size_t count, const char* what) {
  std::istringstream in(text);
  std::vector<double> values;
  std::string token;
  while (in >> token) {
    try {
      std::size_t used = 0;
      values.push_back(std::stod(token, &used));
      if (used != token.size()) throw std::invalid_argument(token);
    } catch (const std::exception&) {
      throw std::invalid_argument(std::string(what) + ": '" + token + "' is not a number");
    }
  }
  if (values.size() != count) {
    std::ostringstream msg;
    msg << what << ": expected " << count << " numbers, got " << values.size() << " in '" << text
        << "'";
    throw std::invalid_argument(msg.str());
  }
  return values;
}

}  // namespace tools
}  // namespace hope
