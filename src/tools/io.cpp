#include "hope/tools/io.h"

#include <fstream>
#include <sstream>
#include <stdexcept>

#include <pcl/PCLPointCloud2.h>
#include <pcl/conversions.h>
#include <pcl/io/pcd_io.h>
#include <pcl/io/ply_io.h>
#include <opencv2/imgcodecs.hpp>

namespace hope {
namespace tools {

namespace {

bool endsWith(const std::string& s, const std::string& suffix) {
  if (s.size() < suffix.size()) return false;
  std::string tail = s.substr(s.size() - suffix.size());
  for (char& c : tail) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return tail == suffix;
}

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

void requireReadable(const std::string& path) {
  std::ifstream probe(path);
  if (!probe) throw std::runtime_error("cannot open '" + path + "' (missing or unreadable)");
}

}  // namespace

InputCloud loadCloud(const std::string& path) {
  requireReadable(path);
  pcl::PCLPointCloud2 blob;
  int status = -1;
  if (endsWith(path, ".pcd")) {
    status = pcl::io::loadPCDFile(path, blob);
  } else if (endsWith(path, ".ply")) {
    status = pcl::io::loadPLYFile(path, blob);
  } else {
    throw std::runtime_error("'" + path + "' is neither .pcd nor .ply");
  }
  if (status < 0) throw std::runtime_error("'" + path + "' could not be parsed as a point cloud");
  for (const char* axis : {"x", "y", "z"}) {
    const pcl::PCLPointField* field = findField(blob, axis);
    if (!field) {
      throw std::runtime_error("'" + path + "' has no '" + axis + "' field; hope needs x, y, z");
    }
    if (field->datatype != pcl::PCLPointField::FLOAT32 &&
        field->datatype != pcl::PCLPointField::FLOAT64) {
      throw std::runtime_error("'" + path + "' field '" + axis +
                               "' is not floating point; hope needs x, y, z in metres");
    }
  }
  InputCloud input;
  input.has_color = findField(blob, "rgb") || findField(blob, "rgba");
  if (input.has_color) {
    pcl::fromPCLPointCloud2(blob, input.cloud);
  } else {
    pcl::PointCloud<pcl::PointXYZ> xyz;
    pcl::fromPCLPointCloud2(blob, xyz);
    input.cloud = withGreyColor(xyz);
  }
  return input;
}

InputCloud loadDepth(const std::string& depth_path, const std::string& rgb_path,
                     const PinholeIntrinsics& intrinsics, double depth_scale) {
  requireReadable(depth_path);
  const cv::Mat depth = cv::imread(depth_path, cv::IMREAD_ANYDEPTH | cv::IMREAD_GRAYSCALE);
  if (depth.empty()) throw std::runtime_error("'" + depth_path + "' is not a readable image");
  InputCloud input;
  if (!rgb_path.empty()) {
    requireReadable(rgb_path);
    const cv::Mat rgb = cv::imread(rgb_path, cv::IMREAD_COLOR);
    if (rgb.empty()) throw std::runtime_error("'" + rgb_path + "' is not a readable image");
    input.cloud = depthToColoredCloud(depth, rgb, intrinsics, depth_scale);
    input.has_color = true;
  } else {
    input.cloud = withGreyColor(depthToCloud(depth, intrinsics, depth_scale));
  }
  return input;
}

void writeLabels(const std::string& path, const pcl::PointCloud<pcl::PointXYZRGB>& cloud,
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
  if (pcl::io::savePCDFileBinary(path, out) < 0) {
    throw std::runtime_error("cannot write '" + path + "'");
  }
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
