// The HoPE pipeline for one cloud: gravity alignment → grid filter → normals → horizontal
// candidates → Z clustering → refinement with PCA → plane description.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "hope/orientation.h"
#include "hope/params.h"
#include "hope/plane.h"
#include "hope/points_view.h"

namespace hope {

// Wall-clock milliseconds spent in each stage.
struct StageTimings {
  double alignment_ms = 0;
  double grid_filter_ms = 0;
  double normals_ms = 0;
  double candidates_ms = 0;
  double clustering_ms = 0;
  double refinement_ms = 0;
  double description_ms = 0;
  double merging_ms = 0;  // the fragment merge (fragment_merging.h), 0 when switched off
  double objects_ms = 0;  // objects and free areas (ExtractOutputs::objects), 0 otherwise
  double total_ms = 0;
};

struct Result {
  std::vector<HorizontalPlane> planes;
  // One entry per input point, in input order: the index into `planes`, or -1 for points
  // on no plane (including non-finite ones). Empty when ExtractOutputs::point_labels is false.
  std::vector<std::int32_t> point_labels;
  // The transform that was applied: points in `planes` are in the reference frame.
  Eigen::Isometry3d sensor_to_reference = Eigen::Isometry3d::Identity();
  // Extractor::alignedPoints() are relative to this point of the reference frame (zero
  // unless the sensor is more than 512 m from its origin; see localOrigin). Plane fields are
  // absolute.
  Eigen::Vector3d local_origin = Eigen::Vector3d::Zero();
  StageTimings timings;
  // Counts along the way, for diagnostics and tuning.
  std::size_t input_points = 0;
  std::size_t finite_points = 0;
  std::size_t voxels = 0;
  std::size_t candidates = 0;
  std::size_t clusters = 0;
  std::size_t rejected_by_refinement = 0;
  std::size_t rejected_by_band_or_area = 0;
  // Voxels given a normal across a LiDAR's ring gap (scan_gap_bridging.h).
  std::size_t bridged_voxels = 0;
  // Planes that the fragment merge joined into another (fragment_merging.h).
  std::size_t merged_fragments = 0;
  // Suspicious input that still produced a result (e.g. a cloud that looks like millimetres).
  std::vector<std::string> warnings;
  // With ExtractOutputs::objects: what stands on each plane (standing_objects.h), and per
  // input point the index into `objects` or -1. Each plane's free_area is set too.
  std::vector<StandingObject> objects;
  std::vector<std::int32_t> point_objects;
  // The sensor's range noise the frame was judged with: ObjectParams::noise when given, else a
  // LiDAR's for a rings × azimuth layout or an unorganized cloud wider than a depth camera sees
  // (10 m), a depth camera's otherwise.
  RangeNoise noise = RangeNoise::depthCamera();

  // Input indices of the points of plane `index`.
  std::vector<std::uint32_t> pointsOf(std::size_t index) const;
};

// What extract() computes besides the planes. Per-point labels cost a pass over the points and
// 4 bytes a point (24 MB for a 6 M-point cloud); a caller that shows no per-point result (the
// nodelet when nobody listens to the labeled cloud, hope_extract without --labels or
// --overlay) can leave them out.
struct ExtractOutputs {
  bool point_labels = true;  // Result::point_labels; left empty when false
  // Result::objects, point_objects and each plane's free_area (point_labels are made too).
  bool objects = false;
  ObjectParams object_params;
};

class Extractor {
 public:
  // Throws std::invalid_argument when a parameter is out of range (see validate()).
  explicit Extractor(const Params& params = Params());
  ~Extractor();
  Extractor(Extractor&&) noexcept;
  Extractor& operator=(Extractor&&) noexcept;
  Extractor(const Extractor&) = delete;
  Extractor& operator=(const Extractor&) = delete;

  const Params& params() const { return params_; }

  // Finds the horizontal planes of one cloud. Non-finite points are skipped; an empty cloud,
  // or one with no horizontal surface, gives an empty result. Throws std::invalid_argument
  // only for input that cannot be a scene in metres (see VoxelGrid::build). Reuses internal
  // buffers across calls, so one Extractor must not run two clouds concurrently.
  Result extract(const PointsView& cloud, const Orientation& orientation,
                 const ExtractOutputs& outputs = ExtractOutputs());

  template <class PointT>
  Result extract(const pcl::PointCloud<PointT>& cloud, const Orientation& orientation,
                 const ExtractOutputs& outputs = ExtractOutputs()) {
    return extract(PointsView::of(cloud), orientation, outputs);
  }

  // The last call's points in the reference frame minus Result::local_origin, one per input
  // point, in input order (an overlay draws them). When the orientation needed no rotation and
  // no translation, extract() made no copy and they are the input cloud itself: then they are
  // valid only while that cloud lives.
  AlignedPoints alignedPoints() const;

 private:
  // The objects standing on result's planes and each plane's free area; `viewpoint` (the
  // sensor in the aligned points' frame, when known) lets touching objects come apart.
  void describeWhatStands(Result& result, const ObjectParams& object_params,
                          const std::optional<Eigen::Vector3d>& viewpoint) const;

  Params params_;
  // The stages' buffers, reused across calls (the grid, normals, candidates, links, labels).
  struct Buffers;
  std::unique_ptr<Buffers> buffers_;
};

}  // namespace hope
