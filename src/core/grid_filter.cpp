#include "hope/grid_filter.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>

namespace hope {

namespace {

// Above this many xy cells a dense column table would cost more memory and time than a hash
// map (sparse LiDAR scans at fine resolution); below it, two counting-sort passes order the
// points by voxel in linear time.
std::size_t denseColumnLimit(std::size_t num_points) {
  const std::size_t floor_limit = std::size_t{1} << 20;
  const std::size_t cap = std::size_t{1} << 25;
  return std::min(cap, std::max(floor_limit, 2 * num_points));
}

std::uint64_t cellCount(double extent, double leaf, const char* axis, const char* leaf_name) {
  const double cells = std::floor(extent / leaf) + 1.0;
  if (!(cells <= static_cast<double>(VoxelGrid::kMaxCellsPerAxis))) {
    std::ostringstream msg;
    msg << "the cloud spans " << extent << " m along " << axis << ", which at " << leaf_name
        << " = " << leaf << " m is more than " << VoxelGrid::kMaxCellsPerAxis
        << " grid cells; crop the cloud, drop outliers or use a coarser " << leaf_name
        << " (are the points in millimetres instead of metres?)";
    throw std::invalid_argument(msg.str());
  }
  return static_cast<std::uint64_t>(cells);
}

}  // namespace

void VoxelGrid::build(const std::vector<Eigen::Vector3f>& aligned, double r_xy, double r_z) {
  r_xy_ = r_xy;
  r_z_ = r_z;
  const std::size_t n = aligned.size();
  if (n > std::numeric_limits<std::int32_t>::max()) {
    throw std::invalid_argument("clouds of more than 2^31 points are not supported");
  }
  point_voxel_.assign(n, -1);
  finite_index_.clear();
  centroid_.clear();
  column_.clear();
  iz_.clear();
  point_order_.clear();
  point_begin_.assign(1, 0);
  dense_column_begin_.clear();
  sparse_columns_.clear();
  nx_ = ny_ = 1;
  extent_.setZero();

  Eigen::Vector3f lo = Eigen::Vector3f::Constant(std::numeric_limits<float>::max());
  Eigen::Vector3f hi = -lo;
  finite_index_.reserve(n);
  for (std::size_t i = 0; i < n; ++i) {
    const Eigen::Vector3f& p = aligned[i];
    if (!p.allFinite()) continue;
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
    finite_index_.push_back(static_cast<std::uint32_t>(i));
  }
  const std::size_t m = finite_index_.size();
  if (m == 0) return;

  origin_ = lo.cast<double>();
  const Eigen::Vector3d extent = hi.cast<double>() - origin_;
  extent_ = extent;
  nx_ = cellCount(extent.x(), r_xy, "x", "r_xy");
  ny_ = cellCount(extent.y(), r_xy, "y", "r_xy");
  const std::uint64_t nz = cellCount(extent.z(), r_z, "z", "r_z");

  // Cell coordinates of every finite point. Clamping guards against the floating-point case
  // where (p - lo) / leaf lands exactly on the cell count.
  point_column_.resize(m);
  point_iz_.resize(m);
  const double inv_xy = 1.0 / r_xy, inv_z = 1.0 / r_z;
  const double ox = origin_.x(), oy = origin_.y(), oz = origin_.z();
  for (std::size_t k = 0; k < m; ++k) {
    const Eigen::Vector3f& p = aligned[finite_index_[k]];
    const auto ix =
        std::min<std::uint64_t>(static_cast<std::uint64_t>((p.x() - ox) * inv_xy), nx_ - 1);
    const auto iy =
        std::min<std::uint64_t>(static_cast<std::uint64_t>((p.y() - oy) * inv_xy), ny_ - 1);
    const auto iz =
        std::min<std::uint64_t>(static_cast<std::uint64_t>((p.z() - oz) * inv_z), nz - 1);
    point_column_[k] = ix + nx_ * iy;
    point_iz_[k] = static_cast<std::uint32_t>(iz);
  }

  const bool dense = nx_ * ny_ <= denseColumnLimit(m);
  if (dense) {
    sortByCounting(static_cast<std::size_t>(nx_ * ny_), static_cast<std::size_t>(nz));
  } else {
    sortByComparison();
  }
  collectVoxels(aligned, dense);
}

// Two stable counting-sort passes (least significant key first): by z cell, then by column.
// Leaves scratch_ holding finite-point positions k sorted by (column, z cell).
void VoxelGrid::sortByCounting(std::size_t num_columns, std::size_t nz) {
  const std::size_t m = point_column_.size();
  std::vector<std::uint32_t> counts(std::max(num_columns, nz) + 1, 0);
  std::vector<std::uint32_t>& by_z = point_order_;  // borrowed as scratch, rewritten later
  by_z.resize(m);
  for (std::size_t k = 0; k < m; ++k) ++counts[point_iz_[k] + 1];
  for (std::size_t b = 1; b <= nz; ++b) counts[b] += counts[b - 1];
  for (std::size_t k = 0; k < m; ++k) by_z[counts[point_iz_[k]]++] = static_cast<std::uint32_t>(k);

  std::fill(counts.begin(), counts.begin() + num_columns + 1, 0);
  for (std::size_t k = 0; k < m; ++k) ++counts[point_column_[k] + 1];
  for (std::size_t b = 1; b <= num_columns; ++b) counts[b] += counts[b - 1];
  scratch_.resize(m);
  for (std::size_t j = 0; j < m; ++j) {
    const std::uint32_t k = by_z[j];
    scratch_[counts[point_column_[k]]++] = k;
  }
}

void VoxelGrid::sortByComparison() {
  const std::size_t m = point_column_.size();
  // Key = (column, z cell) packed in 64 bits: column < 2^42, z cell < 2^21.
  std::vector<std::pair<std::uint64_t, std::uint32_t>> keyed(m);
  for (std::size_t k = 0; k < m; ++k) {
    keyed[k] = {(point_column_[k] << 21) | point_iz_[k], static_cast<std::uint32_t>(k)};
  }
  std::sort(keyed.begin(), keyed.end());
  scratch_.resize(m);
  for (std::size_t j = 0; j < m; ++j) scratch_[j] = keyed[j].second;
}

// Walks the sorted points once: each run of equal (column, z cell) is a voxel.
void VoxelGrid::collectVoxels(const std::vector<Eigen::Vector3f>& aligned, bool dense_columns) {
  const std::size_t m = scratch_.size();
  point_order_.resize(m);
  point_begin_.clear();
  std::uint64_t current_column = std::numeric_limits<std::uint64_t>::max();
  std::uint32_t current_iz = std::numeric_limits<std::uint32_t>::max();
  for (std::size_t j = 0; j < m; ++j) {
    const std::uint32_t k = scratch_[j];
    if (point_column_[k] != current_column || point_iz_[k] != current_iz) {
      current_column = point_column_[k];
      current_iz = point_iz_[k];
      point_begin_.push_back(static_cast<std::uint32_t>(j));
      column_.push_back(current_column);
      iz_.push_back(static_cast<std::int32_t>(current_iz));
    }
    const std::uint32_t input_index = finite_index_[k];
    point_order_[j] = input_index;
    point_voxel_[input_index] = static_cast<std::int32_t>(column_.size() - 1);
  }
  point_begin_.push_back(static_cast<std::uint32_t>(m));

  // Centroids in input order: the points are read sequentially and only the (much smaller)
  // per-voxel sums are accessed at random.
  std::vector<Eigen::Vector3d> sums(column_.size(), Eigen::Vector3d::Zero());
  for (std::size_t i = 0; i < aligned.size(); ++i) {
    const std::int32_t v = point_voxel_[i];
    if (v >= 0) sums[v] += aligned[i].cast<double>();
  }
  centroid_.resize(column_.size());
  for (std::size_t v = 0; v < column_.size(); ++v) {
    centroid_[v] =
        (sums[v] / static_cast<double>(point_begin_[v + 1] - point_begin_[v])).cast<float>();
  }

  const std::size_t num_voxels = column_.size();
  if (dense_columns) {
    dense_column_begin_.assign(nx_ * ny_ + 1, 0);
    for (std::size_t v = 0; v < num_voxels; ++v) ++dense_column_begin_[column_[v] + 1];
    for (std::size_t c = 1; c < dense_column_begin_.size(); ++c) {
      dense_column_begin_[c] += dense_column_begin_[c - 1];
    }
  } else {
    for (std::size_t v = 0; v < num_voxels;) {
      std::size_t end = v + 1;
      while (end < num_voxels && column_[end] == column_[v]) ++end;
      sparse_columns_[column_[v]] = {static_cast<std::uint32_t>(v),
                                     static_cast<std::uint32_t>(end)};
      v = end;
    }
  }
}

std::pair<std::uint32_t, std::uint32_t> VoxelGrid::sparseColumnVoxels(std::uint64_t c) const {
  const auto it = sparse_columns_.find(c);
  return it == sparse_columns_.end() ? std::pair<std::uint32_t, std::uint32_t>{0, 0} : it->second;
}

}  // namespace hope
