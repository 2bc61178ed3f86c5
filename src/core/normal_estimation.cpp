#include "hope/normal_estimation.h"

#include <cmath>
#include <limits>
#include <utility>

#include <Eigen/Eigenvalues>

#include "parallel.h"

namespace hope {

namespace {

// Neighbours spread along a line fix only one direction: their "normal" is any vector across
// the line. Require the middle eigenvalue to carry at least this share of the largest one.
constexpr float kMinPlanarity = 0.05f;

}  // namespace

NormalNeighbourhood::NormalNeighbourhood(const VoxelGrid& grid, double radius_factor)
    : grid_(grid), max_dz_(static_cast<float>(2.0 * grid.rZ())) {
  // Column offsets (in cells) whose centres lie within radius_factor·r_xy.
  const int reach = static_cast<int>(std::floor(radius_factor));
  for (int dy = -reach; dy <= reach; ++dy) {
    for (int dx = -reach; dx <= reach; ++dx) {
      if (dx * dx + dy * dy <= radius_factor * radius_factor) offsets_.emplace_back(dx, dy);
    }
  }
  reach_z_ = static_cast<int>(std::ceil(max_dz_ / grid.rZ())) + 1;
}

NormalNeighbourhood::Moments NormalNeighbourhood::moments(std::size_t v) const {
  const Eigen::Vector3f p = grid_.centroid(v);
  const int cx = grid_.cellX(v), cy = grid_.cellY(v), cz = grid_.cellZ(v);
  // Offsets from p keep the sums small, so single precision stays accurate far from 0.
  Moments m;
  for (const auto& [dx, dy] : offsets_) {
    const auto range = grid_.columnVoxels(cx + dx, cy + dy);
    for (std::uint32_t u = grid_.firstAtOrAbove(range, cz - reach_z_); u < range.second; ++u) {
      if (grid_.cellZ(u) > cz + reach_z_) break;  // a column's voxels are sorted by z cell
      const Eigen::Vector3f d = grid_.centroid(u) - p;
      if (std::fabs(d.z()) > max_dz_) continue;
      m.sum += d;
      m.outer.noalias() += d * d.transpose();
      ++m.count;
    }
  }
  return m;
}

Eigen::Matrix3f NormalNeighbourhood::Moments::covariance() const {
  const Eigen::Vector3f mean = sum / static_cast<float>(count);
  return outer / static_cast<float>(count) - mean * mean.transpose();
}

void estimateNormals(const VoxelGrid& grid, double radius_factor,
                     std::vector<Eigen::Vector3f>& normals, int threads) {
  const std::size_t num_voxels = grid.numVoxels();
  const float nan = std::numeric_limits<float>::quiet_NaN();
  normals.assign(num_voxels, Eigen::Vector3f(nan, nan, nan));
  const NormalNeighbourhood neighbourhood(grid, radius_factor);
  parallel::forShares(num_voxels, parallel::resolve(threads), 2048,
                      [&](int /*share*/, std::size_t begin, std::size_t end) {
                        for (std::size_t v = begin; v < end; ++v) {
                          const NormalNeighbourhood::Moments m = neighbourhood.moments(v);
                          if (m.count < 3) continue;
                          Eigen::SelfAdjointEigenSolver<Eigen::Matrix3f> solver;
                          solver.computeDirect(m.covariance());
                          const Eigen::Vector3f& eigenvalues = solver.eigenvalues();  // ascending
                          if (!(eigenvalues(1) > kMinPlanarity * eigenvalues(2))) continue;
                          Eigen::Vector3f n = solver.eigenvectors().col(0);
                          if (!n.allFinite() || n.squaredNorm() < 0.5f) continue;
                          n.normalize();
                          normals[v] = n.z() < 0 ? Eigen::Vector3f(-n) : n;
                        }
                      });
}

}  // namespace hope
