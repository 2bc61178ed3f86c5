// A non-owning view of xyz points in any memory layout (PCL point types, PointCloud2 buffers,
// plain float arrays), so the core never copies a cloud just to read it.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <vector>

#include <pcl/point_cloud.h>
#include <Eigen/Core>

namespace hope {

struct PointsView {
  const std::uint8_t* data = nullptr;                    // first byte of the first point
  std::size_t count = 0;                                 // number of points (width · height)
  std::size_t stride = 0;                                // bytes from one point to the next
  std::size_t x_offset = 0, y_offset = 4, z_offset = 8;  // byte offsets of float32 x, y, z
  std::uint32_t width = 0;   // organized: image columns; unorganized: count
  std::uint32_t height = 1;  // organized: image rows; unorganized: 1

  bool organized() const { return height > 1; }
  // A camera's image: organized and at most 4 times wider than high. A LiDAR's rings × azimuth
  // layout (64 × 2118) is organized but not image-like.
  bool imageLike() const { return organized() && width <= 4 * std::size_t{height}; }

  // Sets width × height to the image shape a header gives when it accounts for every point,
  // and to one row of `count` points otherwise (an inconsistent header is not trusted).
  void setShape(std::uint32_t image_width, std::uint32_t image_height) {
    const bool consistent = std::uint64_t{image_width} * image_height == count;
    width = consistent ? image_width : static_cast<std::uint32_t>(count);
    height = consistent ? image_height : 1;
  }

  float x(std::size_t i) const { return load(i, x_offset); }
  float y(std::size_t i) const { return load(i, y_offset); }
  float z(std::size_t i) const { return load(i, z_offset); }

  // Any PCL point type with float x, y, z members.
  template <class PointT>
  static PointsView of(const pcl::PointCloud<PointT>& cloud) {
    PointsView v;
    v.data = cloud.empty() ? nullptr : reinterpret_cast<const std::uint8_t*>(&cloud.points[0]);
    v.count = cloud.size();
    v.stride = sizeof(PointT);
    v.x_offset = offsetof(PointT, x);
    v.y_offset = offsetof(PointT, y);
    v.z_offset = offsetof(PointT, z);
    v.setShape(cloud.width, cloud.height);
    return v;
  }

 private:
  float load(std::size_t i, std::size_t offset) const {
    float value;
    std::memcpy(&value, data + i * stride + offset, sizeof(float));  // unaligned-safe
    return value;
  }
};

// The points in the gravity-aligned frame as the stages read them: x, y, z as three
// consecutive float32 at the start of each record of `stride` bytes. Either the extractor's
// aligned copy (a std::vector<Eigen::Vector3f>, which converts implicitly) or, when the
// orientation needs no rotation and no translation, the input cloud itself: no copy is made.
struct AlignedPoints {
  const std::uint8_t* data = nullptr;
  std::size_t count = 0;
  std::size_t stride = sizeof(Eigen::Vector3f);

  AlignedPoints() = default;
  AlignedPoints(const std::uint8_t* first, std::size_t n, std::size_t bytes_per_point)
      : data(first), count(n), stride(bytes_per_point) {}
  // NOLINTNEXTLINE(google-explicit-constructor): a vector is the common case
  AlignedPoints(const std::vector<Eigen::Vector3f>& points)
      : data(reinterpret_cast<const std::uint8_t*>(points.data())), count(points.size()) {}

  std::size_t size() const { return count; }
  bool empty() const { return count == 0; }
  // Point i; non-finite input points are NaN or infinite.
  Eigen::Vector3f operator[](std::size_t i) const {
    float xyz[3];
    std::memcpy(xyz, data + i * stride, sizeof(xyz));  // unaligned-safe
    return Eigen::Vector3f(xyz[0], xyz[1], xyz[2]);
  }
};

}  // namespace hope
