#include "hope/surface_assembly.h"

#include <utility>

#include "hope/fringe_reclustering.h"
#include "hope/plane_description.h"
#include "parallel.h"

namespace hope {

std::vector<Fragment> describeFragments(const VoxelGrid& grid, const AlignedPoints& aligned,
                                        const std::vector<std::vector<std::uint32_t>>& clusters,
                                        const ClusterRefinement& refinement, const Params& params,
                                        int threads, AssemblyCounts& counts) {
  // In the grid's coordinates (the merge works there), each cluster on its own, in parallel,
  // then taken in order. Every surface is measured in full (its points' bbox and hull) only
  // once it is complete.
  const bool merge = params.merge_fragments;
  std::vector<HorizontalPlane> descriptions(clusters.size());
  parallel::forEach(clusters.size(), threads, [&](std::size_t c) {
    if (!refinement.accepted[c] && !merge) return;
    descriptions[c] = describePlane(grid, aligned, clusters[c], Detail::kVoxels);
  });
  std::vector<Fragment> fragments;
  for (std::size_t c = 0; c < clusters.size(); ++c) {
    if (!refinement.accepted[c] && !merge) continue;
    Fragment fragment{std::move(descriptions[c]), &clusters[c], refinement.accepted[c] != 0};
    if (fragment.plane.tilt > params.maxSlope()) fragment.accepted = false;
    if (!fragment.accepted && !merge) continue;
    fragment.plane.mean_normal_tilt = refinement.verdicts[c].mean_tilt;
    fragment.plane.group_angle = refinement.verdicts[c].group_angle;
    fragments.push_back(std::move(fragment));
  }
  std::size_t accepted = 0;
  for (const Fragment& f : fragments) accepted += f.accepted ? 1 : 0;
  counts.rejected_by_refinement = clusters.size() - accepted;
  return fragments;
}

std::vector<Surface> assembleSurfaces(const VoxelGrid& grid, const AlignedPoints& aligned,
                                      const std::vector<Eigen::Vector3f>& normals,
                                      const std::vector<std::uint8_t>& is_candidate,
                                      const std::vector<VoxelLink>& links,
                                      std::vector<Fragment>& fragments,
                                      const std::vector<std::vector<std::size_t>>& groups,
                                      const Params& params, std::vector<std::int32_t>& voxel_plane,
                                      AssemblyCounts& counts) {
  std::vector<Surface> surfaces;
  voxel_plane.assign(grid.numVoxels(), -1);
  for (const std::vector<std::size_t>& group : groups) {
    const std::size_t largest = representative(fragments, group);
    if (!fragments[largest].accepted) continue;
    Surface surface;
    for (std::size_t k : group) {
      surface.voxels.insert(surface.voxels.end(), fragments[k].voxels->begin(),
                            fragments[k].voxels->end());
      // A rejected fragment that joined an accepted surface is part of a plane after all.
      if (!fragments[k].accepted) --counts.rejected_by_refinement;
    }
    if (group.size() == 1) {
      surface.plane = std::move(fragments[largest].plane);
    } else {
      surface.plane = describePlane(grid, aligned, surface.voxels, Detail::kVoxels);
      surface.plane.num_parts = static_cast<int>(group.size());
      // The refinement angles of the largest accepted part.
      surface.plane.mean_normal_tilt = fragments[largest].plane.mean_normal_tilt;
      surface.plane.group_angle = fragments[largest].plane.group_angle;
      counts.merged_fragments += group.size() - 1;
    }
    for (std::uint32_t v : surface.voxels)
      voxel_plane[v] = static_cast<std::int32_t>(surfaces.size());
    surfaces.push_back(std::move(surface));
  }
  if (params.merge_fragments) {
    // Completion once every surface owns its voxels, so that no surface grows into another.
    const std::vector<std::int32_t> owner_before = voxel_plane;
    for (std::size_t k = 0; k < surfaces.size(); ++k) {
      completeSurface(grid, normals, surfaces[k].plane, params.r_z, static_cast<std::int32_t>(k),
                      voxel_plane, surfaces[k].voxels);
    }
    counts.fringe_clusters = reclusterCutOffFringe(grid, aligned, normals, is_candidate, links,
                                                   owner_before, params, voxel_plane, surfaces);
  }
  return surfaces;
}

void redescribeSurfaces(const VoxelGrid& grid, const AlignedPoints& aligned,
                        std::vector<Surface>& surfaces, int threads) {
  parallel::forEach(surfaces.size(), threads, [&](std::size_t k) {
    Surface& surface = surfaces[k];
    HorizontalPlane again = describePlane(grid, aligned, surface.voxels, Detail::kVoxels);
    again.num_parts = surface.plane.num_parts;
    again.mean_normal_tilt = surface.plane.mean_normal_tilt;
    again.group_angle = surface.plane.group_angle;
    surface.plane = std::move(again);
  });
}

KeptSurfaces keepInBandAndArea(std::vector<Surface>& surfaces, double origin_z,
                               const Params& params, std::vector<std::int32_t>& voxel_plane,
                               std::size_t& dropped) {
  // Both known from the voxels (heights as HorizontalPlane::translate makes them): the voxels
  // of a dropped surface belong to no plane, and only the kept surfaces are measured in full.
  KeptSurfaces kept;
  std::vector<std::int32_t> plane_of_surface(surfaces.size(), -1);
  for (std::size_t k = 0; k < surfaces.size(); ++k) {
    const HorizontalPlane& plane = surfaces[k].plane;
    const double height = plane.height + origin_z;
    if (height < params.min_height || height > params.max_height || plane.area < params.min_area) {
      ++dropped;
      continue;
    }
    plane_of_surface[k] = static_cast<std::int32_t>(kept.planes.size());
    kept.voxels.push_back(&surfaces[k].voxels);
    kept.planes.push_back(&surfaces[k].plane);
  }
  for (std::int32_t& owner : voxel_plane) {
    if (owner >= 0) owner = plane_of_surface[static_cast<std::size_t>(owner)];
  }
  return kept;
}

}  // namespace hope
