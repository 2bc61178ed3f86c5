// Loading inputs and writing outputs for the command-line tools.
#pragma once

#include <string>
#include <vector>

#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include "hope/depth_image.h"

namespace hope {
namespace tools {

struct InputCloud {
  pcl::PointCloud<pcl::PointXYZRGB> cloud;  // grey where the input has no colour
  bool has_color = false;
};

// Reads a .pcd or .ply file. Throws std::runtime_error with a readable message when the file
// is missing, unreadable, or lacks float x, y, z fields.
InputCloud loadCloud(const std::string& path);

// Reads a depth PNG (16-bit raw units or 32-bit float metres) and, optionally, a registered
// colour image, and back-projects them into an organized cloud in the camera optical frame.
InputCloud loadDepth(const std::string& depth_path, const std::string& rgb_path,
                     const PinholeIntrinsics& intrinsics, double depth_scale);

// Writes x, y, z (as read) and one `label` per input point, same count, order and
// width × height as the input.
void writeLabels(const std::string& path, const pcl::PointCloud<pcl::PointXYZRGB>& cloud,
                 const std::vector<std::uint32_t>& labels);

// Parses exactly `count` whitespace-separated numbers, e.g. "517.3 516.5 318.6 255.3".
// Throws std::invalid_argument naming `what` otherwise.
std::vector<double> parseNumbers(const std::string& text, std::size_t count, const char* what);

}  // namespace tools
}  // namespace hope
