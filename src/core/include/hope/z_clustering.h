// Z clustering (paper §2.3): region growing over the horizontal candidates in which a voxel
// joins a neighbour in the 8-connected grid neighbourhood (and its own column) when their
// heights differ by less than r_z. Normals are not compared again: every candidate already
// passed Eq 3. Links from the scan-gap bridging (scan_gap_bridging.h) join voxels across the
// gaps between a LiDAR's rings under the same height rule.
#pragma once

#include <cstdint>
#include <vector>

#include "hope/grid_filter.h"
#include "hope/scan_gap_bridging.h"

namespace hope {

// Returns clusters of voxel indices, in the order their seeds appear in the grid; clusters
// with fewer than `min_voxels` voxels are dropped.
std::vector<std::vector<std::uint32_t>> zClustering(const VoxelGrid& grid,
                                                    const std::vector<std::uint8_t>& is_candidate,
                                                    double r_z, int min_voxels,
                                                    const std::vector<VoxelLink>& links = {});

}  // namespace hope
