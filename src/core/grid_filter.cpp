#include "hope/grid_filter.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "parallel.h"
#include "simd.h"

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
  // Every entry is written by the point pass (-1 for non-finite points), or below when no
  // point is finite.
  point_entry_.resize(n);
  centroid_.clear();
  column_.clear();
  cell_x_.clear();
  cell_y_.clear();
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
  if (m == 0) {
    point_entry_.assign(n, -1);
    return;
  }

  origin_ = lo.cast<double>();
  const Eigen::Vector3d extent = hi.cast<double>() - origin_;
  extent_ = extent;
  std::uint64_t nz = 1;
  try {
    nx_ = cellCount(extent.x(), r_xy, "x", "r_xy");
    ny_ = cellCount(extent.y(), r_xy, "y", "r_xy");
    nz = cellCount(extent.z(), r_z, "z", "r_z");
  } catch (...) {
    // Left as an empty grid: the points' entries of the previous cloud must not be read
    // through this one's tables (pointVoxels()).
    point_entry_.assign(n, -1);
    nx_ = ny_ = 1;
    extent_.setZero();
    throw;
  }

  assignPointsToVoxels(aligned, nz, parallel::resolve(hints.threads));
  orderVoxels(nx_ * ny_ <= denseColumnLimit(m));
}

namespace {

constexpr std::uint64_t kEmptySlot = std::numeric_limits<std::uint64_t>::max();
constexpr std::size_t kRecentVoxels = 4096;  // a power of two

// Fibonacci hashing: spreads consecutive keys (neighbouring z cells) over the table.
std::size_t slotOf(std::uint64_t key, std::size_t mask) {
  return static_cast<std::size_t>((key * 0x9E3779B97F4A7C15ull) >> 20) & mask;
}

// The cell arithmetic of the point pass. assignRange copies it into locals: through a
// reference the compiler would reload every field after each store into the tables.
struct CellMath {
  double ox, oy, oz, inv_xy, inv_z;
  std::uint64_t nx, ny, nz;
};

// A point's cell along one axis before the clamp to the last cell: (p - origin) / leaf
// truncated. Every finite point lies in the box the origin comes from, so the quotient is
// never negative and, by the kMaxCellsPerAxis check, far below 2^31: truncating it to 32 bits
// gives what truncating to 64 bits did. A NaN or infinite coordinate gives INT32_MIN (the
// SSE2 conversion's "integer indefinite", mimicked here), so the sign of the cells is the
// finiteness test as well.
inline std::int32_t truncatedCell(double quotient) {
  return quotient >= 0.0 && quotient < 2147483648.0 ? static_cast<std::int32_t>(quotient)
                                                    : std::numeric_limits<std::int32_t>::min();
}

// Assigns the points [begin, end) to voxels of `list` through `index`, writing the list's
// voxel numbers to point_voxel, counting and summing each voxel's points in input order.
// Points that follow each other in a scan or an image mostly share a voxel, so the loop is
// built around that case: a point whose unclamped cells (x and y packed in one word, z) are
// those of the point before joins the current run with one comparison, and only a change of
// cells pays for the finiteness test, the clamp, the key and the lookup (the last voxel's key
// first, then recently seen voxels, and only then the hash table). (A table of the voxels of
// the row above, for organized clouds, cost more than it saved: the recent voxels hold most of
// them, and it took a store per point and a branch per voxel change.) Everything the loop
// touches per point lives in locals: a store through point_voxel or into a table could
// otherwise alias a member, and the compiler would reload them after every point. The current
// voxel's count and coordinate sums are carried in registers while its run of points lasts,
// starting from (and written back to) its stored totals, so each voxel's points are still added
// one by one in input order.
void assignRange(const AlignedPoints& aligned, std::size_t begin, std::size_t end,
                 const CellMath& g, detail::VoxelIndex& index, detail::VoxelList& list,
                 std::int32_t* point_voxel) {
  const std::uint8_t* data = aligned.data;
  const std::size_t stride = aligned.stride;
  const double oz = g.oz, inv_z = g.inv_z;
  const std::uint64_t nx = g.nx, nz = g.nz, last_x = g.nx - 1, last_y = g.ny - 1, last_z = g.nz - 1;
#if HOPE_SSE2
  const __m128d origin_xy = _mm_set_pd(g.oy, g.ox);
  const __m128d inverse_xy = _mm_set1_pd(g.inv_xy);
#else
  const double ox = g.ox, oy = g.oy, inv_xy = g.inv_xy;
#endif
  // The unclamped cells of the current run; no point has these (its cells are >= 0, or
  // INT32_MIN where a coordinate is not finite).
  std::int64_t run_cells_xy = -1;
  std::int32_t run_cell_z = -1;
  std::uint64_t last_key = kEmptySlot;
  std::uint32_t last_voxel = 0, run = 0;
  double sum_x = 0, sum_y = 0, sum_z = 0;
  auto storeRun = [&]() {
    if (run == 0) return;
    list.count[last_voxel] += run;
    list.sum[last_voxel] = Eigen::Vector3d(sum_x, sum_y, sum_z);
  };
  for (std::size_t i = begin; i < end; ++i) {
    const std::uint8_t* record = data + i * stride;
    std::int64_t xy_bits;  // x and y, two float32
    float z_float;
    std::memcpy(&xy_bits, record, sizeof(xy_bits));
    std::memcpy(&z_float, record + sizeof(xy_bits), sizeof(z_float));
    const double pz = z_float;
#if HOPE_SSE2
    const __m128d pxy = _mm_cvtps_pd(_mm_castsi128_ps(_mm_cvtsi64_si128(xy_bits)));
    const __m128i cells = _mm_cvttpd_epi32(_mm_mul_pd(_mm_sub_pd(pxy, origin_xy), inverse_xy));
    const std::int64_t cells_xy = _mm_cvtsi128_si64(cells);  // x cell in the low half
    const std::int32_t cell_z = _mm_cvttsd_si32(_mm_set_sd((pz - oz) * inv_z));
    const double px = _mm_cvtsd_f64(pxy), py = _mm_cvtsd_f64(_mm_unpackhi_pd(pxy, pxy));
#else
    float xy[2];
    std::memcpy(xy, &xy_bits, sizeof(xy));
    const double px = xy[0], py = xy[1];
    const std::int64_t cells_xy = static_cast<std::int64_t>(
        (static_cast<std::uint64_t>(static_cast<std::uint32_t>(truncatedCell((py - oy) * inv_xy)))
         << 32) |
        static_cast<std::uint32_t>(truncatedCell((px - ox) * inv_xy)));
    const std::int32_t cell_z = truncatedCell((pz - oz) * inv_z);
#endif
    if (((cells_xy ^ run_cells_xy) | (cell_z ^ run_cell_z)) != 0) {
      const auto cell_x = static_cast<std::int32_t>(cells_xy & 0xffffffff);
      const auto cell_y = static_cast<std::int32_t>(cells_xy >> 32);
      if ((cell_x | cell_y | cell_z) < 0) {  // NaN or infinite
        point_voxel[i] = -1;
        continue;
      }
      run_cells_xy = cells_xy;
      run_cell_z = cell_z;
      // Clamped to the last cell: in floating point a point at the box's far side can land
      // exactly on the cell count.
      const std::uint64_t ix = std::min(static_cast<std::uint64_t>(cell_x), last_x);
      const std::uint64_t iy = std::min(static_cast<std::uint64_t>(cell_y), last_y);
      const std::uint64_t iz = std::min(static_cast<std::uint64_t>(cell_z), last_z);
      const std::uint64_t column = ix + nx * iy;
      const std::uint64_t key = column * nz + iz;  // < 2^42 · 2^21
      if (key != last_key) {
        storeRun();
        last_key = key;
        // Noise makes neighbouring points alternate between a few voxels of one column:
        // recently seen voxels are kept in a small direct-mapped table (fits the L2 cache) in
        // front of the large hash table.
        auto& recent = index.recent[key & (kRecentVoxels - 1)];
        if (recent.first != key) recent = {key, index.voxelOf(key, column, iz, list)};
        last_voxel = recent.second;
        const Eigen::Vector3d& stored = list.sum[last_voxel];
        sum_x = stored.x(), sum_y = stored.y(), sum_z = stored.z();
        run = 0;
      }
    }
    point_voxel[i] = static_cast<std::int32_t>(last_voxel);
    ++run;
    sum_x += px, sum_y += py, sum_z += pz;
  }
  storeRun();
}

}  // namespace

namespace detail {

void VoxelList::clear() {
  key.clear();
  column.clear();
  iz.clear();
  count.clear();
  sum.clear();
}

void VoxelList::append(const VoxelList& other) {
  key.insert(key.end(), other.key.begin(), other.key.end());
  column.insert(column.end(), other.column.begin(), other.column.end());
  iz.insert(iz.end(), other.iz.begin(), other.iz.end());
  count.insert(count.end(), other.count.begin(), other.count.end());
  sum.insert(sum.end(), other.sum.begin(), other.sum.end());
}

void VoxelIndex::reset() {
  if (slot_key.empty()) {
    slot_key.assign(4096, kEmptySlot);
    slot_voxel.assign(4096, 0);
  }
  // Only the slots in use are cleared: the table keeps the size the largest list needed.
  for (const std::uint32_t slot : voxel_slot) slot_key[slot] = kEmptySlot;
  voxel_slot.clear();
  recent.assign(kRecentVoxels, {kEmptySlot, 0});
}

std::uint32_t VoxelIndex::voxelOf(std::uint64_t k, std::uint64_t c, std::uint64_t z,
                                  VoxelList& list) {
  const std::size_t mask = slot_key.size() - 1;
  std::size_t slot = slotOf(k, mask);
  while (slot_key[slot] != kEmptySlot) {
    if (slot_key[slot] == k) return slot_voxel[slot];
    slot = (slot + 1) & mask;
  }
  const auto voxel = static_cast<std::uint32_t>(list.key.size());
  slot_key[slot] = k;
  slot_voxel[slot] = voxel;
  voxel_slot.push_back(static_cast<std::uint32_t>(slot));
  list.key.push_back(k);
  list.column.push_back(c);
  list.iz.push_back(static_cast<std::uint32_t>(z));
  list.count.push_back(0);
  list.sum.push_back(Eigen::Vector3d::Zero());
  if (2 * voxel_slot.size() > slot_key.size()) grow();  // keep probes short
  return voxel;
}

void VoxelIndex::grow() {
  std::vector<std::uint64_t> keys(voxel_slot.size());
  for (std::size_t v = 0; v < voxel_slot.size(); ++v) keys[v] = slot_key[voxel_slot[v]];
  slot_key.assign(2 * slot_key.size(), kEmptySlot);
  slot_voxel.assign(slot_key.size(), 0);
  const std::size_t mask = slot_key.size() - 1;
  for (std::size_t v = 0; v < keys.size(); ++v) {
    std::size_t slot = slotOf(keys[v], mask);
    while (slot_key[slot] != kEmptySlot) slot = (slot + 1) & mask;
    slot_key[slot] = keys[v];
    slot_voxel[slot] = static_cast<std::uint32_t>(v);
    voxel_slot[v] = static_cast<std::uint32_t>(slot);
  }
}

}  // namespace detail

void VoxelGrid::assignPointsToVoxels(const AlignedPoints& aligned, std::uint64_t nz, int threads) {
  const CellMath g{origin_.x(), origin_.y(), origin_.z(), 1.0 / r_xy_, 1.0 / r_z_, nx_, ny_, nz};
  const std::size_t n = aligned.size();
  const std::size_t num_chunks = (n + kPointsPerChunk - 1) / kPointsPerChunk;
  if (chunks_.size() < num_chunks) chunks_.resize(num_chunks);
  const int workers = static_cast<int>(
      std::min<std::size_t>(std::max(1, threads), std::max<std::size_t>(1, num_chunks)));
  if (indexes_.size() < static_cast<std::size_t>(workers)) {
    indexes_.resize(static_cast<std::size_t>(workers));
  }
  // Each worker takes a contiguous run of chunks, each chunk on the worker's own index.
  parallel::forShares(num_chunks, workers, 1, [&](int worker, std::size_t first, std::size_t last) {
    detail::VoxelIndex& index = indexes_[static_cast<std::size_t>(worker)];
    for (std::size_t c = first; c < last; ++c) {
      detail::VoxelList& list = chunks_[c];
      list.clear();
      index.reset();
      const std::size_t begin = c * kPointsPerChunk;
      assignRange(aligned, begin, std::min(n, begin + kPointsPerChunk), g, index, list,
                  point_entry_.data());
    }
  });
  // Every chunk's voxels side by side: entry chunk_begin_[c] + local is voxel `local` of chunk c.
  chunk_begin_.resize(num_chunks + 1);
  chunk_begin_[0] = 0;
  for (std::size_t c = 0; c < num_chunks; ++c) {
    chunk_begin_[c + 1] = chunk_begin_[c] + static_cast<std::uint32_t>(chunks_[c].size());
  }
}

// Entries sorted by key, ties in entry (chunk) order: a least-significant-digit radix sort,
// stable, 11 bits a pass and as many passes as the largest key needs. Linear in the entries
// whatever the grid's size: a counting sort by column would sweep every column of a sparse
// LiDAR grid (hundreds of thousands for ~20,000 voxels).
void VoxelGrid::sortEntriesByKey() {
  constexpr int kDigitBits = 11;
  constexpr std::size_t kBuckets = std::size_t{1} << kDigitBits;
  const std::size_t num_entries = entries_.size();
  sorted_.resize(num_entries);
  for (std::size_t e = 0; e < num_entries; ++e) sorted_[e] = static_cast<std::uint32_t>(e);
  std::uint64_t max_key = 0;
  for (const std::uint64_t key : entries_.key) max_key = std::max(max_key, key);
  by_digit_.resize(num_entries);
  counts_.resize(kBuckets);
  for (int shift = 0; shift < 64 && (max_key >> shift) != 0; shift += kDigitBits) {
    std::fill(counts_.begin(), counts_.end(), 0);
    for (const std::uint32_t e : sorted_) ++counts_[(entries_.key[e] >> shift) & (kBuckets - 1)];
    std::uint32_t offset = 0;
    for (std::uint32_t& count : counts_) {
      const std::uint32_t bucket_size = count;
      count = offset;
      offset += bucket_size;
    }
    for (const std::uint32_t e : sorted_) {
      by_digit_[counts_[(entries_.key[e] >> shift) & (kBuckets - 1)]++] = e;
    }
    sorted_.swap(by_digit_);
  }
}

// The chunks' voxels sorted by key, i.e. by column (x-major within each row of y) and inside a
// column by z cell, entries of one key in chunk order; runs of one key become one voxel, its
// counts and sums added in chunk order. The points keep their chunk's numbers (PointVoxels).
void VoxelGrid::orderVoxels(bool dense_columns) {
  const std::size_t num_chunks = chunk_begin_.size() - 1;
  const std::size_t num_entries = chunk_begin_[num_chunks];
  entries_.clear();
  for (std::size_t c = 0; c < num_chunks; ++c) entries_.append(chunks_[c]);
  sortEntriesByKey();
  // A run of one key is one voxel.
  entry_voxel_.resize(num_entries);
  column_.resize(num_entries);
  iz_.resize(num_entries);
  count_.resize(num_entries);
  sums_.resize(num_entries);
  std::size_t num_voxels = 0;
  for (std::size_t r = 0; r < num_entries; ++r) {
    const std::uint32_t e = sorted_[r];
    if (r == 0 || entries_.key[e] != entries_.key[sorted_[r - 1]]) {
      column_[num_voxels] = entries_.column[e];
      iz_[num_voxels] = static_cast<std::int32_t>(entries_.iz[e]);
      count_[num_voxels] = 0;
      sums_[num_voxels] = Eigen::Vector3d::Zero();
      ++num_voxels;
    }
    count_[num_voxels - 1] += entries_.count[e];
    sums_[num_voxels - 1] += entries_.sum[e];
    entry_voxel_[e] = static_cast<std::uint32_t>(num_voxels - 1);
  }
  column_.resize(num_voxels);
  iz_.resize(num_voxels);
  count_.resize(num_voxels);
  centroid_.resize(num_voxels);
  cell_x_.resize(num_voxels);
  cell_y_.resize(num_voxels);
  for (std::size_t v = 0; v < num_voxels; ++v) {
    centroid_[v] = (sums_[v] / static_cast<double>(count_[v])).cast<float>();
    cell_x_[v] = static_cast<std::int32_t>(column_[v] % nx_);
    cell_y_[v] = static_cast<std::int32_t>(column_[v] / nx_);
  }
  if (dense_columns) {
    // Column c's voxels begin at the first voxel of a column >= c: one write per column.
    const std::size_t num_columns = static_cast<std::size_t>(nx_ * ny_);
    dense_column_begin_.resize(num_columns + 1);
    std::size_t c = 0;
    for (std::size_t v = 0; v < num_voxels; ++v) {
      while (c <= column_[v]) dense_column_begin_[c++] = static_cast<std::uint32_t>(v);
    }
    while (c <= num_columns) dense_column_begin_[c++] = static_cast<std::uint32_t>(num_voxels);
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

std::vector<std::int32_t> VoxelGrid::pointVoxel() const {
  const PointVoxels voxels = pointVoxels();
  std::vector<std::int32_t> out(voxels.size());
  for (std::size_t i = 0; i < out.size(); ++i) out[i] = voxels[i];
  return out;
}

std::pair<std::uint32_t, std::uint32_t> VoxelGrid::sparseColumnVoxels(std::uint64_t c) const {
  const auto it = sparse_columns_.find(c);
  return it == sparse_columns_.end() ? std::pair<std::uint32_t, std::uint32_t>{0, 0} : it->second;
}

}  // namespace hope
