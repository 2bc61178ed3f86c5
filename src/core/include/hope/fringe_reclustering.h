// Part of surface completion (fragment_merging.h, a departure from the paper). What the
// completion cut off a surface is not noise when it is a surface itself: a kerb's top joined
// to the road through the kerb's face, a driveway climbing away from the road's plane. Those
// voxels are clustered (Z clustering, §2.3) and refined (§2.4) again, and each accepted
// cluster becomes a surface of its own — unless it lies among the surface it was cut from
// (most of its voxels beside that surface's), which makes it that surface's noisy fringe.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "hope/grid_filter.h"
#include "hope/params.h"
#include "hope/points_view.h"
#include "hope/scan_gap_bridging.h"
#include "hope/surface_assembly.h"

namespace hope {

// `owner_before`: each voxel's surface before the completion; `voxel_plane`: after it (both
// surface indices, -1 for none). The cut-off candidates (owned before, not after, and passed
// Eq 3) are re-clustered; each new surface is appended to `surfaces` and marked in
// `voxel_plane`. Returns how many were appended.
std::size_t reclusterCutOffFringe(const VoxelGrid& grid, const AlignedPoints& aligned,
                                  const std::vector<Eigen::Vector3f>& normals,
                                  const std::vector<std::uint8_t>& is_candidate,
                                  const std::vector<VoxelLink>& links,
                                  const std::vector<std::int32_t>& owner_before,
                                  const Params& params, std::vector<std::int32_t>& voxel_plane,
                                  std::vector<Surface>& surfaces);

}  // namespace hope
