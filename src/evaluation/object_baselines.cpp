#include "hope/evaluation/object_baselines.h"

#include <chrono>
#include <cmath>
#include <limits>
#include <map>
#include <vector>

#include <pcl/ModelCoefficients.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>
#include <pcl/search/kdtree.h>
#include <pcl/segmentation/extract_clusters.h>
#include <pcl/segmentation/extract_polygonal_prism_data.h>
#include <pcl/segmentation/lccp_segmentation.h>
#include <pcl/segmentation/sac_segmentation.h>
#include <pcl/segmentation/supervoxel_clustering.h>
#include "hope/convex_hull.h"

namespace hope {
namespace evaluation {

namespace {

using Point = pcl::PointXYZRGBA;
using Cloud = pcl::PointCloud<Point>;

double millisecondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
      .count();
}

// The finite points as a dense PCL cloud, and the input index of each.
struct DenseCloud {
  Cloud::Ptr cloud{new Cloud};
  std::vector<std::size_t> input_index;
};

DenseCloud denseCloud(const std::vector<Eigen::Vector3f>& points,
                      const std::vector<std::uint32_t>& rgb) {
  DenseCloud dense;
  dense.cloud->reserve(points.size());
  dense.input_index.reserve(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) {
    if (!points[i].allFinite()) continue;
    Point p;
    p.x = points[i].x();
    p.y = points[i].y();
    p.z = points[i].z();
    p.rgba = (i < rgb.size() ? rgb[i] : 0x808080u) | 0xff000000u;
    dense.cloud->push_back(p);
    dense.input_index.push_back(i);
  }
  return dense;
}

// The points of the prism above the largest plane perpendicular to `up`, as indices into
// dense.cloud; empty when there is no such plane.
pcl::PointIndices::Ptr tabletopPrism(const DenseCloud& dense, const Eigen::Vector3d& up,
                                     const TabletopParams& params) {
  pcl::PointIndices::Ptr prism(new pcl::PointIndices);
  if (dense.cloud->size() < 3) return prism;
  pcl::SACSegmentation<Point> ransac;
  ransac.setOptimizeCoefficients(true);
  ransac.setModelType(pcl::SACMODEL_PERPENDICULAR_PLANE);
  ransac.setMethodType(pcl::SAC_RANSAC);
  ransac.setAxis(up.normalized().cast<float>());
  ransac.setEpsAngle(params.plane_angle_deg * M_PI / 180.0);
  ransac.setDistanceThreshold(params.plane_distance);
  ransac.setMaxIterations(params.ransac_iterations);
  ransac.setInputCloud(dense.cloud);
  pcl::PointIndices::Ptr inliers(new pcl::PointIndices);
  pcl::ModelCoefficients::Ptr plane(new pcl::ModelCoefficients);
  ransac.segment(*inliers, *plane);
  if (inliers->indices.size() < 3) return prism;

  // The inliers' 2D convex hull on the plane (hope's monotone chain: the same hull PCL's
  // ConvexHull gives, without qhull).
  const Eigen::Vector3d normal =
      Eigen::Vector3d(plane->values[0], plane->values[1], plane->values[2]).normalized();
  const Eigen::Vector3d u = normal.unitOrthogonal(), v = normal.cross(u);
  std::vector<Eigen::Vector2d> flat;
  flat.reserve(inliers->indices.size());
  for (int d : inliers->indices) {
    const Eigen::Vector3d p = (*dense.cloud)[d].getVector3fMap().cast<double>();
    flat.emplace_back(p.dot(u), p.dot(v));
  }
  const double offset =
      -plane->values[3] /
      Eigen::Vector3d(plane->values[0], plane->values[1], plane->values[2]).norm();
  Cloud::Ptr hull(new Cloud);
  for (const Eigen::Vector2d& q : convexHull2D(std::move(flat))) {
    const Eigen::Vector3d p = q.x() * u + q.y() * v + offset * normal;
    Point h;
    h.x = static_cast<float>(p.x());
    h.y = static_cast<float>(p.y());
    h.z = static_cast<float>(p.z());
    hull->push_back(h);
  }
  if (hull->size() < 3) return prism;

  // The prism's side is chosen by the viewpoint (the sensor, at the origin): above the table.
  pcl::ExtractPolygonalPrismData<Point> extract;
  extract.setInputCloud(dense.cloud);
  extract.setInputPlanarHull(hull);
  extract.setHeightLimits(params.min_height, params.max_height);
  extract.segment(*prism);
  return prism;
}

ObjectBaselineResult labelled(const DenseCloud& dense, std::size_t num_points,
                              const std::vector<std::vector<int>>& segments, int min_points) {
  ObjectBaselineResult result;
  result.point_objects.assign(num_points, 0);
  for (const auto& segment : segments) {
    if (static_cast<int>(segment.size()) < min_points) continue;
    ++result.num_objects;
    for (int d : segment) result.point_objects[dense.input_index[d]] = result.num_objects;
  }
  return result;
}

}  // namespace

ObjectBaselineResult tabletopObjects(const std::vector<Eigen::Vector3f>& points,
                                     const Eigen::Vector3d& up, const TabletopParams& params) {
  const auto start = std::chrono::steady_clock::now();
  const DenseCloud dense = denseCloud(points, {});
  const pcl::PointIndices::Ptr prism = tabletopPrism(dense, up, params);
  std::vector<std::vector<int>> segments;
  if (!prism->indices.empty()) {
    pcl::search::KdTree<Point>::Ptr tree(new pcl::search::KdTree<Point>);
    tree->setInputCloud(dense.cloud, pcl::IndicesConstPtr(new std::vector<int>(
                                         prism->indices.begin(), prism->indices.end())));
    pcl::EuclideanClusterExtraction<Point> clustering;
    clustering.setClusterTolerance(params.cluster_tolerance);
    clustering.setMinClusterSize(params.min_cluster);
    clustering.setMaxClusterSize(std::numeric_limits<int>::max());
    clustering.setSearchMethod(tree);
    clustering.setInputCloud(dense.cloud);
    clustering.setIndices(prism);
    std::vector<pcl::PointIndices> clusters;
    clustering.extract(clusters);
    for (const auto& c : clusters) segments.push_back(c.indices);
  }
  ObjectBaselineResult result = labelled(dense, points.size(), segments, params.min_cluster);
  result.ms = millisecondsSince(start);
  return result;
}

ObjectBaselineResult lccpObjects(const std::vector<Eigen::Vector3f>& points,
                                 const std::vector<std::uint32_t>& rgb, const Eigen::Vector3d& up,
                                 const TabletopParams& params) {
  const auto start = std::chrono::steady_clock::now();
  const DenseCloud dense = denseCloud(points, rgb);
  const pcl::PointIndices::Ptr prism = tabletopPrism(dense, up, params);
  std::vector<std::vector<int>> segments;
  if (!prism->indices.empty()) {
    Cloud::Ptr above(new Cloud);
    above->reserve(prism->indices.size());
    for (int d : prism->indices) above->push_back((*dense.cloud)[d]);
    pcl::SupervoxelClustering<Point> supervoxels(static_cast<float>(params.voxel_resolution),
                                                 static_cast<float>(params.seed_resolution));
    supervoxels.setUseSingleCameraTransform(false);
    supervoxels.setInputCloud(above);
    supervoxels.setColorImportance(0.0f);
    supervoxels.setSpatialImportance(1.0f);
    supervoxels.setNormalImportance(4.0f);
    std::map<std::uint32_t, pcl::Supervoxel<Point>::Ptr> clusters;
    supervoxels.extract(clusters);
    std::multimap<std::uint32_t, std::uint32_t> adjacency;
    supervoxels.getSupervoxelAdjacency(adjacency);
    pcl::PointCloud<pcl::PointXYZL>::Ptr labels = supervoxels.getLabeledCloud();
    pcl::LCCPSegmentation<Point> lccp;
    lccp.setConcavityToleranceThreshold(static_cast<float>(params.concavity_tolerance_deg));
    lccp.setSanityCheck(true);
    lccp.setSmoothnessCheck(true, static_cast<float>(params.voxel_resolution),
                            static_cast<float>(params.seed_resolution), 0.1f);
    lccp.setKFactor(0);
    lccp.setMinSegmentSize(3);
    lccp.setInputSupervoxels(clusters, adjacency);
    lccp.segment();
    lccp.relabelCloud(*labels);
    // Supervoxel label 0 is "no supervoxel"; relabelled, every other label is a segment's.
    std::map<std::uint32_t, std::vector<int>> by_segment;
    for (std::size_t k = 0; k < labels->size() && k < prism->indices.size(); ++k) {
      if ((*labels)[k].label != 0) by_segment[(*labels)[k].label].push_back(prism->indices[k]);
    }
    for (auto& [label, members] : by_segment) segments.push_back(std::move(members));
  }
  ObjectBaselineResult result = labelled(dense, points.size(), segments, params.min_cluster);
  result.ms = millisecondsSince(start);
  return result;
}

}  // namespace evaluation
}  // namespace hope
