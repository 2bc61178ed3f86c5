// Grid filter (paper §2.2): an anisotropic voxel grid with leaf (r_xy, r_xy, r_z) in the
// gravity-aligned frame. Unlike a plain down-sampling filter it remembers which voxel every
// input point went to, so results can be given back at full resolution, and it indexes the
// voxels by grid column so that the later stages find neighbours without a k-d tree.
#pragma once

#include <cstdint>
#include <unordered_map>
#include <utility>
#include <vector>

#include <Eigen/Core>

namespace hope {

class VoxelGrid {
 public:
  // Voxelizes the finite points of `aligned` (NaN entries are skipped). Throws
  // std::invalid_argument when the finite points span more than kMaxCellsPerAxis cells on
  // an axis (a unit mistake or a wild outlier; the message says which axis and how far).
  void build(const std::vector<Eigen::Vector3f>& aligned, double r_xy, double r_z);

  static constexpr std::int64_t kMaxCellsPerAxis = std::int64_t{1} << 21;

  std::size_t numVoxels() const { return centroid_.size(); }
  double rXY() const { return r_xy_; }
  double rZ() const { return r_z_; }
  // Size of the box spanned by the finite points, metres (zero when there are none).
  Eigen::Vector3d extent() const { return extent_; }

  // Per voxel. Voxels are ordered by grid column (x-major within each row of y) and, inside
  // a column, by z cell, so one column's voxels are contiguous.
  const Eigen::Vector3f& centroid(std::size_t v) const { return centroid_[v]; }
  int cellX(std::size_t v) const { return static_cast<int>(column_[v] % nx_); }
  int cellY(std::size_t v) const { return static_cast<int>(column_[v] / nx_); }
  int cellZ(std::size_t v) const { return iz_[v]; }
  std::uint64_t column(std::size_t v) const { return column_[v]; }
  std::uint32_t numPointsIn(std::size_t v) const { return point_begin_[v + 1] - point_begin_[v]; }
  // Input indices of the points in voxel v: pointsBegin(v) .. pointsEnd(v).
  const std::uint32_t* pointsBegin(std::size_t v) const {
    return point_order_.data() + point_begin_[v];
  }
  const std::uint32_t* pointsEnd(std::size_t v) const {
    return point_order_.data() + point_begin_[v + 1];
  }
  // Per input point: its voxel, or -1 for non-finite points.
  const std::vector<std::int32_t>& pointVoxel() const { return point_voxel_; }

  // The voxels of grid column (cx, cy) as a half-open index range; empty outside the grid.
  // Inline: every stage after the grid asks it for each voxel's neighbours.
  std::pair<std::uint32_t, std::uint32_t> columnVoxels(std::int64_t cx, std::int64_t cy) const {
    if (cx < 0 || cy < 0 || static_cast<std::uint64_t>(cx) >= nx_ ||
        static_cast<std::uint64_t>(cy) >= ny_) {
      return {0, 0};
    }
    const std::uint64_t c = static_cast<std::uint64_t>(cx) + nx_ * static_cast<std::uint64_t>(cy);
    if (!dense_column_begin_.empty()) return {dense_column_begin_[c], dense_column_begin_[c + 1]};
    return sparseColumnVoxels(c);
  }
  // The xy rectangle covered by column (cx, cy).
  double cellMinX(std::int64_t cx) const { return origin_.x() + cx * r_xy_; }
  double cellMinY(std::int64_t cy) const { return origin_.y() + cy * r_xy_; }

 private:
  std::pair<std::uint32_t, std::uint32_t> sparseColumnVoxels(std::uint64_t column) const;
  void sortByCounting(std::size_t num_columns, std::size_t nz);
  void sortByComparison();
  void collectVoxels(const std::vector<Eigen::Vector3f>& aligned, bool dense_columns);

  double r_xy_ = 0, r_z_ = 0;
  Eigen::Vector3d origin_ = Eigen::Vector3d::Zero();
  Eigen::Vector3d extent_ = Eigen::Vector3d::Zero();
  std::uint64_t nx_ = 1, ny_ = 1;

  // Scratch per finite point (reused across frames to avoid reallocations).
  std::vector<std::uint32_t> finite_index_, point_iz_, scratch_;
  std::vector<std::uint64_t> point_column_;

  std::vector<std::uint32_t> point_order_;  // input indices sorted by voxel
  std::vector<std::int32_t> point_voxel_;
  std::vector<std::uint32_t> point_begin_;  // per voxel + 1, offsets into point_order_
  std::vector<Eigen::Vector3f> centroid_;
  std::vector<std::uint64_t> column_;
  std::vector<std::int32_t> iz_;

  // Column → voxel range: a dense table when the grid is small enough, a hash map otherwise.
  std::vector<std::uint32_t> dense_column_begin_;  // size nx·ny + 1, or empty
  std::unordered_map<std::uint64_t, std::pair<std::uint32_t, std::uint32_t>> sparse_columns_;
};

}  // namespace hope
