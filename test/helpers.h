// Scenes with known answers and small utilities shared by the tests.
#pragma once

#include <cmath>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "hope/extractor.h"
#include "hope/synthetic/scene.h"

namespace hope {
namespace test {

using synthetic::LabeledCloud;
using V3 = Eigen::Vector3d;

// A horizontal rectangle [x0, x1] × [y0, y1] at height z, sampled every `spacing` metres.
inline void addSheet(LabeledCloud& cloud, double x0, double y0, double x1, double y1, double z,
                     double spacing, int label, double noise = 0.0, unsigned seed = 1) {
  synthetic::Rectangle rect(V3(0.5 * (x0 + x1), 0.5 * (y0 + y1), z), V3::UnitX(), V3::UnitY(),
                            0.5 * (x1 - x0), 0.5 * (y1 - y0), label);
  synthetic::sampleRectangle(rect, spacing, label, cloud, noise, seed);
}

inline Result extractZUp(const pcl::PointCloud<pcl::PointXYZ>& cloud,
                         const Params& params = Params()) {
  Extractor extractor(params);
  return extractor.extract(cloud, Orientation::identity());
}

// Index of the plane whose height is nearest to z, or -1 when none is within tolerance.
inline int planeNear(const Result& result, double z, double tolerance) {
  int best = -1;
  for (std::size_t k = 0; k < result.planes.size(); ++k) {
    const double d = std::fabs(result.planes[k].height - z);
    if (d <= tolerance && (best < 0 || d < std::fabs(result.planes[best].height - z))) {
      best = static_cast<int>(k);
    }
  }
  return best;
}

inline std::string describe(const Result& result) {
  std::string s = std::to_string(result.planes.size()) + " plane(s):";
  for (const auto& p : result.planes) {
    s += " [id " + std::to_string(p.id) + " h=" + std::to_string(p.height) +
         " n=" + std::to_string(p.num_points) + " tilt=" + std::to_string(p.mean_normal_tilt) +
         " groups=" + std::to_string(p.group_angle) + "]";
  }
  return s;
}

// A copy of a cloud whose x is not at the start of each point (a 4-byte tag first): stages that
// take a fast path for PCL's layout read it the plain way, so the two can be compared.
struct ShiftedCopy {
  struct Point {
    float tag, x, y, z;
  };
  std::vector<Point> points;

  explicit ShiftedCopy(const pcl::PointCloud<pcl::PointXYZ>& cloud) {
    for (const auto& p : cloud) points.push_back({0.f, p.x, p.y, p.z});
  }
  PointsView view() const {
    PointsView v;
    v.data = reinterpret_cast<const std::uint8_t*>(points.data());
    v.count = points.size();
    v.stride = sizeof(Point);
    v.x_offset = 4, v.y_offset = 8, v.z_offset = 12;
    v.width = static_cast<std::uint32_t>(points.size());
    return v;
  }
};

inline std::string sharedData(const std::string& relative) {
  return std::string(HOPE_SHARED_DATA) + "/" + relative;
}

}  // namespace test
}  // namespace hope
