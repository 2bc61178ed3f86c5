// Grid filter (paper §2.2): an anisotropic voxel grid with leaf (r_xy, r_xy, r_z) in the
// gravity-aligned frame. Unlike a plain down-sampling filter it remembers which voxel every
// input point went to, so results can be given back at full resolution, and it indexes the
// voxels by grid column so that the later stages find neighbours without a k-d tree.
#pragma once

#include <cstdint>
#include <optional>
#include <unordered_map>
#include <utility>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "hope/aligned_points.h"

namespace hope {

// What the caller may already know about the points, to save the grid a pass or lookups.
struct GridHints {
  // Points per image row for an organized cloud (0: unorganized). The point one row up, which
  // often shares the voxel, is then checked before the voxel table.
  std::size_t row_width = 0;
  // The box of the finite points and their number (alignToGravity computes both on its pass);
  // without them build() reads the points once more to find them.
  std::optional<Eigen::AlignedBox3f> finite_box;
  std::size_t finite_points = 0;
  // Threads for the pass that renumbers the points' voxels (Params::threads; 0: every core).
  int threads = 1;
};

class VoxelGrid {
 public:
  // Voxelizes the finite points of `aligned` (NaN entries are skipped). Throws
  // std::invalid_argument when the finite points span more than kMaxCellsPerAxis cells on
  // an axis (a unit mistake or a wild outlier; the message says which axis and how far).
  // The result does not depend on the hints.
  void build(const AlignedPoints& aligned, double r_xy, double r_z,
             const GridHints& hints = GridHints());

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
  std::uint32_t numPointsIn(std::size_t v) const { return count_[v]; }
  // Per input point: its voxel, or -1 for non-finite points. (No per-voxel point lists are
  // kept: the few stages that need points read this once for all voxels they care about.)
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
  // Pass 2 of build(): every finite point's voxel, numbered in order of first appearance
  // (point_voxel_), with each voxel's key, point count and coordinate sums.
  void assignPointsToVoxels(const AlignedPoints& aligned, std::size_t finite_points,
                            std::uint64_t nz, std::size_t row_width);
  std::uint32_t voxelOfKey(std::uint64_t key, std::uint64_t column, std::uint64_t iz);
  void growSlots();
  // Pass 3: voxels renumbered in (column, z cell) order, and the points' voxels with them.
  void orderVoxels(std::uint64_t nz, bool dense_columns, int threads);

  double r_xy_ = 0, r_z_ = 0;
  Eigen::Vector3d origin_ = Eigen::Vector3d::Zero();
  Eigen::Vector3d extent_ = Eigen::Vector3d::Zero();
  std::uint64_t nx_ = 1, ny_ = 1;

  // Voxels in order of first appearance while points are assigned: key (column · nz + z cell)
  // and its two parts, point count and coordinate sums (double, summed in input order); an
  // open-addressing hash table from key to that number (kEmptySlot where free). Reused across
  // frames.
  std::vector<std::uint64_t> found_key_, found_column_;
  std::vector<std::uint32_t> found_iz_;
  std::vector<std::uint32_t> found_count_;
  std::vector<Eigen::Vector3d> found_sum_;
  std::vector<std::uint64_t> slot_key_;
  std::vector<std::uint32_t> slot_voxel_;
  std::vector<std::uint32_t> sorted_;  // first-appearance numbers in (column, z cell) order
  std::vector<std::uint32_t> renumber_, counts_, by_z_;
  std::vector<std::pair<std::uint64_t, std::uint32_t>> row_above_;  // key, voxel per image column
  static constexpr std::size_t kRecentVoxels = 4096;                // a power of two
  std::vector<std::pair<std::uint64_t, std::uint32_t>> recent_voxels_;  // key, voxel

  std::vector<std::int32_t> point_voxel_;
  std::vector<std::uint32_t> count_;  // points per voxel
  std::vector<Eigen::Vector3f> centroid_;
  std::vector<std::uint64_t> column_;
  std::vector<std::int32_t> iz_;

  // Column → voxel range: a dense table when the grid is small enough, a hash map otherwise.
  std::vector<std::uint32_t> dense_column_begin_;  // size nx·ny + 1, or empty
  std::unordered_map<std::uint64_t, std::pair<std::uint32_t, std::uint32_t>> sparse_columns_;
};

}  // namespace hope
