#include "hope/extractor.h"

#include <chrono>
#include <optional>
#include <sstream>

#include "hope/fragment_merging.h"
#include "hope/gravity_alignment.h"
#include "hope/grid_filter.h"
#include "hope/horizontal_candidates.h"
#include "hope/normal_estimation.h"
#include "hope/pca_refinement.h"
#include "hope/placement.h"
#include "hope/plane_description.h"
#include "hope/scan_gap_bridging.h"
#include "hope/standing_objects.h"
#include "hope/surface_assembly.h"
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

struct Extractor::Buffers {
  std::vector<Eigen::Vector3f> aligned;  // the aligned copy, when one is needed
  AlignedPoints aligned_view;            // what the stages read: `aligned` or the input
  VoxelGrid grid;
  std::vector<Eigen::Vector3f> normals;
  std::vector<std::uint8_t> is_candidate;
  std::vector<VoxelLink> links;           // scan-gap links for Z clustering
  std::vector<std::int32_t> voxel_plane;  // plane index of each voxel, -1 for none
};

Extractor::Extractor(const Params& params)
    : params_(params), buffers_(std::make_unique<Buffers>()) {
  validate(params_);
}
Extractor::~Extractor() = default;
Extractor::Extractor(Extractor&&) noexcept = default;
Extractor& Extractor::operator=(Extractor&&) noexcept = default;

AlignedPoints Extractor::alignedPoints() const { return buffers_->aligned_view; }

Result Extractor::extract(const PointsView& cloud, const Orientation& orientation,
                          const ExtractOutputs& outputs) {
  Buffers& b = *buffers_;
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
    b.aligned.clear();
    b.aligned_view = AlignedPoints(cloud.data, cloud.count, cloud.stride);
  } else {
    result.finite_points =
        alignToGravity(cloud, orientation, b.aligned, result.local_origin, &finite_box, threads);
    b.aligned_view = AlignedPoints(b.aligned);
  }
  hints.finite_box = finite_box;
  hints.finite_points = result.finite_points;
  hints.threads = threads;
  result.timings.alignment_ms = stage.lap();

  b.grid.build(b.aligned_view, params_.r_xy, params_.r_z, hints);
  result.voxels = b.grid.numVoxels();
  const Eigen::Vector3d extent = b.grid.extent();
  // No indoor scene and few outdoor scans span a kilometre: such a cloud is almost always in
  // millimetres, which would make every plane look like a slope.
  if (extent.maxCoeff() > 1000.0) {
    std::ostringstream msg;
    msg << "the cloud spans " << extent.x() << " x " << extent.y() << " x " << extent.z()
        << " m; hope expects metres (is it in millimetres?)";
    result.warnings.push_back(msg.str());
  }
  result.timings.grid_filter_ms = stage.lap();

  estimateNormals(b.grid, params_.normal_radius_factor, b.normals, threads);
  // The sensor position in the grid's coordinates, when known.
  std::optional<Eigen::Vector3d> viewpoint;
  if (orientation.viewpoint()) viewpoint = *orientation.viewpoint() - result.local_origin;
  b.links.clear();
  // A camera's image (PointsView::imageLike) samples surfaces densely in
  // both directions; only a LiDAR's rings × azimuth layout or an unorganized scan is bridged.
  // (On the rendered tracking sequences bridging the far floor of depth images added ids.)
  if (params_.bridge_scan_gaps && viewpoint && !cloud.imageLike()) {
    result.bridged_voxels = bridgeScanGaps(b.grid, *viewpoint, params_, b.normals, b.links);
  }
  result.timings.normals_ms = stage.lap();

  const double gamma = params_.gamma();
  result.candidates = selectHorizontalCandidates(b.normals, gamma, b.is_candidate);
  result.timings.candidates_ms = stage.lap();

  const auto clusters =
      zClustering(b.grid, b.is_candidate, params_.r_z, params_.min_cluster_voxels, b.links);
  result.clusters = clusters.size();
  result.timings.clustering_ms = stage.lap();

  const ClusterRefinement refinement = refineClusters(b.grid, b.normals, clusters, gamma);
  result.timings.refinement_ms = stage.lap();

  AssemblyCounts counts;
  std::vector<Fragment> fragments =
      describeFragments(b.grid, b.aligned_view, clusters, refinement, params_, threads, counts);
  result.timings.description_ms = stage.lap();

  const std::vector<std::vector<std::size_t>> groups =
      groupFragments(b.grid, fragments, viewpoint, params_);
  std::vector<Surface> surfaces =
      assembleSurfaces(b.grid, b.aligned_view, b.normals, b.is_candidate, b.links, fragments,
                       groups, params_, b.voxel_plane, counts);
  result.rejected_by_refinement = counts.rejected_by_refinement;
  result.merged_fragments = counts.merged_fragments;
  result.clusters += counts.fringe_clusters;
  result.timings.merging_ms = stage.lap();

  if (params_.merge_fragments) redescribeSurfaces(b.grid, b.aligned_view, surfaces, threads);
  const KeptSurfaces kept = keepInBandAndArea(surfaces, result.local_origin.z(), params_,
                                              b.voxel_plane, result.rejected_by_band_or_area);
  // Each kept surface measured in full, as the paper's planes are: bbox and hull from the
  // points, for all surfaces in one read of the points' voxels, which labels the points too.
  PointLabelling labelling;
  if (outputs.point_labels || outputs.objects) {
    result.point_labels.resize(cloud.count);
    labelling.voxel_label = &b.voxel_plane;
    labelling.point_labels = result.point_labels.data();
  }
  describeInFull(b.grid, b.aligned_view, kept.voxels, kept.planes, threads, labelling);
  for (HorizontalPlane* plane : kept.planes) {
    plane->translate(result.local_origin);
    if (orientation.viewpoint()) {
      const Eigen::Vector3d& eye = *orientation.viewpoint();
      plane->facing = plane->normal.dot(eye - plane->centroid) >= 0 ? Facing::kUp : Facing::kDown;
    }
    plane->id = static_cast<int>(result.planes.size());
    result.planes.push_back(std::move(*plane));
  }
  result.timings.description_ms += stage.lap();

  // The sensor's noise, when not given: a LiDAR's for a rings × azimuth layout or an
  // unorganized cloud wider than a depth camera sees (10 m), a depth camera's otherwise.
  if (outputs.object_params.noise) {
    result.noise = *outputs.object_params.noise;
  } else {
    const bool scan = cloud.organized() ? !cloud.imageLike() : extent.maxCoeff() > 10.0;
    result.noise = scan ? RangeNoise::lidar() : RangeNoise::depthCamera();
  }
  if (outputs.objects) {
    ObjectParams object_params = outputs.object_params;
    object_params.noise = result.noise;
    describeWhatStands(result, object_params, viewpoint);
  }
  result.timings.objects_ms = stage.lap();
  // Each plane its own surface; FramePipeline groups the pieces of one (surface_grouping.h).
  for (HorizontalPlane& plane : result.planes) plane.surface_id = plane.id;
  result.timings.total_ms = total.lap();
  return result;
}

void Extractor::describeWhatStands(Result& result, const ObjectParams& object_params,
                                   const std::optional<Eigen::Vector3d>& viewpoint) const {
  const Buffers& b = *buffers_;
  StandingObjects standing =
      findStandingObjects(b.aligned_view, result.planes, result.point_labels, result.local_origin,
                          params_, object_params, viewpoint);
  const std::vector<double> free = freeAreas(b.aligned_view, result.planes, result.point_labels,
                                             standing, result.local_origin, params_);
  for (std::size_t p = 0; p < result.planes.size(); ++p) result.planes[p].free_area = free[p];
  result.objects = std::move(standing.objects);
  result.point_objects = std::move(standing.point_objects);
}

}  // namespace hope
