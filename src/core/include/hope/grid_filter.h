// Grid filter (paper §2.2): an anisotropic voxel grid with leaf (r_xy, r_xy, r_z) in the
// gravity-aligned frame. Unlike a plain down-sampling filter it remembers which voxel every
// input point went to, so results can be given back at full resolution, and it indexes the
// voxels by grid column so that the later stages find neighbours without a k-d tree.
#pragma once

#include <algorithm>
#include <cstdint>
#include <optional>
#include <unordered_map>
#include <utility>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "hope/points_view.h"

namespace hope {

// What the caller may already know about the points, to save the grid a pass over them.
struct GridHints {
  // The box of the finite points and their number (alignToGravity computes both on its pass);
  // without them build() reads the points once more to find them.
  std::optional<Eigen::AlignedBox3f> finite_box;
  std::size_t finite_points = 0;
  // Threads for the point passes (Params::threads; 0: every core). The result does not depend
  // on it.
  int threads = 1;
};

namespace detail {

// Voxels in order of first appearance: key (column · nz + z cell) and its two parts, point
// count and coordinate sums (double, each voxel's points added in input order).
struct VoxelList {
  std::vector<std::uint64_t> key, column;
  std::vector<std::uint32_t> iz, count;
  std::vector<Eigen::Vector3d> sum;
  void clear();
  void append(const VoxelList& other);  // other's voxels after these
  std::size_t size() const { return key.size(); }
};

// From key to its number in a VoxelList: an open-addressing hash table (slots cleared one by
// one after use, so a small list costs little however large the table grew), with a small
// direct-mapped table of recently seen voxels in front of it. One per thread, reused across
// chunks and frames.
struct VoxelIndex {
  std::vector<std::uint64_t> slot_key;
  std::vector<std::uint32_t> slot_voxel, voxel_slot;
  std::vector<std::pair<std::uint64_t, std::uint32_t>> recent;  // key, voxel

  // Empties the index (for a new list).
  void reset();
  // The number of `key` in `list`, appended (count and sum zero) when new.
  std::uint32_t voxelOf(std::uint64_t key, std::uint64_t column, std::uint64_t iz, VoxelList& list);

 private:
  void grow();
};

}  // namespace detail

class VoxelGrid {
 public:
  // Voxelizes the finite points of `aligned` (NaN entries are skipped). Throws
  // std::invalid_argument when the finite points span more than kMaxCellsPerAxis cells on
  // an axis (a unit mistake or a wild outlier; the message says which axis and how far).
  // The result does not depend on the hints.
  void build(const AlignedPoints& aligned, double r_xy, double r_z,
             const GridHints& hints = GridHints());

  static constexpr std::int64_t kMaxCellsPerAxis = std::int64_t{1} << 21;
  // The points are voxelized in chunks of this many (input order), on as many threads as
  // GridHints::threads allows; each voxel's coordinates are summed in input order within a
  // chunk and the chunks' sums added in chunk order. The chunks do not depend on the number of
  // threads, so neither does the result.
  static constexpr int kChunkBits = 16;
  static constexpr std::size_t kPointsPerChunk = std::size_t{1} << kChunkBits;
  // Columns of up to this many voxels are scanned rather than bisected (firstAtOrAbove).
  static constexpr std::uint32_t kShortColumn = 12;

  std::size_t numVoxels() const { return centroid_.size(); }
  double rXY() const { return r_xy_; }
  double rZ() const { return r_z_; }
  // Size of the box spanned by the finite points, metres (zero when there are none).
  Eigen::Vector3d extent() const { return extent_; }

  // Per voxel. Voxels are ordered by grid column (x-major within each row of y) and, inside
  // a column, by z cell, so one column's voxels are contiguous.
  const Eigen::Vector3f& centroid(std::size_t v) const { return centroid_[v]; }
  int cellX(std::size_t v) const { return cell_x_[v]; }
  int cellY(std::size_t v) const { return cell_y_[v]; }
  int cellZ(std::size_t v) const { return iz_[v]; }
  std::uint64_t column(std::size_t v) const { return column_[v]; }
  std::uint32_t numPointsIn(std::size_t v) const { return count_[v]; }
  // Per input point: its voxel, or -1 for non-finite points. (No per-voxel point lists are
  // kept: the few stages that need points read this once for all voxels they care about.)
  // The grid keeps each point's voxel as numbered within its chunk of points, and the view
  // renumbers it on reading: the one stage that reads every point (describeInFull) does so in
  // its own pass, instead of the grid spending a pass over the points on renumbering them.
  class PointVoxels {
   public:
    std::size_t size() const { return size_; }
    std::int32_t operator[](std::size_t i) const {
      const std::int32_t local = local_[i];
      if (local < 0) return -1;
      return static_cast<std::int32_t>(
          entry_voxel_[chunk_begin_[i >> kChunkBits] + static_cast<std::uint32_t>(local)]);
    }

   private:
    friend class VoxelGrid;
    // Raw pointers, not the grid: a loop that stores through an int32_t pointer (labels) would
    // otherwise reload the grid's vectors after every store.
    explicit PointVoxels(const VoxelGrid& grid)
        : local_(grid.point_entry_.data()),
          entry_voxel_(grid.entry_voxel_.data()),
          chunk_begin_(grid.chunk_begin_.data()),
          size_(grid.point_entry_.size()) {}
    const std::int32_t* local_;
    const std::uint32_t* entry_voxel_;
    const std::uint32_t* chunk_begin_;
    std::size_t size_;
  };
  // The view reads the grid's tables in place: valid until the next build().
  PointVoxels pointVoxels() const { return PointVoxels(*this); }
  // The same as a vector, written out on each call (one pass over the points).
  std::vector<std::int32_t> pointVoxel() const;

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
  // Whether columns are kept in a dense table; then rowVoxels() works.
  bool denseColumns() const { return !dense_column_begin_.empty(); }
  // The voxels of columns cx0..cx1 (inclusive, clipped to the grid) of row cy as one half-open
  // index range: voxels are ordered by column, x-major within a row, so they are contiguous,
  // each column's voxels after the previous column's. A stage that looks at three neighbouring
  // columns of a row then needs one lookup, not three. Empty unless denseColumns().
  std::pair<std::uint32_t, std::uint32_t> rowVoxels(std::int64_t cx0, std::int64_t cx1,
                                                    std::int64_t cy) const {
    if (dense_column_begin_.empty()) return {0, 0};
    cx0 = std::max<std::int64_t>(cx0, 0);
    cx1 = std::min<std::int64_t>(cx1, static_cast<std::int64_t>(nx_) - 1);
    if (cy < 0 || static_cast<std::uint64_t>(cy) >= ny_ || cx0 > cx1) return {0, 0};
    const std::uint64_t row = nx_ * static_cast<std::uint64_t>(cy);
    return {dense_column_begin_[row + static_cast<std::uint64_t>(cx0)],
            dense_column_begin_[row + static_cast<std::uint64_t>(cx1) + 1]};
  }
  // The first voxel of `range` (one column's voxels, from columnVoxels) whose z cell is at least
  // `iz`, or range.second: the stages that look a few z cells around a voxel search a tall
  // column (a wall, an object's side at a fine r_z) instead of walking it from the floor.
  // Most columns hold a few voxels, which a plain scan settles faster than a bisection.
  std::uint32_t firstAtOrAbove(std::pair<std::uint32_t, std::uint32_t> range, int iz) const {
    if (range.second - range.first <= kShortColumn) {
      std::uint32_t u = range.first;
      while (u < range.second && iz_[u] < iz) ++u;
      return u;
    }
    return static_cast<std::uint32_t>(
        std::lower_bound(iz_.begin() + range.first, iz_.begin() + range.second, iz) - iz_.begin());
  }
  // The xy rectangle covered by column (cx, cy).
  double cellMinX(std::int64_t cx) const { return origin_.x() + cx * r_xy_; }
  double cellMinY(std::int64_t cy) const { return origin_.y() + cy * r_xy_; }

 private:
  std::pair<std::uint32_t, std::uint32_t> sparseColumnVoxels(std::uint64_t column) const;
  // Pass 2 of build(): each chunk's points assigned to the chunk's own voxels (point_entry_
  // holds the chunk's voxel numbers), with their keys, point counts and coordinate sums, on up
  // to `threads` threads.
  void assignPointsToVoxels(const AlignedPoints& aligned, std::uint64_t nz, int threads);
  // Pass 3: the chunks' voxels sorted by (column, z cell) and a key's entries joined into one
  // voxel (counts and sums added in chunk order); entry_voxel_ maps each chunk's voxels to them.
  void orderVoxels(bool dense_columns);
  void sortEntriesByKey();  // into sorted_

  double r_xy_ = 0, r_z_ = 0;
  Eigen::Vector3d origin_ = Eigen::Vector3d::Zero();
  Eigen::Vector3d extent_ = Eigen::Vector3d::Zero();
  std::uint64_t nx_ = 1, ny_ = 1;

  std::vector<detail::VoxelIndex> indexes_;       // one per thread
  std::vector<detail::VoxelList> chunks_;         // the voxels of each chunk of points
  detail::VoxelList entries_;                     // every chunk's voxels, chunk after chunk
  std::vector<std::uint32_t> chunk_begin_;        // per chunk: offset of its voxels in entries_
  std::vector<std::uint32_t> sorted_;             // entries in (column, z cell, chunk) order
  std::vector<std::uint32_t> entry_voxel_;        // entry → voxel
  std::vector<std::uint32_t> counts_, by_digit_;  // radix sort: buckets, the other buffer
  std::vector<Eigen::Vector3d> sums_;             // per voxel: coordinate sums

  // Per point: its voxel's number within the point's chunk (an entry, less the chunk's first),
  // or -1; see PointVoxels.
  std::vector<std::int32_t> point_entry_;
  std::vector<std::uint32_t> count_;  // points per voxel
  std::vector<Eigen::Vector3f> centroid_;
  std::vector<std::uint64_t> column_;
  // column_ split into its x and y cells once, so that the stages' neighbour lookups need no
  // division.
  std::vector<std::int32_t> cell_x_, cell_y_;
  std::vector<std::int32_t> iz_;

  // Column → voxel range: a dense table when the grid is small enough, a hash map otherwise.
  std::vector<std::uint32_t> dense_column_begin_;  // size nx·ny + 1, or empty
  std::unordered_map<std::uint64_t, std::pair<std::uint32_t, std::uint32_t>> sparse_columns_;
};

}  // namespace hope
