#include "hope/tools/io.h"

#include <cerrno>
#include <cstring>

#include <fstream>
#include <sstream>
#include <stdexcept>

#include <pcl/PCLPointCloud2.h>
#include <pcl/io/pcd_io.h>
#include <pcl/io/ply_io.h>
#include <opencv2/imgcodecs.hpp>

#include "hope/tools/cloud_file_check.h"

namespace hope {
namespace tools {

namespace {

const pcl::PCLPointField* findField(const pcl::PCLPointCloud2& blob, const std::string& name) {
  for (const auto& field : blob.fields) {
    if (field.name == name) return &field;
  }
  return nullptr;
}

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

// Reads one float32 or float64 value (the only types loadCloud accepts for x, y, z).
float readCoordinate(const std::uint8_t* point, const pcl::PCLPointField& field) {
  if (field.datatype == pcl::PCLPointField::FLOAT64) {
    double value;
    std::memcpy(&value, point + field.offset, sizeof(value));
    return static_cast<float>(value);
  }
  float value;
  std::memcpy(&value, point + field.offset, sizeof(value));
  return value;
}

std::size_t byteSize(std::uint8_t datatype) {
  switch (datatype) {
    case pcl::PCLPointField::INT8:
    case pcl::PCLPointField::UINT8:
      return 1;
    case pcl::PCLPointField::INT16:
    case pcl::PCLPointField::UINT16:
      return 2;
    case pcl::PCLPointField::FLOAT64:
      return 8;
    default:
      return 4;
  }
}

// The blob's points as PointXYZRGB, read field by field with every offset checked against the
// point size (PCL's own conversion maps a float64 x to nothing and leaves zeros).
InputCloud fromBlob(const std::string& path, const pcl::PCLPointCloud2& blob) {
  const std::uint64_t count = std::uint64_t(blob.width) * blob.height;
  const std::uint64_t step = blob.point_step;
  if (count > 0 && (step == 0 || blob.data.size() / step < count)) {
    throw std::runtime_error("'" + path + "' holds " + std::to_string(blob.data.size()) +
                             " bytes of points, fewer than its " + std::to_string(count) +
                             " points need");
  }
  const pcl::PCLPointField* axes[3];
  const char* names[3] = {"x", "y", "z"};
  for (int k = 0; k < 3; ++k) {
    axes[k] = findField(blob, names[k]);
    if (!axes[k]) {
      throw std::runtime_error("'" + path + "' has no '" + names[k] +
                               "' field; hope needs x, y, z");
    }
    if (axes[k]->datatype != pcl::PCLPointField::FLOAT32 &&
        axes[k]->datatype != pcl::PCLPointField::FLOAT64) {
      throw std::runtime_error("'" + path + "' field '" + names[k] +
                               "' is not floating point; hope needs x, y, z in metres");
    }
  }
  const pcl::PCLPointField* color = findField(blob, "rgb");
  if (!color) color = findField(blob, "rgba");
  if (color && byteSize(color->datatype) != 4) color = nullptr;  // not a packed colour
  for (const pcl::PCLPointField* f : {axes[0], axes[1], axes[2], color}) {
    if (f && std::uint64_t(f->offset) + byteSize(f->datatype) > step) {
      throw std::runtime_error("'" + path + "' field '" + f->name + "' lies outside its point");
    }
  }
  InputCloud input;
  input.has_color = color != nullptr;
  input.cloud.resize(static_cast<std::size_t>(count));
  input.cloud.width = blob.width;
  input.cloud.height = blob.height;
  input.cloud.is_dense = blob.is_dense;
  for (std::size_t i = 0; i < count; ++i) {
    const std::uint8_t* point = blob.data.data() + i * step;
    pcl::PointXYZRGB& p = input.cloud[i];
    p.x = readCoordinate(point, *axes[0]);
    p.y = readCoordinate(point, *axes[1]);
    p.z = readCoordinate(point, *axes[2]);
    if (color) {
      std::uint32_t rgb;
      std::memcpy(&rgb, point + color->offset, sizeof(rgb));
      p.r = static_cast<std::uint8_t>(rgb >> 16);
      p.g = static_cast<std::uint8_t>(rgb >> 8);
      p.b = static_cast<std::uint8_t>(rgb);
    } else {
      p.r = p.g = p.b = 160;
    }
  }
  return input;
}

}  // namespace

InputCloud loadCloud(const std::string& path, std::uint64_t max_points) {
  // PCL trusts the header it reads; it is checked first (sizes, file type, truncation).
  const CloudFormat format = checkCloudFile(path, max_points);
  pcl::PCLPointCloud2 blob;
  const int status = format == CloudFormat::kPcd ? pcl::io::loadPCDFile(path, blob)
                                                 : pcl::io::loadPLYFile(path, blob);
  if (status < 0) throw std::runtime_error("'" + path + "' could not be parsed as a point cloud");
  return fromBlob(path, blob);
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
