// Loading inputs and writing outputs for the command-line tools.
#pragma once

#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "hope/depth_image.h"
#include "hope/frame_pipeline.h"
#include "hope/tools/cloud_file.h"
#include "hope/tools/output_file.h"

namespace hope {
namespace tools {

// Reads a .pcd or .ply file; x, y, z may be float32 or float64. Throws std::runtime_error with
// a message naming the file and the problem when it is missing, unreadable, not a regular
// file, malformed, truncated, claims more than `max_points` points, or lacks floating-point
// x, y, z fields (see cloud_file.h: hope reads both formats itself, not with PCL's readers).
InputCloud loadCloud(const std::string& path, std::uint64_t max_points = kDefaultMaxPoints);

// Reads a depth image (a 16-bit grey PNG of raw units, or one channel of 32-bit float metres)
// and, optionally, a registered colour image, and back-projects them into an organized cloud
// in the camera optical frame. Throws std::runtime_error naming the file when it is not a
// regular file, not an image, has more than `max_points` pixels (checked before decoding for
// a PNG), is a colour or 8-bit image, or does not fit the intrinsics.
InputCloud loadDepth(const std::string& depth_path, const std::string& rgb_path,
                     const PinholeIntrinsics& intrinsics, double depth_scale,
                     std::uint64_t max_points = kDefaultMaxPoints);

// Writes x, y, z (as read), one `label` (uint32) and one `object` (int32) per input point, same
// count, order and width × height as the input, as binary PCD. Throws std::runtime_error when
// it cannot.
void writeLabels(const OutputFile& file, const InputCloud& cloud,
                 const std::vector<std::uint32_t>& labels,
                 const std::vector<std::int32_t>& objects);

// Writes the points of `cloud` at `indices` (x, y, z as read, and rgb when the cloud has it), in
// that order, as an unorganized binary PCD (hope_extract --obstacles). Throws
// std::runtime_error when it cannot.
void writePoints(const OutputFile& file, const InputCloud& cloud,
                 const std::vector<std::uint32_t>& indices);

// Writes the floor grid as ROS map_server loads a map: `image` a PGM (row 0 the grid's last row,
// the largest y; 0 occupied, 254 free, 205 unseen) and `yaml` its description (image, named
// relative to the YAML; resolution; origin; negate 0; occupied_thresh 0.65; free_thresh
// 0.196), the floor's height in a comment. Throws std::runtime_error when it cannot.
void writeFloorGrid(const OutputFile& image, const OutputFile& yaml, const FloorGrid& grid);

// Writes an image in the format of the file's extension (.png, .jpg, …); throws
// std::runtime_error when it cannot.
void writeImage(const OutputFile& file, const cv::Mat& image);

// `text` as it can be shown in a message: bytes that are not printable ASCII written as \xNN,
// cut after `max_chars` with the full length said, so that a binary file or a 64 MB line
// never floods the terminal.
std::string printableExcerpt(const std::string& text, std::size_t max_chars = 80);

// Parses exactly `count` whitespace-separated numbers, e.g. "517.3 516.5 318.6 255.3".
// Throws std::invalid_argument naming `what` otherwise.
std::vector<double> parseNumbers(const std::string& text, std::size_t count, const char* what);

}  // namespace tools
}  // namespace hope
