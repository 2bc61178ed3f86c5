// Reading .pcd and .ply files without trusting them. PCL's readers trust their headers: a
// WIDTH × HEIGHT that overflows writes out of bounds, a compressed PCD that claims gigabytes
// allocates them, a directory or a FIFO makes them loop or block forever, and a fuzzer finds
// inputs that crash them within seconds. hope reads both formats itself: every size comes from
// a header checked in 64-bit or overflow-checked arithmetic against the file's real size
// before anything is allocated.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "hope/points_view.h"

namespace hope {
namespace tools {

// Default cap on the points a file may claim (a 6.5 M-point merged room is large; 100 M
// points with colour are 1.6 GB in memory). `hope_extract --max-points` raises it.
constexpr std::uint64_t kDefaultMaxPoints = 100000000;

// A cloud as the tools hold it: 12 bytes a point, 16 with colour. A 6 M-point scan takes
// 72 MB, where a pcl::PointCloud<pcl::PointXYZRGB> would take 192 MB.
struct InputCloud {
  std::vector<Eigen::Vector3f> points;  // x, y, z as read; NaN where the sensor saw nothing
  std::vector<std::uint32_t> rgb;       // 0xRRGGBB per point; empty when the input has none
  std::uint32_t width = 0, height = 1;  // organized: image columns and rows
  bool hasColor() const { return !rgb.empty(); }
  std::size_t size() const { return points.size(); }
  // The points as Extractor::extract reads them (in place: a z-up cloud is not copied).
  PointsView view() const;
};

// One field of a point (PCD) or one scalar property of a vertex (PLY).
struct FileField {
  std::string name;
  char type = 'F';           // F float, I signed, U unsigned
  std::uint32_t size = 4;    // bytes of one value
  std::uint32_t count = 1;   // values (PCD COUNT)
  std::uint64_t offset = 0;  // bytes from the start of a point (binary layouts)
};

// What a checked header says about the points that follow it.
struct CloudFileLayout {
  enum class Format { kPcd, kPly } format = Format::kPcd;
  enum class Encoding { kAscii, kBinary, kBinaryBigEndian, kBinaryCompressed };
  Encoding encoding = Encoding::kAscii;
  std::vector<FileField> fields;
  std::uint32_t width = 0, height = 1;  // PLY: width = vertices, height = 1
  std::uint64_t point_bytes = 0;        // one point, binary layouts
  std::uint64_t data_offset = 0;        // first byte after the header
  std::uint64_t file_size = 0;
  // PLY: the elements before the vertices (skipped): count and scalar sizes or list types.
  struct SkippedElement {
    std::uint64_t count = 0;
    // Per property: {size of a scalar, 0} or {size of the list's count, size of an item}.
    std::vector<std::pair<std::uint32_t, std::uint32_t>> properties;
  };
  std::vector<SkippedElement> skipped;

  std::uint64_t points() const { return std::uint64_t(width) * height; }
};

// Throws std::runtime_error naming the file and what is wrong when `path` is missing,
// unreadable, not a regular file (a directory, device, FIFO or a link to one), empty, or when
// its header is malformed, claims more than `max_points` points, or claims more data than the
// file holds. The extension (.pcd or .ply) chooses the format.
CloudFileLayout checkCloudFile(const std::string& path,
                               std::uint64_t max_points = kDefaultMaxPoints);

// Reads the points of a checked file: x, y, z (float32 or float64) and, when the file has
// them, colours (PCD rgb/rgba, PLY red/green/blue). The cloud keeps the file's width × height.
// Binary data is read a block at a time, so reading takes little more memory than the cloud.
// Throws std::runtime_error for data that does not match the header.
InputCloud readCloudFile(const std::string& path, const CloudFileLayout& layout);

// The same checks for any input file that is read whole (images, text lists): exists,
// readable, a regular file, not empty. Returns its size in bytes.
std::uint64_t requireRegularFile(const std::string& path);

}  // namespace tools
}  // namespace hope
