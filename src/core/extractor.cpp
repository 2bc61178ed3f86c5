#include "hope/extractor.h"

#include <chrono>
#include <sstream>

#include "hope/horizontal_candidates.h"
#include "hope/normal_estimation.h"
#include "hope/pca_refinement.h"
#include "hope/plane_description.h"
#include "hope/z_clustering.h"

namespace hope {

namespace {

class Stopwatch {
 public:
  // Milliseconds since the last lap (or construction).
  double lap() {
    const auto now = std::chrono::steady_clock::now();
    const double ms = std::chrono::duration<double, std::milli>(now - last_).count();
    last_ = now;
    return ms;
  }

 private:
  std::chrono::steady_clock::time_point last_ = std::chrono::steady_clock::now();
};

}  // namespace

std::vector<std::uint32_t> Result::pointsOf(std::size_t index) const {
  std::vector<std::uint32_t> indices;
  for (std::size_t i = 0; i < point_labels.size(); ++i) {
    if (point_labels[i] == static_cast<std::int32_t>(index)) {
      indices.push_back(static_cast<std::uint32_t>(i));
    }
  }
  return indices;
}

Extractor::Extractor(const Params& params) : params_(params) { validate(params_); }

Result Extractor::extract(const PointsView& cloud, const Orientation& orientation) {
  Result result;
  result.sensor_to_reference = orientation.sensorToReference();
  result.input_points = cloud.count;
  Stopwatch total, stage;

  result.local_origin = localOrigin(orientation);
  result.finite_points = alignToGravity(cloud, orientation, aligned_, result.local_origin);
  result.timings.alignment_ms = stage.lap();

  grid_.build(aligned_, params_.r_xy, params_.r_z);
  result.voxels = grid_.numVoxels();
  const Eigen::Vector3d extent = grid_.extent();
  // No indoor scene and few outdoor scans span a kilometre: such a cloud is almost always in
  // millimetres, which would make every plane look like a slope.
  if (extent.maxCoeff() > 1000.0) {
    std::ostringstream msg;
    msg << "the cloud spans " << extent.x() << " x " << extent.y() << " x " << extent.z()
        << " m; hope expects metres (is it in millimetres?)";
    result.warnings.push_back(msg.str());
  }
  result.timings.grid_filter_ms = stage.lap();

  estimateNormals(grid_, params_.normal_radius_factor, normals_);
  result.timings.normals_ms = stage.lap();

  const double gamma = params_.gamma();
  result.candidates = selectHorizontalCandidates(normals_, gamma, is_candidate_);
  result.timings.candidates_ms = stage.lap();

  const auto clusters = zClustering(grid_, is_candidate_, params_.r_z, params_.min_cluster_voxels);
  result.clusters = clusters.size();
  result.timings.clustering_ms = stage.lap();

  std::vector<std::size_t> kept;
  std::vector<RefinementVerdict> verdicts(clusters.size());
  for (std::size_t c = 0; c < clusters.size(); ++c) {
    verdicts[c] = refineWithPCA(normals_, clusters[c], gamma);
    if (verdicts[c].horizontal &&
        footprintMinorVariance(grid_, clusters[c]) >= kMinFootprintVariance) {
      kept.push_back(c);
    }
  }
  result.rejected_by_refinement = clusters.size() - kept.size();
  result.timings.refinement_ms = stage.lap();

  result.point_labels.assign(cloud.count, -1);
  voxel_plane_.assign(grid_.numVoxels(), -1);
  for (std::size_t c : kept) {
    HorizontalPlane plane = describePlane(grid_, aligned_, clusters[c]);
    plane.translate(result.local_origin);
    // The plane fitted through the cluster's points must itself be within the accepted slope:
    // grid normals underestimate slopes just steeper than atan γ (Z clustering cuts them into
    // level strips), and the fit over the whole strip sees what the normals miss.
    if (plane.tilt > params_.maxSlope()) {
      ++result.rejected_by_refinement;
      continue;
    }
    if (plane.height < params_.min_height || plane.height > params_.max_height ||
        plane.area < params_.min_area) {
      ++result.rejected_by_band_or_area;
      continue;
    }
    plane.id = static_cast<int>(result.planes.size());
    plane.mean_normal_tilt = verdicts[c].mean_tilt;
    plane.group_angle = verdicts[c].group_angle;
    for (std::uint32_t v : clusters[c]) voxel_plane_[v] = plane.id;
    result.planes.push_back(std::move(plane));
  }
  // Point labels in one sequential pass over the points' voxels (the voxel → plane table is
  // small enough to stay in cache), rather than scattered writes plane by plane.
  const std::vector<std::int32_t>& point_voxel = grid_.pointVoxel();
  for (std::size_t i = 0; i < point_voxel.size(); ++i) {
    if (point_voxel[i] >= 0) result.point_labels[i] = voxel_plane_[point_voxel[i]];
  }
  result.timings.description_ms = stage.lap();
  result.timings.total_ms = total.lap();
  return result;
}

}  // namespace hope
