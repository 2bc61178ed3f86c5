#include "hope/fringe_reclustering.h"

#include <utility>

#include "hope/pca_refinement.h"
#include "hope/plane_description.h"
#include "hope/z_clustering.h"

namespace hope {

std::size_t reclusterCutOffFringe(const VoxelGrid& grid, const AlignedPoints& aligned,
                                  const std::vector<Eigen::Vector3f>& normals,
                                  const std::vector<std::uint8_t>& is_candidate,
                                  const std::vector<VoxelLink>& links,
                                  const std::vector<std::int32_t>& owner_before,
                                  const Params& params, std::vector<std::int32_t>& voxel_plane,
                                  std::vector<Surface>& surfaces) {
  std::vector<std::uint8_t> trimmed(grid.numVoxels(), 0);
  for (std::size_t v = 0; v < trimmed.size(); ++v) {
    trimmed[v] = owner_before[v] >= 0 && voxel_plane[v] < 0 && is_candidate[v];
  }
  // Whether `v` lies in or beside (4-adjacent column) a voxel of the surface it was cut from.
  auto besideItsOrigin = [&](std::uint32_t v) {
    const int cx = grid.cellX(v), cy = grid.cellY(v);
    const int offsets[5][2] = {{0, 0}, {1, 0}, {-1, 0}, {0, 1}, {0, -1}};
    for (const auto& d : offsets) {
      const auto range = grid.columnVoxels(cx + d[0], cy + d[1]);
      for (std::uint32_t u = range.first; u < range.second; ++u) {
        if (voxel_plane[u] >= 0 && voxel_plane[u] == owner_before[v]) return true;
      }
    }
    return false;
  };
  const double gamma = params.gamma();
  std::size_t appended = 0;
  for (std::vector<std::uint32_t>& cluster :
       zClustering(grid, trimmed, params.r_z, params.min_cluster_voxels, links)) {
    std::size_t beside = 0;
    for (std::uint32_t v : cluster) beside += besideItsOrigin(v) ? 1 : 0;
    if (2 * beside > cluster.size()) continue;
    const RefinementVerdict verdict = refineWithPCA(normals, cluster, gamma);
    if (!verdict.horizontal || footprintMinorVariance(grid, cluster) < kMinFootprintVariance) {
      continue;
    }
    Surface surface{describePlane(grid, aligned, cluster, Detail::kVoxels), std::move(cluster)};
    if (surface.plane.tilt > params.maxSlope()) continue;
    surface.plane.mean_normal_tilt = verdict.mean_tilt;
    surface.plane.group_angle = verdict.group_angle;
    for (std::uint32_t v : surface.voxels)
      voxel_plane[v] = static_cast<std::int32_t>(surfaces.size());
    surfaces.push_back(std::move(surface));
    ++appended;
  }
  return appended;
}

}  // namespace hope
