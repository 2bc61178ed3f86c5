#include "hope/extractor.h"

#include <chrono>
#include <optional>
#include <sstream>

#include "hope/fragment_merging.h"
#include "hope/horizontal_candidates.h"
#include "hope/normal_estimation.h"
#include "hope/pca_refinement.h"
#include "hope/plane_description.h"
#include "hope/scan_gap_bridging.h"
#include "hope/z_clustering.h"
#include "parallel.h"

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

Result Extractor::extract(const PointsView& cloud, const Orientation& orientation,
                          const ExtractOutputs& outputs) {
  Result result;
  result.sensor_to_reference = orientation.sensorToReference();
  result.input_points = cloud.count;
  Stopwatch total, stage;

  result.local_origin = localOrigin(orientation);
  GridHints hints;
  Eigen::AlignedBox3f finite_box;
  const int threads = parallel::resolve(params_.threads);
  if (alignmentIsIdentity(cloud, orientation, result.local_origin)) {
    // A z-up cloud in its own frame (LiDAR, merged maps): read in place, only its box is needed.
    result.finite_points = finiteBox(cloud, finite_box, threads);
    aligned_.clear();
    aligned_view_ = AlignedPoints(cloud.data, cloud.count, cloud.stride);
  } else {
    result.finite_points =
        alignToGravity(cloud, orientation, aligned_, result.local_origin, &finite_box, threads);
    aligned_view_ = AlignedPoints(aligned_);
  }
  hints.finite_box = finite_box;
  hints.finite_points = result.finite_points;
  hints.threads = threads;
  result.timings.alignment_ms = stage.lap();

  grid_.build(aligned_view_, params_.r_xy, params_.r_z, hints);
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

  estimateNormals(grid_, params_.normal_radius_factor, normals_, threads);
  // The sensor position in the grid's coordinates, when known.
  std::optional<Eigen::Vector3d> viewpoint;
  if (orientation.viewpoint()) viewpoint = *orientation.viewpoint() - result.local_origin;
  links_.clear();
  // A camera's image (organized, at most 4 times wider than high) samples surfaces densely in
  // both directions; only a LiDAR's rings × azimuth layout or an unorganized scan is bridged.
  // (On the rendered tracking sequences bridging the far floor of depth images added ids.)
  const bool image_like = cloud.organized() && cloud.width <= 4 * std::size_t{cloud.height};
  if (params_.bridge_scan_gaps && viewpoint && !image_like) {
    result.bridged_voxels = bridgeScanGaps(grid_, *viewpoint, params_, normals_, links_);
  }
  result.timings.normals_ms = stage.lap();

  const double gamma = params_.gamma();
  result.candidates = selectHorizontalCandidates(normals_, gamma, is_candidate_);
  result.timings.candidates_ms = stage.lap();

  const auto clusters =
      zClustering(grid_, is_candidate_, params_.r_z, params_.min_cluster_voxels, links_);
  result.clusters = clusters.size();
  result.timings.clustering_ms = stage.lap();

  std::vector<RefinementVerdict> verdicts(clusters.size());
  std::vector<std::uint8_t> accepted(clusters.size(), 0);
  for (std::size_t c = 0; c < clusters.size(); ++c) {
    verdicts[c] = refineWithPCA(normals_, clusters[c], gamma);
    accepted[c] = verdicts[c].horizontal &&
                  footprintMinorVariance(grid_, clusters[c]) >= kMinFootprintVariance;
  }
  result.timings.refinement_ms = stage.lap();

  // Description of each cluster from its voxels, in the grid's coordinates (the merge works
  // there). With the merge on, rejected clusters are described too (they may join an accepted
  // surface). Every surface is measured in full (its points' bbox and hull) once it is
  // complete. The clusters are described in parallel, each on its own, then taken in order.
  const bool merge = params_.merge_fragments;
  std::vector<HorizontalPlane> descriptions(clusters.size());
  parallel::forEach(clusters.size(), threads, [&](std::size_t c) {
    if (!accepted[c] && !merge) return;
    descriptions[c] = describePlane(grid_, aligned_view_, clusters[c], Detail::kVoxels);
  });
  std::vector<Fragment> fragments;
  for (std::size_t c = 0; c < clusters.size(); ++c) {
    if (!accepted[c] && !merge) continue;
    Fragment fragment{std::move(descriptions[c]), &clusters[c], accepted[c] != 0};
    // The plane fitted through the cluster's points must itself be within the accepted slope:
    // grid normals underestimate slopes just steeper than atan γ (Z clustering cuts them into
    // level strips), and the fit over the whole strip sees what the normals miss.
    if (fragment.plane.tilt > params_.maxSlope()) fragment.accepted = false;
    if (!fragment.accepted && !merge) continue;
    fragment.plane.mean_normal_tilt = verdicts[c].mean_tilt;
    fragment.plane.group_angle = verdicts[c].group_angle;
    fragments.push_back(std::move(fragment));
  }
  std::size_t accepted_fragments = 0;
  for (const Fragment& f : fragments) accepted_fragments += f.accepted ? 1 : 0;
  result.rejected_by_refinement = clusters.size() - accepted_fragments;
  result.timings.description_ms = stage.lap();

  const std::vector<std::vector<std::size_t>> groups =
      groupFragments(grid_, fragments, viewpoint, params_);

  // The surfaces: groups with at least one accepted fragment (a rejected one never stands
  // alone). voxel_plane_ holds the surface index of each voxel until the ids are known.
  struct Surface {
    HorizontalPlane plane;
    std::vector<std::uint32_t> voxels;
  };
  std::vector<Surface> surfaces;
  voxel_plane_.assign(grid_.numVoxels(), -1);
  for (const std::vector<std::size_t>& group : groups) {
    const std::size_t largest = representative(fragments, group);
    if (!fragments[largest].accepted) continue;
    Surface surface;
    for (std::size_t k : group) {
      surface.voxels.insert(surface.voxels.end(), fragments[k].voxels->begin(),
                            fragments[k].voxels->end());
      if (!fragments[k].accepted) --result.rejected_by_refinement;
    }
    if (group.size() == 1) {
      surface.plane = std::move(fragments[largest].plane);
    } else {
      surface.plane = describePlane(grid_, aligned_view_, surface.voxels, Detail::kVoxels);
      surface.plane.num_parts = static_cast<int>(group.size());
      // The refinement angles of the largest accepted part.
      surface.plane.mean_normal_tilt = fragments[largest].plane.mean_normal_tilt;
      surface.plane.group_angle = fragments[largest].plane.group_angle;
      result.merged_fragments += group.size() - 1;
    }
    for (std::uint32_t v : surface.voxels) {
      voxel_plane_[v] = static_cast<std::int32_t>(surfaces.size());
    }
    surfaces.push_back(std::move(surface));
  }
  if (merge) {
    // Surface completion (fragment_merging.h) once every surface owns its voxels, so that no
    // surface grows into another.
    const std::vector<std::int32_t> owner_before = voxel_plane_;
    for (std::size_t k = 0; k < surfaces.size(); ++k) {
      completeSurface(grid_, normals_, surfaces[k].plane, params_.r_z, static_cast<std::int32_t>(k),
                      voxel_plane_, surfaces[k].voxels);
    }
    // What the completion cut off a surface is not noise when it is a surface itself: a kerb's
    // top joined to the road through the kerb's face, a driveway climbing away from the road's
    // plane. Those voxels are clustered and refined again, and each accepted cluster becomes a
    // surface of its own — unless it lies among the surface it was cut from (its voxels mostly
    // beside that surface's), which makes it the surface's noisy fringe.
    std::vector<std::uint8_t> trimmed(grid_.numVoxels(), 0);
    for (std::size_t v = 0; v < trimmed.size(); ++v) {
      trimmed[v] = owner_before[v] >= 0 && voxel_plane_[v] < 0 && is_candidate_[v];
    }
    auto besideItsOrigin = [&](std::uint32_t v) {
      const int cx = grid_.cellX(v), cy = grid_.cellY(v);
      const int offsets[5][2] = {{0, 0}, {1, 0}, {-1, 0}, {0, 1}, {0, -1}};
      for (const auto& d : offsets) {
        const auto range = grid_.columnVoxels(cx + d[0], cy + d[1]);
        for (std::uint32_t u = range.first; u < range.second; ++u) {
          if (voxel_plane_[u] >= 0 && voxel_plane_[u] == owner_before[v]) return true;
        }
      }
      return false;
    };
    for (std::vector<std::uint32_t>& cluster :
         zClustering(grid_, trimmed, params_.r_z, params_.min_cluster_voxels, links_)) {
      std::size_t beside = 0;
      for (std::uint32_t v : cluster) beside += besideItsOrigin(v) ? 1 : 0;
      if (2 * beside > cluster.size()) continue;
      const RefinementVerdict verdict = refineWithPCA(normals_, cluster, gamma);
      if (!verdict.horizontal || footprintMinorVariance(grid_, cluster) < kMinFootprintVariance) {
        continue;
      }
      Surface surface{describePlane(grid_, aligned_view_, cluster, Detail::kVoxels),
                      std::move(cluster)};
      if (surface.plane.tilt > params_.maxSlope()) continue;
      surface.plane.mean_normal_tilt = verdict.mean_tilt;
      surface.plane.group_angle = verdict.group_angle;
      for (std::uint32_t v : surface.voxels) {
        voxel_plane_[v] = static_cast<std::int32_t>(surfaces.size());
      }
      ++result.clusters;
      surfaces.push_back(std::move(surface));
    }
  }
  result.timings.merging_ms = stage.lap();
  if (merge) {
    // Every surface measured again from its voxels now that the merge joined and completed it.
    parallel::forEach(surfaces.size(), threads, [&](std::size_t k) {
      Surface& surface = surfaces[k];
      HorizontalPlane again = describePlane(grid_, aligned_view_, surface.voxels, Detail::kVoxels);
      again.num_parts = surface.plane.num_parts;
      again.mean_normal_tilt = surface.plane.mean_normal_tilt;
      again.group_angle = surface.plane.group_angle;
      surface.plane = std::move(again);
    });
  }
  // Ids in order, after the optional height band and minimum area (both known from the voxels;
  // heights as translate() makes them): the voxels of a dropped surface belong to no plane, and
  // only the kept surfaces are measured in full.
  std::vector<std::int32_t> plane_of_surface(surfaces.size(), -1);
  std::vector<const std::vector<std::uint32_t>*> kept_voxels;
  std::vector<HorizontalPlane*> kept;
  for (std::size_t k = 0; k < surfaces.size(); ++k) {
    const HorizontalPlane& plane = surfaces[k].plane;
    const double height = plane.height + result.local_origin.z();
    if (height < params_.min_height || height > params_.max_height ||
        plane.area < params_.min_area) {
      ++result.rejected_by_band_or_area;
      continue;
    }
    plane_of_surface[k] = static_cast<std::int32_t>(kept.size());
    kept_voxels.push_back(&surfaces[k].voxels);
    kept.push_back(&surfaces[k].plane);
  }
  for (std::int32_t& owner : voxel_plane_) {
    if (owner >= 0) owner = plane_of_surface[static_cast<std::size_t>(owner)];
  }
  // Each kept surface measured in full, as the paper's planes are: bbox and hull from the
  // points, for all surfaces in one read of the points' voxels, which labels the points too.
  PointLabelling labelling;
  if (outputs.point_labels) {
    result.point_labels.resize(cloud.count);
    labelling.voxel_label = &voxel_plane_;
    labelling.point_labels = result.point_labels.data();
  }
  describeInFull(grid_, aligned_view_, kept_voxels, kept, threads, labelling);
  for (HorizontalPlane* plane : kept) {
    plane->translate(result.local_origin);
    if (orientation.viewpoint()) {
      const Eigen::Vector3d& eye = *orientation.viewpoint();
      plane->facing = plane->normal.dot(eye - plane->centroid) >= 0 ? Facing::kUp : Facing::kDown;
    }
    plane->id = static_cast<int>(result.planes.size());
    result.planes.push_back(std::move(*plane));
  }
  result.timings.description_ms += stage.lap();
  result.timings.total_ms = total.lap();
  return result;
}

}  // namespace hope
