// Fragment merging — a departure from the paper, which defines a plane as one connected region
// of the grid. In a cluttered scene the objects standing on a table, and the shadows they cast
// from the sensor's point of view, cut the table top into several connected regions; a floor
// seen past a chair or a person falls apart the same way. A robot means the surface, so after
// the refinement (§2.4) the fragments of one surface are joined again.
//
// Two planes are fragments of one surface when
//  - their heights agree within r_z (the larger plane's fitted plane, evaluated at the smaller
//    one's centroid, so that a slightly tilted reference frame does not split a long floor),
//    and their normals within atan(r_z / r_xy), the accepted slope;
//  - a path of at most max_merge_gap metres leads from one to the other through cells that
//    are consistent with one continuous surface: the surface itself seen there (voxels at its
//    height that did not make it into a plane), something standing on it or in front of it
//    (points between the sensor and the surface), or the shadow such a thing casts on it;
//  - and no cell on that path shows a real gap: a return from beyond the surface on a ray
//    that crosses the surface's height in that cell (the floor seen between two tables).
// Without a viewpoint (a z-up cloud whose sensor position is unknown) shadows cannot be told
// from empty space: only cells with the surface or something above it in their column are
// passable, and points below it in a column mark a gap.
// The test works on the voxel grid, not the points, and on one small raster per group of
// compatible planes, so it costs a fraction of the pipeline.
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include <Eigen/Core>

#include "hope/grid_filter.h"
#include "hope/params.h"
#include "hope/plane.h"

namespace hope {

// One connected region of the grid that passed Z clustering, described.
struct Fragment {
  HorizontalPlane plane;                     // in the grid's coordinates
  const std::vector<std::uint32_t>* voxels;  // its cluster
  // Passed the refinement (§2.4). A rejected cluster — typically a sliver of a table cut off
  // by an object, too small for its edge normals to look flat — may join an accepted surface
  // when its voxels lie on that surface's plane (all within r_z, 80 % within r_z / 2), but
  // never stands alone.
  bool accepted = true;
};

// Groups of indices into `fragments` that are parts of one surface (each group sorted, the
// groups ordered by their first index; a fragment merged with nothing is a group of one).
// `viewpoint` is in the grid's coordinates (aligned points minus the local origin).
std::vector<std::vector<std::size_t>> groupFragments(
    const VoxelGrid& grid, const std::vector<Fragment>& fragments,
    const std::optional<Eigen::Vector3d>& viewpoint, const Params& params);

// The fragment of `group` that stands for the surface: the accepted one with the largest
// footprint (the best estimate of the surface), or the first when none is accepted (such a
// group never becomes a plane).
std::size_t representative(const std::vector<Fragment>& fragments,
                           const std::vector<std::size_t>& group);

// Surface completion, part of the same departure (on when the merge is on). An object standing
// on a surface bends the normals of the voxels beside it (their neighbourhood takes in the
// object's foot), so Eq 3 drops a rim one cell wide around every object, and each rim is cut
// out of the surface; something lying flat on it, thinner than r_z, is glued to it by Z
// clustering. The surface's voxels are made those that lie on its fitted plane: members whose
// centroid is farther (vertically) than the tolerance are let go, and neighbouring voxels
// (same or 8-adjacent column) that no plane owns and that are within it join, breadth-first.
// Tolerance: r_z / 2 (a voxel of the surface cut by a z cell boundary keeps its centroid
// within it), or 2.5 robust standard deviations of the members' offsets where the surface is
// noisier (a far floor). A voxel of something vertical never joins — one whose normal leans
// more than 72.5°, or whose column goes on in the z cells just above and below it: a level
// patch on a wall (a ledge, or a step of depth quantization) would otherwise grow along the
// wall as a horizontal band, while the rim's bent normals lean much less and a table has
// nothing right under its top. Updates voxel_owner and `voxels`; returns how many changed.
std::size_t completeSurface(const VoxelGrid& grid, const std::vector<Eigen::Vector3f>& normals,
                            const HorizontalPlane& plane, double r_z, std::int32_t id,
                            std::vector<std::int32_t>& voxel_owner,
                            std::vector<std::uint32_t>& voxels);

}  // namespace hope
