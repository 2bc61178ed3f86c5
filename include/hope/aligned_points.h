// The points in the gravity-aligned frame as the stages read them: x, y, z as three
// consecutive float32 at the start of each record of `stride` bytes. Either the extractor's
// aligned copy (a std::vector<Eigen::Vector3f>, which converts implicitly) or, when the
// orientation needs no rotation and no translation, the input cloud itself: no copy is made.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <vector>

#include <Eigen/Core>

namespace hope {

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
