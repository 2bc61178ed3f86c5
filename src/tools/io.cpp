#include "hope/tools/io.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iomanip>
#include <sstream>
#include <stdexcept>

#include <opencv2/imgcodecs.hpp>  // the IMREAD_ flags only: the codecs are in the module

#include "hope/plane_colors.h"
#include "hope/tools/cloud_file.h"
#include "hope/tools/image_codecs.h"

namespace hope {
namespace tools {

namespace {

// An image's points (depth_image.h) as the tools hold a cloud, organized shape kept.
template <class PointT>
InputCloud fromImageCloud(const pcl::PointCloud<PointT>& image_cloud) {
  InputCloud input;
  input.width = image_cloud.width;
  input.height = image_cloud.height;
  input.points.reserve(image_cloud.size());
  for (const PointT& p : image_cloud) input.points.emplace_back(p.x, p.y, p.z);
  return input;
}

// A binary PCD header for `points` points of the fields x y z label object.
std::string labelsPcdHeader(const InputCloud& cloud) {
  const PointsView shape = cloud.view();
  std::ostringstream header;
  header << "# .PCD v0.7 - Point Cloud Data file format\nVERSION 0.7\nFIELDS x y z label object\n"
         << "SIZE 4 4 4 4 4\nTYPE F F F U I\nCOUNT 1 1 1 1 1\nWIDTH " << shape.width << "\nHEIGHT "
         << shape.height << "\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS " << cloud.size()
         << "\nDATA binary\n";
  return header.str();
}

// A PNG's size and kind from its IHDR chunk, checked before any pixel is decoded: a 1 MB PNG
// of 20000 x 20000 zeros would otherwise take 800 MB to decode and 4.8 GB as points. Other
// formats are left to the decoder.
void checkPngHeader(const std::string& path, std::uint64_t max_points) {
  std::ifstream in(path, std::ios::binary);
  unsigned char header[26] = {};
  if (!in.read(reinterpret_cast<char*>(header), sizeof(header))) return;
  static const unsigned char kSignature[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  if (std::memcmp(header, kSignature, 8) != 0 || std::memcmp(header + 12, "IHDR", 4) != 0) return;
  auto bigEndian = [&](int at) {
    return (std::uint32_t(header[at]) << 24) | (std::uint32_t(header[at + 1]) << 16) |
           (std::uint32_t(header[at + 2]) << 8) | std::uint32_t(header[at + 3]);
  };
  const std::uint64_t width = bigEndian(16), height = bigEndian(20);
  if (width * height > max_points) {
    throw std::runtime_error("'" + path + "' is a " + std::to_string(width) + " x " +
                             std::to_string(height) + " image, more pixels than --max-points " +
                             std::to_string(max_points));
  }
  const int bit_depth = header[24], colour_type = header[25];
  if (colour_type != 0) {  // 0: grey; 2 RGB, 3 palette, 4 grey + alpha, 6 RGBA
    throw std::runtime_error("'" + path + "' is a colour PNG (" + std::to_string(bit_depth) +
                             "-bit, colour type " + std::to_string(colour_type) +
                             "); a depth image has one grey channel");
  }
  if (bit_depth != 16) {
    throw std::runtime_error("'" + path + "' is a grey PNG of " + std::to_string(bit_depth) +
                             " bits a pixel; depth PNGs have 16 (raw units, see --depth-scale)");
  }
}

}  // namespace

InputCloud loadCloud(const std::string& path, std::uint64_t max_points) {
  const CloudFileLayout layout = checkCloudFile(path, max_points);
  return readCloudFile(path, layout);
}

InputCloud loadDepth(const std::string& depth_path, const std::string& rgb_path,
                     const PinholeIntrinsics& intrinsics, double depth_scale,
                     std::uint64_t max_points) {
  requireRegularFile(depth_path);
  checkPngHeader(depth_path, max_points);
  // Every other format: OpenCV refuses images of more pixels than this before decoding. It
  // reads the variable once, at its first image; a user's own setting is kept.
  ::setenv("OPENCV_IO_MAX_IMAGE_PIXELS", std::to_string(max_points).c_str(), 0);
  cv::Mat depth;
  // Unchanged, not converted: a colour image or a 16-bit RGB PNG must be refused as depth,
  // not averaged into one.
  if (!readImageFile(depth_path, cv::IMREAD_UNCHANGED, depth))
    throw std::runtime_error("'" + depth_path + "' is not a readable image");
  if (static_cast<std::uint64_t>(depth.total()) > max_points) {
    throw std::runtime_error("'" + depth_path + "' has " + std::to_string(depth.total()) +
                             " pixels, more than --max-points " + std::to_string(max_points));
  }
  try {
    if (rgb_path.empty()) return fromImageCloud(depthToCloud(depth, intrinsics, depth_scale));
  } catch (const std::invalid_argument& e) {  // the image's type or size: name the file
    throw std::runtime_error("'" + depth_path + "': " + e.what());
  }
  requireRegularFile(rgb_path);
  cv::Mat rgb;
  if (!readImageFile(rgb_path, cv::IMREAD_COLOR, rgb))
    throw std::runtime_error("'" + rgb_path + "' is not a readable image");
  pcl::PointCloud<pcl::PointXYZRGB> colored;
  try {
    colored = depthToColoredCloud(depth, rgb, intrinsics, depth_scale);
  } catch (const std::invalid_argument& e) {
    throw std::runtime_error("'" + depth_path + "' with '" + rgb_path + "': " + e.what());
  }
  InputCloud input = fromImageCloud(colored);
  input.rgb.reserve(colored.size());
  for (const pcl::PointXYZRGB& p : colored) {
    input.rgb.push_back(packRgb({p.r, p.g, p.b}));
  }
  return input;
}

// hope's own binary PCD writer (x y z label object, 20 bytes a point, a block at a time): the
// tools then need no PCL I/O library, whose load alone costs ~20 MB of memory.
void writeLabels(const OutputFile& file, const InputCloud& cloud,
                 const std::vector<std::uint32_t>& labels,
                 const std::vector<std::int32_t>& objects) {
  if (labels.size() != cloud.size() || objects.size() != cloud.size()) {
    throw std::logic_error("writeLabels: one label and one object per point are needed");
  }
  errno = 0;
  std::ofstream out(file.writePath(), std::ios::binary | std::ios::trunc);
  if (!out) throwCannotWrite(file.path());
  out << labelsPcdHeader(cloud);
  constexpr std::size_t kBlockPoints = 1 << 16;
  std::vector<std::uint8_t> block;
  for (std::size_t first = 0; first < cloud.size() && out; first += kBlockPoints) {
    const std::size_t count = std::min(kBlockPoints, cloud.size() - first);
    block.resize(count * 20);
    for (std::size_t k = 0; k < count; ++k) {
      std::memcpy(&block[20 * k], cloud.points[first + k].data(), 12);
      std::memcpy(&block[20 * k + 12], &labels[first + k], 4);
      std::memcpy(&block[20 * k + 16], &objects[first + k], 4);
    }
    out.write(reinterpret_cast<const char*>(block.data()),
              static_cast<std::streamsize>(block.size()));
  }
  out.close();
  if (out.fail()) throwCannotWrite(file.path());
}

void writePoints(const OutputFile& file, const InputCloud& cloud,
                 const std::vector<std::uint32_t>& indices) {
  const bool colour = cloud.hasColor();
  const std::size_t step = colour ? 16 : 12;
  errno = 0;
  std::ofstream out(file.writePath(), std::ios::binary | std::ios::trunc);
  if (!out) throwCannotWrite(file.path());
  out << "# .PCD v0.7 - Point Cloud Data file format (hope_extract --obstacles)\nVERSION 0.7\n"
      << (colour ? "FIELDS x y z rgb\nSIZE 4 4 4 4\nTYPE F F F U\nCOUNT 1 1 1 1\n"
                 : "FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\n")
      << "WIDTH " << indices.size() << "\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS "
      << indices.size() << "\nDATA binary\n";
  std::vector<std::uint8_t> block(indices.size() * step);
  for (std::size_t k = 0; k < indices.size(); ++k) {
    std::memcpy(&block[step * k], cloud.points.at(indices[k]).data(), 12);
    if (colour) std::memcpy(&block[step * k + 12], &cloud.rgb[indices[k]], 4);
  }
  out.write(reinterpret_cast<const char*>(block.data()),
            static_cast<std::streamsize>(block.size()));
  out.close();
  if (out.fail()) throwCannotWrite(file.path());
}

void writeFloorGrid(const OutputFile& image, const OutputFile& yaml, const FloorGrid& grid) {
  // map_server's trinary reading with negate 0: occupancy = (255 − p) / 255, occupied above
  // 0.65, free below 0.196.
  cv::Mat pixels(grid.height, grid.width, CV_8UC1);
  for (int y = 0; y < grid.height; ++y) {
    for (int x = 0; x < grid.width; ++x) {
      const std::int8_t cell = grid.cells[static_cast<std::size_t>(y) * grid.width + x];
      pixels.at<std::uint8_t>(grid.height - 1 - y, x) = cell == FloorGrid::kOccupied ? 0
                                                        : cell == FloorGrid::kFree   ? 254
                                                                                     : 205;
    }
  }
  writeImage(image, pixels);
  const std::string name = image.path().substr(image.path().find_last_of('/') + 1);
  writeText(yaml, [&](std::ostream& out) {
    out << std::setprecision(9)
        << "# hope_extract --floor-grid: the floor at z = " << grid.floor_height
        << " m in the reference frame\n"
        << "image: " << name << "\nresolution: " << grid.resolution << "\norigin: ["
        << grid.origin.x() << ", " << grid.origin.y()
        << ", 0.0]\nnegate: 0\noccupied_thresh: 0.65\nfree_thresh: 0.196\n";
  });
}

void writeImage(const OutputFile& file, const cv::Mat& image) {
  errno = 0;
  if (!writeImageFile(file.writePath(), image)) throwCannotWrite(file.path());
}

std::string printableExcerpt(const std::string& text, std::size_t max_chars) {
  std::string out;
  std::size_t shown = 0;
  for (; shown < text.size() && out.size() < max_chars; ++shown) {
    const unsigned char c = static_cast<unsigned char>(text[shown]);
    if (c >= 0x20 && c < 0x7f) {
      out += static_cast<char>(c);
    } else {
      char hex[8];
      std::snprintf(hex, sizeof(hex), "\\x%02x", c);
      out += hex;
    }
  }
  if (shown < text.size()) out += "... (" + std::to_string(text.size()) + " bytes)";
  return out;
}

std::vector<double> parseNumbers(const std::string& text, std::size_t count, const char* what) {
  std::istringstream in(text);
  std::vector<double> values;
  std::string token;
  while (in >> token) {
    // strtod, not std::stod: stod refuses subnormals such as 1e-310 as "out of range".
    char* end = nullptr;
    const double value = std::strtod(token.c_str(), &end);
    if (end != token.c_str() + token.size()) {
      throw std::invalid_argument(std::string(what) + ": '" + printableExcerpt(token) +
                                  "' is not a number");
    }
    if (!std::isfinite(value)) {
      throw std::invalid_argument(std::string(what) + ": '" + printableExcerpt(token) +
                                  "' is not a finite number");
    }
    values.push_back(value);
  }
  if (values.size() != count) {
    std::ostringstream msg;
    msg << what << ": expected " << count << " numbers, got " << values.size() << " in '"
        << printableExcerpt(text) << "'";
    throw std::invalid_argument(msg.str());
  }
  return values;
}

}  // namespace tools
}  // namespace hope
