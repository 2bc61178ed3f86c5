// From refined clusters to surfaces, the steps between the paper's refinement (§2.4) and the
// description of the kept planes: each cluster described as a fragment, the fragments of one
// surface joined (fragment_merging.h), every surface completed over the rim its objects cut
// out of it and what the completion cut off re-clustered (fringe_reclustering.h), then the
// height band and the minimum area applied. With the merge off (the paper's pipeline) each
// accepted cluster is a surface of its own.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "hope/fragment_merging.h"
#include "hope/grid_filter.h"
#include "hope/params.h"
#include "hope/pca_refinement.h"
#include "hope/plane.h"
#include "hope/points_view.h"
#include "hope/scan_gap_bridging.h"

namespace hope {

// A surface: its plane (in the grid's coordinates) and the voxels it owns.
struct Surface {
  HorizontalPlane plane;
  std::vector<std::uint32_t> voxels;
};

// What the assembly tells the Result.
struct AssemblyCounts {
  std::size_t rejected_by_refinement = 0;  // refined clusters that are part of no surface
  std::size_t merged_fragments = 0;        // fragments joined to another one's surface
  std::size_t fringe_clusters = 0;         // surfaces found in what the completion cut off
};

// Each refined cluster (refineClusters) described from its voxels as a fragment, with its
// verdict's angles. With the merge off only the accepted ones are
// kept; with it on the rejected ones too (they may join an accepted surface). A fragment whose
// fitted plane is steeper than the accepted slope is rejected: grid normals underestimate
// slopes just steeper than atan γ (Z clustering cuts them into level strips), and the fit over
// the whole strip sees what the normals miss. The clusters are described in parallel.
std::vector<Fragment> describeFragments(const VoxelGrid& grid, const AlignedPoints& aligned,
                                        const std::vector<std::vector<std::uint32_t>>& clusters,
                                        const ClusterRefinement& refinement, const Params& params,
                                        int threads, AssemblyCounts& counts);

// The surfaces: one per group of `groupFragments` with at least one accepted fragment (a
// rejected one never stands alone), measured again from its voxels when it has several parts.
// With the merge on, each surface is then completed (completeSurface) and what the completion
// cut off is re-clustered (reclusterCutOffFringe). `voxel_plane` (one entry per voxel) gets
// each voxel's surface index, -1 for none.
std::vector<Surface> assembleSurfaces(const VoxelGrid& grid, const AlignedPoints& aligned,
                                      const std::vector<Eigen::Vector3f>& normals,
                                      const std::vector<std::uint8_t>& is_candidate,
                                      const std::vector<VoxelLink>& links,
                                      std::vector<Fragment>& fragments,
                                      const std::vector<std::vector<std::size_t>>& groups,
                                      const Params& params, std::vector<std::int32_t>& voxel_plane,
                                      AssemblyCounts& counts);

// With the merge on: every surface measured again from its voxels, now that the merge joined
// and completed it (the parts' count and the refinement angles kept). In parallel.
void redescribeSurfaces(const VoxelGrid& grid, const AlignedPoints& aligned,
                        std::vector<Surface>& surfaces, int threads);

// The surfaces inside the height band and of the minimum area (heights in the reference
// frame: the grid's plus `origin_z`), in order: they become the planes 0, 1, … .
// `voxel_plane` is renumbered from surfaces to kept planes (-1 for a dropped surface's
// voxels); `dropped` counts the surfaces left out.
struct KeptSurfaces {
  std::vector<const std::vector<std::uint32_t>*> voxels;
  std::vector<HorizontalPlane*> planes;
};
KeptSurfaces keepInBandAndArea(std::vector<Surface>& surfaces, double origin_z,
                               const Params& params, std::vector<std::int32_t>& voxel_plane,
                               std::size_t& dropped);

}  // namespace hope
