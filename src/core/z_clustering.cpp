#include "hope/z_clustering.h"

#include <cmath>

namespace hope {

namespace {

// Three columns holding up to this many voxels are scanned whole; taller ones (a wall, an
// object's side) are searched column by column from the voxel's z cell.
constexpr std::uint32_t kScannedRow = 3 * VoxelGrid::kShortColumn;

}  // namespace

std::vector<std::vector<std::uint32_t>> zClustering(const VoxelGrid& grid,
                                                    const std::vector<std::uint8_t>& is_candidate,
                                                    double r_z, int min_voxels,
                                                    const std::vector<VoxelLink>& links) {
  std::vector<std::vector<std::uint32_t>> clusters;
  const std::size_t num_voxels = grid.numVoxels();
  // The links as an adjacency list in both directions (compressed rows).
  std::vector<std::uint32_t> link_begin, link_target;
  if (!links.empty()) {
    link_begin.assign(num_voxels + 1, 0);
    for (const VoxelLink& link : links) {
      ++link_begin[link.first + 1];
      ++link_begin[link.second + 1];
    }
    for (std::size_t v = 1; v <= num_voxels; ++v) link_begin[v] += link_begin[v - 1];
    link_target.resize(2 * links.size());
    std::vector<std::uint32_t> fill(link_begin.begin(), link_begin.end() - 1);
    for (const VoxelLink& link : links) {
      link_target[fill[link.first]++] = link.second;
      link_target[fill[link.second]++] = link.first;
    }
  }
  std::vector<std::uint8_t> visited(num_voxels, 0);
  std::vector<std::uint32_t> members;
  const float max_step = static_cast<float>(r_z);
  const bool dense = grid.denseColumns();

  for (std::size_t seed = 0; seed < num_voxels; ++seed) {
    if (!is_candidate[seed] || visited[seed]) continue;
    members.clear();
    members.push_back(static_cast<std::uint32_t>(seed));
    visited[seed] = 1;
    // `members` doubles as the region-growing queue.
    for (std::size_t head = 0; head < members.size(); ++head) {
      const std::uint32_t v = members[head];
      const float z = grid.centroid(v).z();
      const int cx = grid.cellX(v), cy = grid.cellY(v), cz = grid.cellZ(v);
      // Centroids less than r_z apart are at most one z cell apart.
      auto consider = [&](std::uint32_t u) {
        if (visited[u] || !is_candidate[u]) return;
        if (std::fabs(grid.centroid(u).z() - z) >= max_step) return;
        visited[u] = 1;
        members.push_back(u);
      };
      for (int dy = -1; dy <= 1; ++dy) {
        if (dense) {
          // The row's three columns in one range, in the same order as column by column.
          const auto row = grid.rowVoxels(cx - 1, cx + 1, cy + dy);
          if (row.second - row.first <= kScannedRow) {
            for (std::uint32_t u = row.first; u < row.second; ++u) {
              if (grid.cellZ(u) >= cz - 1 && grid.cellZ(u) <= cz + 1) consider(u);
            }
            continue;
          }
        }
        for (int dx = -1; dx <= 1; ++dx) {
          const auto range = grid.columnVoxels(cx + dx, cy + dy);
          for (std::uint32_t u = grid.firstAtOrAbove(range, cz - 1); u < range.second; ++u) {
            if (grid.cellZ(u) > cz + 1) break;
            consider(u);
          }
        }
      }
      if (link_begin.empty()) continue;
      for (std::uint32_t k = link_begin[v]; k < link_begin[v + 1]; ++k) {
        const std::uint32_t u = link_target[k];
        if (visited[u] || !is_candidate[u]) continue;
        if (std::fabs(grid.centroid(u).z() - z) >= max_step) continue;
        visited[u] = 1;
        members.push_back(u);
      }
    }
    if (static_cast<int>(members.size()) >= min_voxels) clusters.push_back(members);
  }
  return clusters;
}

}  // namespace hope
