// The grid filter written the plain way, for tests that check the optimized VoxelGrid against
// it (test_stages, test_reference_pipeline).
#pragma once

#include <cmath>
#include <cstdint>
#include <limits>
#include <map>
#include <utility>
#include <vector>

#include <gtest/gtest.h>
#include <Eigen/Core>

#include "hope/grid_filter.h"

namespace hope {
namespace test {

// The grid filter as the paper describes it, written the plain way: the box of the finite
// points, each point's cell, a sorted map from (column, z cell) to the points in input order,
// centroids summed in double in input order within each chunk of kPointsPerChunk points and
// the chunks' sums added in chunk order (the grid's documented summation order). The
// optimized VoxelGrid must give exactly this.
struct ReferenceVoxel {
  std::vector<std::uint32_t> points;
  std::map<std::size_t, Eigen::Vector3d> chunk_sums;  // by chunk, in chunk order
};

inline void expectSameAsReference(const VoxelGrid& grid, const std::vector<Eigen::Vector3f>& pts,
                                  double r_xy, double r_z) {
  Eigen::Vector3f lo = Eigen::Vector3f::Constant(std::numeric_limits<float>::max());
  Eigen::Vector3f hi = -lo;
  for (const auto& p : pts) {
    if (!p.allFinite()) continue;
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  const Eigen::Vector3d origin = lo.cast<double>();
  const Eigen::Vector3d extent = hi.cast<double>() - origin;
  const auto nx = static_cast<std::uint64_t>(std::floor(extent.x() / r_xy) + 1);
  const auto ny = static_cast<std::uint64_t>(std::floor(extent.y() / r_xy) + 1);
  const auto nz = static_cast<std::uint64_t>(std::floor(extent.z() / r_z) + 1);
  std::map<std::pair<std::uint64_t, std::uint64_t>, ReferenceVoxel> voxels;
  for (std::size_t i = 0; i < pts.size(); ++i) {
    const Eigen::Vector3f& p = pts[i];
    if (!p.allFinite()) continue;
    const auto ix = std::min<std::uint64_t>(
        static_cast<std::uint64_t>((p.x() - origin.x()) * (1.0 / r_xy)), nx - 1);
    const auto iy = std::min<std::uint64_t>(
        static_cast<std::uint64_t>((p.y() - origin.y()) * (1.0 / r_xy)), ny - 1);
    const auto iz = std::min<std::uint64_t>(
        static_cast<std::uint64_t>((p.z() - origin.z()) * (1.0 / r_z)), nz - 1);
    ReferenceVoxel& voxel = voxels[{ix + nx * iy, iz}];
    voxel.points.push_back(static_cast<std::uint32_t>(i));
    auto chunk = voxel.chunk_sums.emplace(i / VoxelGrid::kPointsPerChunk, Eigen::Vector3d::Zero());
    chunk.first->second += p.cast<double>();
  }
  ASSERT_EQ(grid.numVoxels(), voxels.size());
  const std::vector<std::int32_t> voxel_of_point = grid.pointVoxel();  // through pointVoxels()
  ASSERT_EQ(voxel_of_point.size(), pts.size());
  std::size_t v = 0;
  for (const auto& [key, voxel] : voxels) {
    EXPECT_EQ(grid.column(v), key.first);
    EXPECT_EQ(static_cast<std::uint64_t>(grid.cellZ(v)), key.second);
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    for (const auto& chunk : voxel.chunk_sums) sum += chunk.second;
    const Eigen::Vector3f centroid = (sum / static_cast<double>(voxel.points.size())).cast<float>();
    EXPECT_EQ(grid.centroid(v), centroid) << "voxel " << v;  // bit for bit
    ASSERT_EQ(grid.numPointsIn(v), voxel.points.size());
    for (const std::uint32_t i : voxel.points) {
      ASSERT_EQ(voxel_of_point[i], static_cast<std::int32_t>(v));
    }
    const auto range = grid.columnVoxels(grid.cellX(v), grid.cellY(v));
    EXPECT_TRUE(range.first <= v && v < range.second);
    ++v;
  }
  for (std::size_t i = 0; i < pts.size(); ++i) {
    if (!pts[i].allFinite()) {
      ASSERT_EQ(voxel_of_point[i], -1);
    }
  }
}

}  // namespace test
}  // namespace hope
