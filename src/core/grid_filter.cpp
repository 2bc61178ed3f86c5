#include "hope/grid_filter.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "parallel.h"

namespace hope {

namespace {

// Above this many xy cells a dense column table would cost more memory and time than a hash
// map (sparse LiDAR scans at fine resolution).
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

void VoxelGrid::build(const AlignedPoints& aligned, double r_xy, double r_z,
                      const GridHints& hints) {
  r_xy_ = r_xy;
  r_z_ = r_z;
  const std::size_t n = aligned.size();
  if (n > std::numeric_limits<std::int32_t>::max()) {
    throw std::invalid_argument("clouds of more than 2^31 points are not supported");
  }
  point_voxel_.assign(n, -1);
  centroid_.clear();
  column_.clear();
  iz_.clear();
  count_.clear();
  dense_column_begin_.clear();
  sparse_columns_.clear();
  nx_ = ny_ = 1;
  extent_.setZero();

  // Pass 1: the box of the finite points (aligned non-finite points are NaN), unless known.
  Eigen::Vector3f lo = Eigen::Vector3f::Constant(std::numeric_limits<float>::max());
  Eigen::Vector3f hi = -lo;
  std::size_t m = 0;
  if (hints.finite_box) {
    m = hints.finite_points;
    lo = hints.finite_box->min();
    hi = hints.finite_box->max();
  } else {
    for (std::size_t i = 0; i < n; ++i) {
      const Eigen::Vector3f p = aligned[i];
      if (!p.allFinite()) continue;
      lo = lo.cwiseMin(p);
      hi = hi.cwiseMax(p);
      ++m;
    }
  }
  if (m == 0) return;

  origin_ = lo.cast<double>();
  const Eigen::Vector3d extent = hi.cast<double>() - origin_;
  extent_ = extent;
  nx_ = cellCount(extent.x(), r_xy, "x", "r_xy");
  ny_ = cellCount(extent.y(), r_xy, "y", "r_xy");
  const std::uint64_t nz = cellCount(extent.z(), r_z, "z", "r_z");

  assignPointsToVoxels(aligned, m, nz, hints.row_width);
  orderVoxels(nz, nx_ * ny_ <= denseColumnLimit(m), hints.threads);
}

namespace {
constexpr std::uint64_t kEmptySlot = std::numeric_limits<std::uint64_t>::max();

// Fibonacci hashing: spreads consecutive keys (neighbouring z cells) over the table.
std::size_t slotOf(std::uint64_t key, std::size_t mask) {
  return static_cast<std::size_t>((key * 0x9E3779B97F4A7C15ull) >> 20) & mask;
}
}  // namespace

// One read of the points in input order. Points that follow each other in a scan or an image
// mostly share a voxel, so the last voxel is checked before the hash table. Summing each
// voxel's points in input order keeps the centroids independent of how voxels are numbered.
void VoxelGrid::assignPointsToVoxels(const AlignedPoints& aligned, std::size_t finite_points,
                                     std::uint64_t nz, std::size_t row_width) {
  found_key_.clear();
  found_column_.clear();
  found_iz_.clear();
  found_count_.clear();
  found_sum_.clear();
  // Start at last frame's size (growing costs rehashes), but never above what this cloud can
  // fill (at most one voxel per finite point, half the slots used).
  std::size_t capacity = 4096;
  while (capacity < slot_key_.size() && capacity < 2 * finite_points) capacity *= 2;
  slot_key_.assign(capacity, kEmptySlot);
  slot_voxel_.assign(capacity, 0);

  const double inv_xy = 1.0 / r_xy_, inv_z = 1.0 / r_z_;
  const double ox = origin_.x(), oy = origin_.y(), oz = origin_.z();
  // (p - origin) / leaf is never negative here, so the cheaper signed conversion truncates
  // exactly as an unsigned one would. Clamping guards against the floating-point case where
  // it lands exactly on the cell count.
  auto cell = [](double offset, double inverse_leaf, std::uint64_t cells) {
    return std::min(static_cast<std::uint64_t>(static_cast<std::int64_t>(offset * inverse_leaf)),
                    cells - 1);
  };
  row_above_.assign(row_width, {kEmptySlot, 0});
  recent_voxels_.assign(kRecentVoxels, {kEmptySlot, 0});
  // Everything the loop touches per point lives in locals: a store through point_voxel or
  // into a table could otherwise alias a member, and the compiler would reload them all after
  // every point. The current voxel's count and coordinate sums are carried in registers while
  // its run of points lasts, starting from (and written back to) its stored totals, so each
  // voxel's points are still summed one by one in input order.
  const std::uint64_t nx = nx_, ny = ny_;
  const std::uint8_t* data = aligned.data;
  const std::size_t stride = aligned.stride;
  std::int32_t* point_voxel = point_voxel_.data();
  std::pair<std::uint64_t, std::uint32_t>* row_above = row_above_.data();
  std::size_t column_in_row = 0;
  std::uint64_t last_key = kEmptySlot;
  std::uint32_t last_voxel = 0, run = 0;
  double sum_x = 0, sum_y = 0, sum_z = 0;
  auto storeRun = [&]() {
    if (run == 0) return;
    found_count_[last_voxel] += run;
    found_sum_[last_voxel] = Eigen::Vector3d(sum_x, sum_y, sum_z);
  };
  const std::size_t n = aligned.size();
  for (std::size_t i = 0; i < n; ++i) {
    float xyz[3];
    std::memcpy(xyz, data + i * stride, sizeof(xyz));
    std::pair<std::uint64_t, std::uint32_t>* above = nullptr;
    if (row_width > 0) {
      above = &row_above[column_in_row];
      if (++column_in_row == row_width) column_in_row = 0;
    }
    if ((xyz[0] - xyz[0]) + (xyz[1] - xyz[1]) + (xyz[2] - xyz[2]) != 0.0f) continue;  // NaN/inf
    const double px = xyz[0], py = xyz[1], pz = xyz[2];
    const std::uint64_t ix = cell(px - ox, inv_xy, nx);
    const std::uint64_t iy = cell(py - oy, inv_xy, ny);
    const std::uint64_t iz = cell(pz - oz, inv_z, nz);
    const std::uint64_t column = ix + nx * iy;
    const std::uint64_t key = column * nz + iz;  // < 2^42 · 2^21
    if (key != last_key) {
      storeRun();
      last_key = key;
      if (above && above->first == key) {
        last_voxel = above->second;
      } else {
        // Noise makes neighbouring points alternate between a few voxels of one column:
        // recently seen voxels are kept in a small direct-mapped table (fits the L2 cache)
        // in front of the large hash table.
        auto& recent = recent_voxels_[key & (kRecentVoxels - 1)];
        if (recent.first != key) recent = {key, voxelOfKey(key, column, iz)};
        last_voxel = recent.second;
      }
      const Eigen::Vector3d& stored = found_sum_[last_voxel];
      sum_x = stored.x(), sum_y = stored.y(), sum_z = stored.z();
      run = 0;
    }
    if (above) *above = {key, last_voxel};
    point_voxel[i] = static_cast<std::int32_t>(last_voxel);
    ++run;
    sum_x += px, sum_y += py, sum_z += pz;
  }
  storeRun();
}

std::uint32_t VoxelGrid::voxelOfKey(std::uint64_t key, std::uint64_t column, std::uint64_t iz) {
  const std::size_t mask = slot_key_.size() - 1;
  std::size_t slot = slotOf(key, mask);
  while (slot_key_[slot] != kEmptySlot) {
    if (slot_key_[slot] == key) return slot_voxel_[slot];
    slot = (slot + 1) & mask;
  }
  const auto voxel = static_cast<std::uint32_t>(found_key_.size());
  slot_key_[slot] = key;
  slot_voxel_[slot] = voxel;
  found_key_.push_back(key);
  found_column_.push_back(column);
  found_iz_.push_back(static_cast<std::uint32_t>(iz));
  found_count_.push_back(0);
  found_sum_.push_back(Eigen::Vector3d::Zero());
  if (2 * found_key_.size() > slot_key_.size()) growSlots();  // keep probes short
  return voxel;
}

void VoxelGrid::growSlots() {
  slot_key_.assign(2 * slot_key_.size(), kEmptySlot);
  slot_voxel_.assign(slot_key_.size(), 0);
  const std::size_t mask = slot_key_.size() - 1;
  for (std::size_t v = 0; v < found_key_.size(); ++v) {
    std::size_t slot = slotOf(found_key_[v], mask);
    while (slot_key_[slot] != kEmptySlot) slot = (slot + 1) & mask;
    slot_key_[slot] = found_key_[v];
    slot_voxel_[slot] = static_cast<std::uint32_t>(v);
  }
}

// Voxels sorted by key, i.e. by column (x-major within each row of y) and inside a column by
// z cell; then the points' voxels are renumbered (each point on its own: split across threads).
void VoxelGrid::orderVoxels(std::uint64_t nz, bool dense_columns, int threads) {
  const std::size_t num_voxels = found_key_.size();
  sorted_.resize(num_voxels);
  if (dense_columns) {
    // Two stable counting sorts, by z cell and then by column: linear in the voxels, where a
    // comparison sort of tens of thousands of fine voxels costs milliseconds.
    const std::size_t num_columns = static_cast<std::size_t>(nx_ * ny_);
    counts_.assign(std::max<std::size_t>(num_columns, nz) + 1, 0);
    for (std::size_t v = 0; v < num_voxels; ++v) ++counts_[found_iz_[v] + 1];
    for (std::size_t b = 1; b <= nz; ++b) counts_[b] += counts_[b - 1];
    by_z_.resize(num_voxels);
    for (std::size_t v = 0; v < num_voxels; ++v) {
      by_z_[counts_[found_iz_[v]]++] = static_cast<std::uint32_t>(v);
    }
    std::fill(counts_.begin(), counts_.begin() + num_columns + 1, 0);
    for (std::size_t v = 0; v < num_voxels; ++v) ++counts_[found_column_[v] + 1];
    for (std::size_t b = 1; b <= num_columns; ++b) counts_[b] += counts_[b - 1];
    for (const std::uint32_t v : by_z_) sorted_[counts_[found_column_[v]]++] = v;
  } else {
    for (std::size_t v = 0; v < num_voxels; ++v) sorted_[v] = static_cast<std::uint32_t>(v);
    std::sort(sorted_.begin(), sorted_.end(),
              [this](std::uint32_t a, std::uint32_t b) { return found_key_[a] < found_key_[b]; });
  }
  renumber_.resize(num_voxels);
  column_.resize(num_voxels);
  iz_.resize(num_voxels);
  centroid_.resize(num_voxels);
  count_.resize(num_voxels);
  for (std::size_t r = 0; r < num_voxels; ++r) {
    const std::uint32_t found = sorted_[r];
    renumber_[found] = static_cast<std::uint32_t>(r);
    column_[r] = found_column_[found];
    iz_[r] = static_cast<std::int32_t>(found_iz_[found]);
    count_[r] = found_count_[found];
    centroid_[r] = (found_sum_[found] / static_cast<double>(count_[r])).cast<float>();
  }
  parallel::forShares(point_voxel_.size(), parallel::resolve(threads), std::size_t{1} << 15,
                      [this](int /*share*/, std::size_t begin, std::size_t end) {
                        for (std::size_t i = begin; i < end; ++i) {
                          const std::int32_t found = point_voxel_[i];
                          if (found >= 0) {
                            point_voxel_[i] = static_cast<std::int32_t>(renumber_[found]);
                          }
                        }
                      });

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
