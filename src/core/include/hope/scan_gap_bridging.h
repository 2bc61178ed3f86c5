// Scan-gap bridging (a departure from the paper, for spinning LiDARs and other sparse scans).
//
// A spinning LiDAR samples the ground in rings whose spacing grows with the square of the
// range: on an HDL-64E 1.8 m above a road they are 0.35 m apart at 8 m, 1.6 m at 20 m and
// 10 m at 50 m. Once the spacing exceeds r_xy a ring's voxels have neighbours along the ring
// only, §2.2's normal is undefined (a line fixes no plane) and §2.3's clustering cannot reach
// the next ring: the paper's pipeline finds the ground near the sensor only.
//
// What fixes the plane is the neighbouring ring, which lies along the sensor's horizontal ray
// through the voxel, nearer or farther. For every voxel without a normal the bridging walks
// that ray inward and outward (up to half the voxel's range) to the first voxel within r_z in
// height, skipping what stands higher or lower (a car, a kerb). The plane through the voxel's
// own scan line (its neighbourhood's main direction) and that link gives the normal, the more
// level of the two sides winning (at a surface's edge only one side is the surface). Each link
// whose plane passes Eq 3 also joins the two voxels in Z clustering. A voxel whose column goes
// on above and below it (a wall's scan lines) is not bridged.
//
// Needs the sensor position (Orientation::viewpoint()); clouds from a moving sensor merged
// into a map have none, and the bridging is skipped. The extractor skips it for a camera's
// image too (organized, at most 4 times wider than high), whose rows are dense.
#pragma once

#include <cstdint>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "hope/grid_filter.h"
#include "hope/params.h"

namespace hope {

using VoxelLink = std::pair<std::uint32_t, std::uint32_t>;

// `viewpoint` in the grid's coordinates. Fills the NaN entries of `normals` it can and
// appends the links found to `links`; returns the number of voxels given a normal.
std::size_t bridgeScanGaps(const VoxelGrid& grid, const Eigen::Vector3d& viewpoint,
                           const Params& params, std::vector<Eigen::Vector3f>& normals,
                           std::vector<VoxelLink>& links);

}  // namespace hope
