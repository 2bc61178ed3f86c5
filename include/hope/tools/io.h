// Loading inputs and writing outputs for the command-line tools.
#pragma once

#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "hope/depth_image.h"
#include "hope/tools/cloud_file.h"
#include "hope/tools/output_file.h"

namespace hope {
namespace tools {

// Reads a .pcd or .ply file; x, y, z may be float32 or float64. Throws std::runtime_error with
// a message naming the file and the problem when it is missing, unreadable, not a regular
// file, malformed, truncated, claims more than `max_points` points, or lacks floating-point
// x, y, z fields (see cloud_file.h: hope reads both formats itself, not with PCL's readers).
InputCloud loadCloud(const std::string& path, std::uint64_t max_points = kDefaultMaxPoints);

// Reads a depth PNG (16-bit raw units or 32-bit float metres) and, optionally, a registered
// colour image, and back-projects them into an organized cloud in the camera optical frame.
InputCloud loadDepth(const std::string& depth_path, const std::string& rgb_path,
                     const PinholeIntrinsics& intrinsics, double depth_scale);

// Writes x, y, z (as read) and one `label` per input point, same count, order and
// width × height as the input, as binary PCD. Throws std::runtime_error when it cannot.
void writeLabels(const OutputFile& file, const InputCloud& cloud,
                 const std::vector<std::uint32_t>& labels);

// Writes an image in the format of the file's extension (.png, .jpg, …); throws
// std::runtime_error when it cannot.
void writeImage(const OutputFile& file, const cv::Mat& image);

// Parses exactly `count` whitespace-separated numbers, e.g. "517.3 516.5 318.6 255.3".
// Throws std::invalid_argument naming `what` otherwise.
std::vector<double> parseNumbers(const std::string& text, std::size_t count, const char* what);

}  // namespace tools
}  // namespace hope
