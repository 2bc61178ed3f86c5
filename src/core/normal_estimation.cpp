#include "hope/normal_estimation.h"

#include <cmath>
#include <limits>
#include <utility>

#include <Eigen/Eigenvalues>

namespace hope {

namespace {

// Neighbours spread along a line fix only one direction: their "normal" is any vector across
// the line. Require the middle eigenvalue to carry at least this share of the largest one.
constexpr float kMinPlanarity = 0.05f;

}  // namespace

void estimateNormals(const VoxelGrid& grid, double radius_factor,
                     std::vector<Eigen::Vector3f>& normals) {
  const std::size_t num_voxels = grid.numVoxels();
  const float nan = std::numeric_limits<float>::quiet_NaN();
  normals.assign(num_voxels, Eigen::Vector3f(nan, nan, nan));

  // Column offsets (in cells) whose centres lie within radius_factor·r_xy.
  std::vector<std::pair<int, int>> offsets;
  const int reach = static_cast<int>(std::floor(radius_factor));
  for (int dy = -reach; dy <= reach; ++dy) {
    for (int dx = -reach; dx <= reach; ++dx) {
      if (dx * dx + dy * dy <= radius_factor * radius_factor) offsets.emplace_back(dx, dy);
    }
  }
  const float max_dz = static_cast<float>(2.0 * grid.rZ());
  const int reach_z = static_cast<int>(std::ceil(max_dz / grid.rZ())) + 1;

  for (std::size_t v = 0; v < num_voxels; ++v) {
    const Eigen::Vector3f p = grid.centroid(v);
    const int cx = grid.cellX(v), cy = grid.cellY(v), cz = grid.cellZ(v);
    // Offsets from p keep the sums small, so single precision stays accurate far from 0.
    Eigen::Vector3f sum = Eigen::Vector3f::Zero();
    Eigen::Matrix3f outer = Eigen::Matrix3f::Zero();
    int count = 0;
    for (const auto& [dx, dy] : offsets) {
      const auto range = grid.columnVoxels(cx + dx, cy + dy);
      for (std::uint32_t u = range.first; u < range.second; ++u) {
        const int uz = grid.cellZ(u);
        if (uz < cz - reach_z) continue;
        if (uz > cz + reach_z) break;  // a column's voxels are sorted by z cell
        const Eigen::Vector3f d = grid.centroid(u) - p;
        if (std::fabs(d.z()) > max_dz) continue;
        sum += d;
        outer.noalias() += d * d.transpose();
        ++count;
      }
    }
    if (count < 3) continue;
    const Eigen::Vector3f mean = sum / static_cast<float>(count);
    const Eigen::Matrix3f covariance = outer / static_cast<float>(count) - mean * mean.transpose();
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3f> solver;
    solver.computeDirect(covariance);
    const Eigen::Vector3f& eigenvalues = solver.eigenvalues();  // ascending
    if (!(eigenvalues(1) > kMinPlanarity * eigenvalues(2))) continue;
    Eigen::Vector3f n = solver.eigenvectors().col(0);
    if (!n.allFinite() || n.squaredNorm() < 0.5f) continue;
    n.normalize();
    normals[v] = n.z() < 0 ? Eigen::Vector3f(-n) : n;
  }
}

}  // namespace hope
