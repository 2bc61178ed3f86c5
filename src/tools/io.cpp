#include "hope/tools/io.h"

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <fstream>
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

// A binary PCD header for `points` points of the fields x y z label.
std::string labelsPcdHeader(const InputCloud& cloud) {
  const PointsView shape = cloud.view();
  std::ostringstream header;
  header << "# .PCD v0.7 - Point Cloud Data file format\nVERSION 0.7\nFIELDS x y z label\n"
         << "SIZE 4 4 4 4\nTYPE F F F U\nCOUNT 1 1 1 1\nWIDTH " << shape.width << "\nHEIGHT "
         << shape.height << "\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS " << cloud.size()
         << "\nDATA binary\n";
  return header.str();
}

}  // namespace

InputCloud loadCloud(const std::string& path, std::uint64_t max_points) {
  const CloudFileLayout layout = checkCloudFile(path, max_points);
  return readCloudFile(path, layout);
}

InputCloud loadDepth(const std::string& depth_path, const std::string& rgb_path,
                     const PinholeIntrinsics& intrinsics, double depth_scale) {
  requireRegularFile(depth_path);
  cv::Mat depth;
  if (!readImageFile(depth_path, cv::IMREAD_ANYDEPTH | cv::IMREAD_GRAYSCALE, depth))
    throw std::runtime_error("'" + depth_path + "' is not a readable image");
  if (rgb_path.empty()) return fromImageCloud(depthToCloud(depth, intrinsics, depth_scale));
  requireRegularFile(rgb_path);
  cv::Mat rgb;
  if (!readImageFile(rgb_path, cv::IMREAD_COLOR, rgb))
    throw std::runtime_error("'" + rgb_path + "' is not a readable image");
  const pcl::PointCloud<pcl::PointXYZRGB> colored =
      depthToColoredCloud(depth, rgb, intrinsics, depth_scale);
  InputCloud input = fromImageCloud(colored);
  input.rgb.reserve(colored.size());
  for (const pcl::PointXYZRGB& p : colored) {
    input.rgb.push_back(packRgb({p.r, p.g, p.b}));
  }
  return input;
}

// hope's own binary PCD writer (x y z label, 16 bytes a point, written a block at a time): the
// tools then need no PCL I/O library, whose load alone costs ~20 MB of memory.
void writeLabels(const OutputFile& file, const InputCloud& cloud,
                 const std::vector<std::uint32_t>& labels) {
  if (labels.size() != cloud.size()) {
    throw std::logic_error("writeLabels: one label per point is needed");
  }
  errno = 0;
  std::ofstream out(file.writePath(), std::ios::binary | std::ios::trunc);
  if (!out) throwCannotWrite(file.path());
  out << labelsPcdHeader(cloud);
  constexpr std::size_t kBlockPoints = 1 << 16;
  std::vector<std::uint8_t> block;
  for (std::size_t first = 0; first < cloud.size() && out; first += kBlockPoints) {
    const std::size_t count = std::min(kBlockPoints, cloud.size() - first);
    block.resize(count * 16);
    for (std::size_t k = 0; k < count; ++k) {
      std::memcpy(&block[16 * k], cloud.points[first + k].data(), 12);
      std::memcpy(&block[16 * k + 12], &labels[first + k], 4);
    }
    out.write(reinterpret_cast<const char*>(block.data()),
              static_cast<std::streamsize>(block.size()));
  }
  out.close();
  if (out.fail()) throwCannotWrite(file.path());
}

void writeImage(const OutputFile& file, const cv::Mat& image) {
  errno = 0;
  if (!writeImageFile(file.writePath(), image)) throwCannotWrite(file.path());
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
