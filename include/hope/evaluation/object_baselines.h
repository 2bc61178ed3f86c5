// The reference pipelines a tabletop user runs today to get the objects standing on a table
// (the objects-and-placements issue), in PCL, to compare hope's objects with on the same
// input: the classic tabletop pipeline and LCCP on its prism points.
#pragma once

#include <cstdint>
#include <vector>

#include <Eigen/Core>

namespace hope {
namespace evaluation {

struct ObjectBaselineResult {
  // One entry per input point, in input order: 0 no object, k > 0 object k (as hope_extract's
  // `object` field).
  std::vector<std::int32_t> point_objects;
  int num_objects = 0;
  double ms = 0;  // from the input points to the labels, everything included
};

// Tuned on mosd_dev (13 Kinect tabletop scenes).
struct TabletopParams {
  double plane_distance = 0.01;   // RANSAC inlier distance, m
  double plane_angle_deg = 10.0;  // the plane's normal within this of `up`
  int ransac_iterations = 200;
  double min_height = 0.01;         // prism from here above the table …
  double max_height = 0.5;          // … to here, m
  double cluster_tolerance = 0.01;  // Euclidean clustering, m
  int min_cluster = 40;             // points, as hope's ObjectParams::min_points
  // LCCP on the prism points: supervoxels of these resolutions, concavity tolerance (degrees).
  double voxel_resolution = 0.0075;
  double seed_resolution = 0.03;
  double concavity_tolerance_deg = 10.0;
};

// Classic tabletop (tabletop_object_detector, jsk_pcl_ros): RANSAC plane perpendicular to
// `up` (SACMODEL_PERPENDICULAR_PLANE) → 2D convex hull of its inliers → the points of the
// prism above it (ExtractPolygonalPrismData) → EuclideanClusterExtraction. `points` in the
// sensor frame (NaN for none), `rgb` 0xRRGGBB per point or empty, `up` against gravity in the
// sensor frame.
ObjectBaselineResult tabletopObjects(const std::vector<Eigen::Vector3f>& points,
                                     const Eigen::Vector3d& up,
                                     const TabletopParams& params = TabletopParams());

// LCCP (Stein et al. 2014): the tabletop pipeline's prism points → SupervoxelClustering →
// LCCPSegmentation (locally convex connected supervoxels) → segments of min_cluster points.
ObjectBaselineResult lccpObjects(const std::vector<Eigen::Vector3f>& points,
                                 const std::vector<std::uint32_t>& rgb, const Eigen::Vector3d& up,
                                 const TabletopParams& params = TabletopParams());

}  // namespace evaluation
}  // namespace hope
