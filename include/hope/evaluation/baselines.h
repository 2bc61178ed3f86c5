// The paper's reference methods (§3, Table 1), run the way the paper compares them: PCL's
// RANSAC with a plane model perpendicular to z, and PCL's region growing keeping horizontal
// segments, both on the same anisotropic grid as hope (so all methods see the same points).
#pragma once

#include <cstdint>
#include <vector>

#include <pcl/point_cloud.h>
#include <pcl/point_types.h>
#include <Eigen/Core>

#include "hope/params.h"

namespace hope {
namespace evaluation {

// The input of the baselines: hope's grid filter (r_xy, r_xy, r_z) applied to a z-up cloud,
// timed from the same PCL cloud hope receives (the copy into a float array included, as hope's
// alignment stage pays it too).
struct GriddedCloud {
  pcl::PointCloud<pcl::PointXYZ>::Ptr voxels{new pcl::PointCloud<pcl::PointXYZ>};
  std::vector<std::int32_t> point_voxel;  // voxel of each input point, -1 for non-finite
  double grid_ms = 0;                     // time of the grid filter
};
GriddedCloud gridded(const pcl::PointCloud<pcl::PointXYZ>& z_up_cloud, const Params& params);

struct BaselineResult {
  std::vector<int> point_labels;  // plane of each input point, -1 for none
  std::vector<double> heights;    // mean z of each plane's voxels
  std::vector<double> tilts;      // angle of each plane's normal from z, radians
  double segmentation_ms = 0;     // everything after the shared grid filter
};

// SACSegmentation, SACMODEL_PERPENDICULAR_PLANE, axis z, angle atan(r_z / r_xy), 500 RANSAC
// iterations, distance threshold distance_factor · r_xy (the paper's μ · r_xy). Planes are
// extracted one after another until a plane would have fewer than `min_inliers` voxels or
// fewer than 5 % of the voxels remain.
BaselineResult ransacPlanes(const GriddedCloud& cloud, const Params& params,
                            double distance_factor = 0.5, int min_inliers = 10);

// RegionGrowing with K = 20 neighbours, smoothness 8°, curvature threshold 1.0, normals from
// NormalEstimation with the same K; segments of at least `min_cluster` voxels whose mean
// normal is within atan(r_z / r_xy) of z are kept as horizontal planes.
BaselineResult regionGrowingPlanes(const GriddedCloud& cloud, const Params& params,
                                   int min_cluster = 10);

}  // namespace evaluation
}  // namespace hope
