// Plane description: turns a cluster that survived refinement into a HorizontalPlane
// measured on the full-resolution input points (not only voxel centroids).
#pragma once

#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "hope/convex_hull.h"
#include "hope/grid_filter.h"
#include "hope/plane.h"

namespace hope {

// How much of a plane to measure. kFull reads every input point of the plane (bbox and hull
// from the points themselves); kVoxels only the voxels (bbox from the occupied grid cells, no
// hull), which is all the fragment merge needs before the final description.
enum class Detail { kFull, kVoxels };

// Height, bbox, centroid, least-squares normal, footprint area, counts and convex hull of the
// input points in the cluster's voxels. `id` and the refinement angles are left to the caller.
HorizontalPlane describePlane(const VoxelGrid& grid, const AlignedPoints& aligned,
                              const std::vector<std::uint32_t>& members,
                              Detail detail = Detail::kFull);

// Optionally, describeInFull's read of the points' voxels also labels every point: the entry
// of `voxel_label` for its voxel, -1 for a point without one. One read of the cloud instead of
// two (the labels would otherwise take a pass of their own).
struct PointLabelling {
  const std::vector<std::int32_t>* voxel_label = nullptr;  // one entry per voxel
  std::int32_t* point_labels = nullptr;                    // room for one per input point
};

// Completes planes described with Detail::kVoxels (planes[k] from members[k]) with what needs
// their points: the bbox and convex hull of the points themselves, and the outline. Reads the
// points' voxels once for all planes, so describing many planes costs one pass over the cloud,
// not one each. The member lists must not share voxels. `threads` as Params::threads.
void describeInFull(const VoxelGrid& grid, const AlignedPoints& aligned,
                    const std::vector<const std::vector<std::uint32_t>*>& members,
                    const std::vector<HorizontalPlane*>& planes, int threads = 1,
                    const PointLabelling& labelling = PointLabelling());

}  // namespace hope
