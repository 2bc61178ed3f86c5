// Checks a .pcd or .ply file before PCL reads it. PCL's readers trust their headers: a
// WIDTH × HEIGHT that overflows writes out of bounds, a compressed PCD that claims gigabytes
// allocates them, a directory or a FIFO makes them loop or block forever. Everything a size
// comes from is read and checked here first, in 64-bit or overflow-checked arithmetic.
#pragma once

#include <cstdint>
#include <string>

namespace hope {
namespace tools {

// Default cap on the points a file may claim (a 6.5 M-point merged room is large; 100 M
// points of PointXYZRGB are 3.2 GB in memory). `hope_extract --max-points` raises it.
constexpr std::uint64_t kDefaultMaxPoints = 100000000;

enum class CloudFormat { kPcd, kPly };

// Throws std::runtime_error naming the file and what is wrong when `path` is missing,
// unreadable, not a regular file (a directory, device, FIFO or a link to one), empty, or
// when its header is malformed, claims more than `max_points` points, or claims more data
// than the file holds. Returns the format chosen by the extension (.pcd or .ply).
CloudFormat checkCloudFile(const std::string& path, std::uint64_t max_points = kDefaultMaxPoints);

// The same for any input file that is read whole (images, text lists): exists, readable,
// a regular file, not empty. Returns its size in bytes.
std::uint64_t requireRegularFile(const std::string& path);

}  // namespace tools
}  // namespace hope
