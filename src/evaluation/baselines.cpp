#include "hope/evaluation/baselines.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>

#include <pcl/ModelCoefficients.h>
#include <pcl/features/normal_3d.h>
#include <pcl/search/kdtree.h>
#include <pcl/segmentation/region_growing.h>
#include <pcl/segmentation/sac_segmentation.h>

#include "hope/grid_filter.h"

namespace hope {
namespace evaluation {

namespace {

double millisecondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
      .count();
}

// Spreads voxel labels to the input points and fills in each plane's height and tilt.
void finish(const GriddedCloud& cloud, const std::vector<int>& voxel_labels,
            const std::vector<Eigen::Vector3f>& normals, BaselineResult& result) {
  const std::size_t planes = result.heights.size();
  std::vector<double> z_sum(planes, 0.0);
  std::vector<std::size_t> count(planes, 0);
  std::vector<Eigen::Vector3d> normal_sum(planes, Eigen::Vector3d::Zero());
  for (std::size_t v = 0; v < voxel_labels.size(); ++v) {
    const int label = voxel_labels[v];
    if (label < 0) continue;
    z_sum[label] += cloud.voxels->points[v].z;
    ++count[label];
    if (!normals.empty()) normal_sum[label] += normals[v].cast<double>();
  }
  for (std::size_t k = 0; k < planes; ++k) {
    result.heights[k] = count[k] ? z_sum[k] / count[k] : 0.0;
    if (!normals.empty() && normal_sum[k].norm() > 0) {
      result.tilts[k] = std::acos(std::min(1.0, std::fabs(normal_sum[k].normalized().z())));
    }
  }
  result.point_labels.assign(cloud.point_voxel.size(), -1);
  for (std::size_t i = 0; i < cloud.point_voxel.size(); ++i) {
    const int v = cloud.point_voxel[i];
    if (v >= 0) result.point_labels[i] = voxel_labels[v];
  }
}

}  // namespace

GriddedCloud gridded(const pcl::PointCloud<pcl::PointXYZ>& z_up_cloud, const Params& params) {
  GriddedCloud out;
  const auto start = std::chrono::steady_clock::now();
  std::vector<Eigen::Vector3f> aligned_points;
  aligned_points.reserve(z_up_cloud.size());
  for (const auto& p : z_up_cloud) aligned_points.emplace_back(p.x, p.y, p.z);
  VoxelGrid grid;
  grid.build(aligned_points, params.r_xy, params.r_z);
  out.voxels->resize(grid.numVoxels());
  for (std::size_t v = 0; v < grid.numVoxels(); ++v) {
    const Eigen::Vector3f& c = grid.centroid(v);
    out.voxels->points[v] = pcl::PointXYZ(c.x(), c.y(), c.z());
  }
  out.point_voxel = grid.pointVoxel();
  out.grid_ms = millisecondsSince(start);
  return out;
}

BaselineResult ransacPlanes(const GriddedCloud& cloud, const Params& params, double distance_factor,
                            int min_inliers) {
  BaselineResult result;
  const auto start = std::chrono::steady_clock::now();
  const std::size_t total = cloud.voxels->size();
  std::vector<int> voxel_labels(total, -1);
  std::vector<Eigen::Vector3f> plane_normals;
  pcl::SACSegmentation<pcl::PointXYZ> seg;
  seg.setOptimizeCoefficients(true);
  seg.setModelType(pcl::SACMODEL_PERPENDICULAR_PLANE);
  seg.setMethodType(pcl::SAC_RANSAC);
  seg.setAxis(Eigen::Vector3f::UnitZ());
  seg.setEpsAngle(params.maxSlope());
  seg.setMaxIterations(500);
  seg.setDistanceThreshold(distance_factor * params.r_xy);
  seg.setInputCloud(cloud.voxels);
  pcl::IndicesPtr remaining(new pcl::Indices(total));
  for (std::size_t v = 0; v < total; ++v) (*remaining)[v] = static_cast<pcl::index_t>(v);
  // A fixed seed: the report is reproducible.
  std::srand(1);
  while (remaining->size() >= std::max<std::size_t>(total / 20, 3) && result.heights.size() < 500) {
    seg.setIndices(remaining);
    pcl::PointIndices inliers;
    pcl::ModelCoefficients coefficients;
    seg.segment(inliers, coefficients);
    if (static_cast<int>(inliers.indices.size()) < min_inliers) break;
    const int label = static_cast<int>(result.heights.size());
    for (const auto v : inliers.indices) voxel_labels[v] = label;
    result.heights.push_back(0);
    result.tilts.push_back(0);
    Eigen::Vector3f n(coefficients.values[0], coefficients.values[1], coefficients.values[2]);
    plane_normals.push_back(n.normalized());
    pcl::Indices rest;
    rest.reserve(remaining->size());
    for (const auto v : *remaining)
      if (voxel_labels[v] < 0) rest.push_back(v);
    remaining->swap(rest);
  }
  result.segmentation_ms = millisecondsSince(start);
  // The model's normal is the plane's orientation; spread it to the voxels for finish().
  std::vector<Eigen::Vector3f> normals(total, Eigen::Vector3f::Zero());
  for (std::size_t v = 0; v < total; ++v) {
    if (voxel_labels[v] >= 0) {
      Eigen::Vector3f n = plane_normals[voxel_labels[v]];
      normals[v] = n.z() < 0 ? Eigen::Vector3f(-n) : n;
    }
  }
  finish(cloud, voxel_labels, normals, result);
  return result;
}

BaselineResult regionGrowingPlanes(const GriddedCloud& cloud, const Params& params,
                                   int min_cluster) {
  BaselineResult result;
  const auto start = std::chrono::steady_clock::now();
  pcl::search::KdTree<pcl::PointXYZ>::Ptr tree(new pcl::search::KdTree<pcl::PointXYZ>);
  pcl::PointCloud<pcl::Normal>::Ptr normals(new pcl::PointCloud<pcl::Normal>);
  pcl::NormalEstimation<pcl::PointXYZ, pcl::Normal> estimation;
  estimation.setInputCloud(cloud.voxels);
  estimation.setSearchMethod(tree);
  estimation.setKSearch(20);
  estimation.compute(*normals);

  pcl::RegionGrowing<pcl::PointXYZ, pcl::Normal> growing;
  growing.setMinClusterSize(min_cluster);
  growing.setMaxClusterSize(std::numeric_limits<int>::max());
  growing.setSearchMethod(tree);
  growing.setNumberOfNeighbours(20);
  growing.setInputCloud(cloud.voxels);
  growing.setInputNormals(normals);
  growing.setSmoothnessThreshold(static_cast<float>(8.0 / 180.0 * M_PI));
  growing.setCurvatureThreshold(1.0);
  std::vector<pcl::PointIndices> clusters;
  growing.extract(clusters);

  // Keep the horizontal segments: mean normal within atan(γ) of z.
  const std::size_t total = cloud.voxels->size();
  std::vector<int> voxel_labels(total, -1);
  std::vector<Eigen::Vector3f> voxel_normals(total, Eigen::Vector3f::Zero());
  for (const auto& cluster : clusters) {
    Eigen::Vector3d mean = Eigen::Vector3d::Zero();
    for (const auto v : cluster.indices) {
      const auto& n = normals->points[v];
      if (!std::isfinite(n.normal_z)) continue;
      const double sign = n.normal_z < 0 ? -1.0 : 1.0;
      mean += sign * Eigen::Vector3d(n.normal_x, n.normal_y, n.normal_z);
    }
    if (mean.norm() == 0) continue;
    if (std::acos(std::min(1.0, std::fabs(mean.normalized().z()))) > params.maxSlope()) continue;
    const int label = static_cast<int>(result.heights.size());
    result.heights.push_back(0);
    result.tilts.push_back(0);
    for (const auto v : cluster.indices) {
      voxel_labels[v] = label;
      const auto& n = normals->points[v];
      if (std::isfinite(n.normal_z)) {
        voxel_normals[v] =
            Eigen::Vector3f(n.normal_x, n.normal_y, n.normal_z) * (n.normal_z < 0 ? -1.f : 1.f);
      }
    }
  }
  result.segmentation_ms = millisecondsSince(start);
  finish(cloud, voxel_labels, voxel_normals, result);
  return result;
}

}  // namespace evaluation
}  // namespace hope
