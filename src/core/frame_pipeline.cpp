#include "hope/frame_pipeline.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <iomanip>
#include <sstream>
#include <stdexcept>

#include "hope/floor_grid.h"
#include "hope/gravity_alignment.h"
#include "hope/obstacle_points.h"
#include "hope/placement.h"
#include "hope/scene_odometry.h"
#include "hope/standing_objects.h"
#include "hope/surface_grouping.h"
#include "hope/up_estimation.h"

namespace hope {

namespace {

// Identity::kAuto as a pipeline that knows nothing of a fixed frame takes it (frame_pipeline.h).
PipelineOptions withIdentityResolved(PipelineOptions options) {
  options.identity = resolveIdentity(options.identity, PoseInput::kOrientation);
  return options;
}

TrackerOptions trackerOptionsFor(Identity identity) {
  TrackerOptions options;
  options.mode = identity == Identity::kPaper ? TrackingMode::kPaper : TrackingMode::kImproved;
  return options;
}

// The map's cells and gates follow the extraction's grid (surfaceMapOptionsFor), its memory
// the pipeline's option.
SurfaceMapOptions mapOptionsFor(const PipelineOptions& options) {
  SurfaceMapOptions map = surfaceMapOptionsFor(options.extraction);
  map.forget_after_frames = options.map_forget_frames;
  return map;
}

// `plane` as seen in the frame `world_from_frame` takes it to (a turn about z and a shift: the
// odometry's), as the map reads it: height, centroid, normal, hull, outline and their box.
HorizontalPlane carried(const HorizontalPlane& plane, const Eigen::Isometry3d& world_from_frame) {
  HorizontalPlane out = plane;
  out.height += world_from_frame.translation().z();
  out.centroid = world_from_frame * plane.centroid;
  out.normal = world_from_frame.linear() * plane.normal;
  Eigen::Vector2d lo(HUGE_VAL, HUGE_VAL), hi(-HUGE_VAL, -HUGE_VAL);
  const auto take = [&](Eigen::Vector3d& p) {
    p = world_from_frame * p;
    lo = lo.cwiseMin(p.head<2>());
    hi = hi.cwiseMax(p.head<2>());
  };
  for (Eigen::Vector3d& p : out.hull) take(p);
  for (auto& ring : out.outline) {
    for (Eigen::Vector3d& p : ring) take(p);
  }
  if (out.hull.empty() && out.outline.empty()) {
    const auto& b = plane.bbox;
    for (Eigen::Vector3d corner :
         {Eigen::Vector3d(b[0], b[1], plane.height), Eigen::Vector3d(b[2], b[1], plane.height),
          Eigen::Vector3d(b[0], b[3], plane.height), Eigen::Vector3d(b[2], b[3], plane.height)}) {
      take(corner);
    }
  }
  out.bbox = {lo.x(), lo.y(), hi.x(), hi.y()};
  return out;
}

// The odometry's finest voxel follows the extraction's vertical step: 1.5 r_z (3 cm at the
// default 2 cm), so that a surface's voxels hold its samples and their noise.
OdometryParams odometryParamsFor(const Params& extraction) {
  OdometryParams params;
  params.cell = 1.5 * extraction.r_z;
  params.level_tilt_deg = std::atan(extraction.gamma()) * 180.0 / M_PI;  // Eq 3
  return params;
}

LevellingParams levellingFor(const PipelineOptions& options) {
  LevellingParams params = LevellingParams::forExtraction(options.extraction);
  params.max_correction_deg = options.level_bound_deg;
  return params;
}

}  // namespace

SceneLevelling sceneLevellingFromString(const std::string& name) {
  if (name == "off") return SceneLevelling::kOff;
  if (name == "estimate") return SceneLevelling::kEstimate;
  if (name == "refine") return SceneLevelling::kRefine;
  throw std::invalid_argument("levelling '" + name + "' is not one of off, estimate, refine");
}

const char* toString(SceneLevelling levelling) {
  switch (levelling) {
    case SceneLevelling::kEstimate:
      return "estimate";
    case SceneLevelling::kRefine:
      return "refine";
    case SceneLevelling::kOff:
      break;
  }
  return "off";
}

Identity defaultIdentity(PoseInput input) {
  return input == PoseInput::kFixedFramePoses ? Identity::kMap : Identity::kOdometry;
}

Identity resolveIdentity(Identity identity, PoseInput input) {
  return identity == Identity::kAuto ? defaultIdentity(input) : identity;
}

Identity identityFromString(const std::string& name) {
  if (name == "auto") return Identity::kAuto;
  if (name == "improved") return Identity::kImproved;
  if (name == "paper") return Identity::kPaper;
  if (name == "map") return Identity::kMap;
  if (name == "odometry") return Identity::kOdometry;
  throw std::invalid_argument("tracking '" + name +
                              "' is not one of auto, improved, paper, map, odometry");
}

const char* toString(Identity identity) {
  switch (identity) {
    case Identity::kPaper:
      return "paper";
    case Identity::kMap:
      return "map";
    case Identity::kOdometry:
      return "odometry";
    case Identity::kAuto:
      return "auto";
    case Identity::kImproved:
      break;
  }
  return "improved";
}

bool keepsSurfaceMap(Identity identity) {
  return identity == Identity::kMap || identity == Identity::kOdometry ||
         identity == Identity::kAuto;
}

void validate(const PipelineOptions& options) {
  validate(options.extraction);
  validate(options.object_params);
  validate(levellingFor(options));
  if (!(options.level_smoothing > 0 && options.level_smoothing <= 1)) {
    throw std::invalid_argument("level_smoothing must be in (0, 1] (got " +
                                std::to_string(options.level_smoothing) + ")");
  }
  if (!(options.level_hold_s >= 0 && options.level_hold_s <= 3600)) {
    throw std::invalid_argument("level_hold_s must be in [0, 3600] seconds (got " +
                                std::to_string(options.level_hold_s) + ")");
  }
  if (!(options.gravity_window_s >= 0 && options.gravity_window_s <= 60)) {
    throw std::invalid_argument("gravity_window_s must be in [0, 60] seconds (got " +
                                std::to_string(options.gravity_window_s) + ")");
  }
  // Ranges that meet at 1 m: the band is never empty.
  if (!(options.obstacle_min_height >= 0 && options.obstacle_min_height <= 1)) {
    throw std::invalid_argument("obstacle_min_height must be in [0, 1] m (got " +
                                std::to_string(options.obstacle_min_height) + ")");
  }
  if (!(options.obstacle_max_height > 1 && options.obstacle_max_height <= 100)) {
    throw std::invalid_argument("obstacle_max_height must be in (1, 100] m (got " +
                                std::to_string(options.obstacle_max_height) + ")");
  }
  if (!(options.map_forget_frames >= 0 && options.map_forget_frames <= 1000000)) {
    throw std::invalid_argument("map_forget_frames must be in [0, 1000000] frames (got " +
                                std::to_string(options.map_forget_frames) + ")");
  }
  if (!(options.grid_resolution >= 0.005 && options.grid_resolution <= 10)) {
    throw std::invalid_argument("grid_resolution must be in [0.005, 10] m (got " +
                                std::to_string(options.grid_resolution) + ")");
  }
}

FramePipeline::FramePipeline(const PipelineOptions& options)
    : options_((validate(options), withIdentityResolved(options))),
      extractor_(options.extraction),
      up_smoother_(std::make_unique<UpSmoother>(options.level_smoothing)),
      tracker_(trackerOptionsFor(options_.identity)),
      map_(mapOptionsFor(options_)),
      floor_map_(std::make_unique<FloorMap>()),
      surfaces_(std::make_unique<SurfaceGrouping>(surfaceGroupingOptionsFor(options.extraction))),
      odometry_(std::make_unique<SceneOdometry>(odometryParamsFor(options.extraction))) {}

FramePipeline::~FramePipeline() = default;

std::vector<std::string> FramePipeline::setOptions(const PipelineOptions& given) {
  validate(given);
  const PipelineOptions options = withIdentityResolved(given);
  std::vector<std::string> notes;
  extractor_ = Extractor(options.extraction);
  if (options.identity != options_.identity) {
    tracker_ = PlaneTracker(trackerOptionsFor(options.identity));
    // The odometry's world is not the poses' fixed frame: the map starts afresh across them.
    if ((options.identity == Identity::kOdometry || options_.identity == Identity::kOdometry) &&
        map_.size() > 0) {
      notes.push_back("surface map restarted: tracking " +
                      std::string(toString(options_.identity)) + " -> " +
                      toString(options.identity) + " changes its frame; " +
                      std::to_string(map_.size()) + " surfaces forgotten");
      map_.reset();
    }
    odometry_->reset();
    if (!keepsSurfaceMap(options.identity) && map_.size() > 0) {
      notes.push_back("tracking " + std::string(toString(options.identity)) +
                      ": the surface map's " + std::to_string(map_.size()) +
                      " surfaces are no longer used");
    }
  }
  // The map's cells are r_xy and its extension gate r_z: other values start it afresh (ids go
  // on, never given twice); so does another memory.
  const SurfaceMapOptions map_options = mapOptionsFor(options);
  const SurfaceMapOptions& in_use = map_.options();
  std::string why;
  if (map_options.cell != in_use.cell ||
      map_options.max_extension_height_change != in_use.max_extension_height_change) {
    why = "its cells follow r_xy (" + std::to_string(in_use.cell) + " -> " +
          std::to_string(map_options.cell) + " m) and r_z";
  } else if (map_options.forget_after_frames != in_use.forget_after_frames) {
    why = "map_forget_frames " + std::to_string(in_use.forget_after_frames) + " -> " +
          std::to_string(map_options.forget_after_frames);
  }
  if (!why.empty()) {
    if (map_.size() > 0) {
      notes.push_back("surface map restarted: " + why + "; " + std::to_string(map_.size()) +
                      " surfaces forgotten");
    }
    map_.reset(map_options);
  }
  if (options.grid_resolution != options_.grid_resolution || options.identity != Identity::kMap) {
    *floor_map_ = FloorMap();  // its cells are the resolution's
  }
  if (levellingFor(options).cell != levellingFor(options_).cell ||
      options.level_bound_deg != options_.level_bound_deg) {
    up_estimator_.reset();  // made again with the new grid on the next frame
  }
  if (options.level_smoothing != options_.level_smoothing ||
      options.levelling != options_.levelling) {
    *up_smoother_ = UpSmoother(options.level_smoothing);
    last_level_stamp_.reset();
  }
  if (options.extraction.r_z != options_.extraction.r_z) {
    *surfaces_ = SurfaceGrouping(surfaceGroupingOptionsFor(options.extraction));
    *odometry_ = SceneOdometry(odometryParamsFor(options.extraction));  // its voxels follow r_z
  }
  options_ = options;
  return notes;
}

std::vector<HorizontalPlane> FramePipeline::mapSurfaces() const { return map_.surfaces(); }

std::size_t FramePipeline::mapSize() const { return map_.size(); }

void FramePipeline::resetMap() {
  map_.reset();
  odometry_->reset();  // a new world for a new map
  *floor_map_ = FloorMap();
  first_map_pose_.reset();
  map_sensor_moved_ = map_warned_ = false;
}

std::optional<std::string> FramePipeline::mapInputWarning(const Orientation& orientation) {
  const Eigen::Isometry3d& pose = orientation.sensorToReference();
  if (!first_map_pose_) first_map_pose_ = pose;
  // A hand-held or mounted sensor's position changes by more than a millimetre between any
  // two poses a tracking system gives while it turns by 10°; an orientation written as a pose
  // keeps it exactly.
  map_sensor_moved_ =
      map_sensor_moved_ || (pose.translation() - first_map_pose_->translation()).norm() > 1e-3;
  const double turned_deg =
      Eigen::AngleAxisd(first_map_pose_->linear().transpose() * pose.linear()).angle() * 180.0 /
      M_PI;
  if (map_sensor_moved_ || map_warned_ || turned_deg < 10.0) return std::nullopt;
  map_warned_ = true;
  return "tracking map: the sensor turned " + std::to_string(static_cast<int>(turned_deg)) +
         " degrees and its position never changed: an orientation only (an IMU, rotation-only "
         "poses, a tf with a fixed translation)? The surface map needs the sensor's pose in a "
         "fixed frame; if the sensor moves, its ids will not hold (use tracking improved)";
}

void FramePipeline::restart() {
  tracker_.reset();
  gravity_.clear();
  up_smoother_->reset();
  last_level_stamp_.reset();
  surfaces_->reset();
  // The odometry's world ends with the time it was built in: the map in it starts afresh.
  if (options_.identity == Identity::kOdometry) resetMap();
}

std::optional<Eigen::Vector3d> FramePipeline::smoothedUp() const {
  if (up_smoother_->empty()) return std::nullopt;
  return up_smoother_->value();
}

void FramePipeline::noteStamp(double stamp, Frame& frame) {
  frame.stamp = stamp;
  // A stamp older than the last: a bag started over, or a clock was reset; one source's stamps
  // never go back otherwise. Tracks, the gravity average and the running up belong to another
  // time; new ids continue from the last one.
  if (last_stamp_ && stamp < *last_stamp_) {
    restart();
    frame.time_jump = true;
    ++counters_.time_jumps;
  }
  last_stamp_ = stamp;
}

Frame FramePipeline::process(const PointsView& cloud, double stamp, const Orientation& given,
                             const FrameOutputs& outputs) {
  Frame frame;
  noteStamp(stamp, frame);
  Orientation orientation = given;
  if (!level(cloud, orientation, frame)) return frame;
  return extractAndIdentify(cloud, std::move(frame), orientation, outputs);
}

Frame FramePipeline::processWithGravity(const PointsView& cloud, double stamp,
                                        const Eigen::Vector3d& specific_force,
                                        const FrameOutputs& outputs,
                                        const Eigen::Vector3d& viewpoint) {
  // stableNorm: a corrupt sample of 1e300 m/s² is said as such, not as infinite.
  const double magnitude = specific_force.stableNorm();
  if (!specific_force.allFinite() || !(magnitude >= 1.0 && magnitude <= 30.0)) {
    std::ostringstream why;
    why << "an accelerometer sample of " << std::setprecision(2) << magnitude
        << " m/s² is not gravity; is it in m/s²?";
    throw std::invalid_argument(why.str());
  }
  if (options_.identity == Identity::kMap) {
    throw std::invalid_argument(
        "the surface map needs poses in a fixed frame; an accelerometer gives an orientation "
        "only (use tracking odometry or improved)");
  }
  Frame frame;
  noteStamp(stamp, frame);
  gravity_.push_back({stamp, specific_force});
  while (gravity_.size() > 1 && gravity_.front().stamp < stamp - options_.gravity_window_s) {
    gravity_.pop_front();
  }
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (const GravitySample& g : gravity_) mean += g.force;
  Orientation orientation =
      Orientation::fromGravity(mean.x(), mean.y(), mean.z()).withViewpoint(viewpoint);
  if (!level(cloud, orientation, frame)) return frame;
  return extractAndIdentify(cloud, std::move(frame), orientation, outputs);
}

Frame FramePipeline::processAlone(const PointsView& cloud, const Orientation& given,
                                  const FrameOutputs& outputs) {
  Frame frame;
  Orientation orientation = given;
  if (options_.levelling != SceneLevelling::kOff) {
    if (!up_estimator_) up_estimator_ = std::make_unique<UpEstimator>(levellingFor(options_));
    try {
      frame.levelling = options_.levelling == SceneLevelling::kEstimate
                            ? up_estimator_->estimate(cloud)
                            : up_estimator_->refine(cloud, given);
    } catch (const LevellingError& error) {
      frame.skipped = error.what();  // no earlier up to hold: the cloud stands alone
      return frame;
    }
    // As process() turns a first frame: the given orientation about the sensor.
    if (frame.levelling->applied) orientation = levelledTo(given, frame.levelling->up_in_sensor);
  }
  return extractAndIdentify(cloud, std::move(frame), orientation, outputs, false);
}

bool FramePipeline::level(const PointsView& cloud, Orientation& orientation, Frame& frame) {
  if (options_.levelling == SceneLevelling::kOff) return true;
  if (!up_estimator_) up_estimator_ = std::make_unique<UpEstimator>(levellingFor(options_));
  if (options_.levelling == SceneLevelling::kEstimate) {
    try {
      frame.levelling = up_estimator_->estimate(cloud);
      // The share options_.level_smoothing is for frames 1/30 s apart; a frame later than that
      // weighs more, since the sensor may have turned since (header).
      const double since = last_level_stamp_ ? frame.stamp - *last_level_stamp_ : 0.0;
      const double share =
          1.0 - std::pow(1.0 - options_.level_smoothing, std::max(1.0, 30.0 * since));
      orientation =
          levelledTo(orientation, up_smoother_->add(frame.levelling->up_in_sensor, share));
      last_level_stamp_ = frame.stamp;
      ++counters_.levelled;
      return true;
    } catch (const LevellingError& error) {
      // Nothing level in view: the last up holds for a while, then frames are skipped.
      frame.skipped = error.what();
      if (up_smoother_->empty() || !last_level_stamp_ ||
          frame.stamp - *last_level_stamp_ > options_.level_hold_s) {
        ++counters_.skipped;
        return false;
      }
      frame.level_held = true;
      ++counters_.level_held;
      orientation = levelledTo(orientation, up_smoother_->value());
      return true;
    }
  }
  // Refinement: the scene's up in the given reference frame (near +z) is what is smoothed, so
  // that a moving sensor's orientation keeps coming from its source.
  frame.levelling = up_estimator_->refine(cloud, orientation);
  const Eigen::Matrix3d rotation = orientation.sensorToReference().linear();
  if (frame.levelling->applied) {
    up_smoother_->add(rotation * frame.levelling->up_in_sensor);
    ++counters_.levelled;
  } else {
    ++counters_.uncorrected;
  }
  if (!up_smoother_->empty()) {
    orientation = levelledTo(orientation, rotation.transpose() * up_smoother_->value());
  }
  return true;
}

Frame FramePipeline::extractAndIdentify(const PointsView& cloud, Frame frame,
                                        const Orientation& orientation, const FrameOutputs& outputs,
                                        bool identify) {
  frame.orientation = orientation;
  // Identity::kOdometry: where this frame's reference frame lies in the odometry's world. The
  // frame is extracted as given (its planes and objects are what the tracker's frame gives);
  // only the map sees them carried into that world.
  std::optional<Eigen::Isometry3d> world_from_frame;
  std::vector<HorizontalPlane> in_world;  // the planes there
  std::optional<Eigen::Vector3d> world_eye = orientation.viewpoint();
  if (identify && options_.identity == Identity::kOdometry) {
    const auto start = std::chrono::steady_clock::now();
    const OdometryStep step = odometry_->update(cloud, orientation.sensorToReference());
    world_from_frame = step.world_from_frame;
    Frame::Odometry report;
    report.tracked = step.tracked;
    report.started = step.started;
    report.overlap = step.overlap;
    report.world_from_frame = step.world_from_frame;
    report.ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    frame.odometry = report;
  }
  ExtractOutputs wanted;
  wanted.point_labels = outputs.point_labels || outputs.keep_points;
  wanted.objects = options_.objects && outputs.objects;
  wanted.object_params = options_.object_params;
  frame.result = extractor_.extract(cloud, orientation, wanted);
  const auto start = std::chrono::steady_clock::now();
  // Not identified: the ids stay the extraction order, the objects' plane ids already theirs.
  if (identify && options_.identity == Identity::kMap) {
    if (auto warning = mapInputWarning(orientation)) frame.result.warnings.push_back(*warning);
    frame.events = map_.update(frame.result.planes, frame.stamp, orientation.viewpoint());
  } else if (world_from_frame) {
    // The planes carried into the odometry's world for the map; their ids come back below.
    in_world.reserve(frame.result.planes.size());
    for (const HorizontalPlane& plane : frame.result.planes) {
      in_world.push_back(carried(plane, *world_from_frame));
    }
    if (world_eye) world_eye = *world_from_frame * *world_eye;
    frame.events = map_.update(in_world, frame.stamp, world_eye);
  } else if (identify) {
    frame.events = tracker_.update(frame.result.planes, frame.stamp);
  }
  frame.identity_ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  // The noise the extraction judged the sensor by: how far one surface's pieces may differ in
  // height at their ranges.
  if (world_from_frame) {
    // The pieces of one surface in the odometry's world too: the boxes their ids had in the
    // last second lie there, wherever the sensor turned.
    surfaces_->assign(in_world, frame.stamp, world_eye, frame.result.noise, identify);
    for (std::size_t k = 0; k < in_world.size(); ++k) {
      HorizontalPlane& plane = frame.result.planes[k];
      plane.id = in_world[k].id;
      plane.age = in_world[k].age;
      plane.last_seen = in_world[k].last_seen;
      plane.split_from = in_world[k].split_from;
      plane.surface_id = in_world[k].surface_id;
    }
  } else {
    surfaces_->assign(frame.result.planes, frame.stamp, orientation.viewpoint(), frame.result.noise,
                      identify);
  }
  // The objects were found under the frame's own plane indices; the planes (in the same order)
  // now carry their persistent ids.
  for (StandingObject& o : frame.result.objects) {
    o.plane_id = frame.result.planes[o.plane_index].id;
  }
  const std::optional<std::size_t> floor =
      outputs.obstacles || outputs.floor_grid ? findFloor(frame.result.planes) : std::nullopt;
  if (floor) {
    frame.floor_index = static_cast<int>(*floor);
    const HorizontalPlane& floor_plane = frame.result.planes[*floor];
    if (outputs.obstacles && !outputs.floor_grid) {
      frame.obstacles =
          obstaclePoints(extractor_.alignedPoints(), frame.result.local_origin, floor_plane,
                         options_.obstacle_min_height, options_.obstacle_max_height);
    }
    if (outputs.floor_grid) {
      // Centred on the sensor where it is known, else on the floor.
      const Eigen::Vector3d centre = orientation.viewpoint().value_or(floor_plane.centroid);
      // The floor's own points lie within its clustering tolerance r_z of its plane (§2.3).
      frame.floor_grid = floorGrid(
          extractor_.alignedPoints(), frame.result.local_origin, floor_plane, centre.head<2>(),
          std::max(options_.obstacle_min_height, options_.extraction.r_z),
          options_.obstacle_min_height, options_.obstacle_max_height, options_.grid_resolution,
          outputs.obstacles ? &frame.obstacles : nullptr);  // both outputs from one pass
      if (identify && options_.identity == Identity::kMap) {
        accumulate(*floor_map_, frame.floor_grid, centre.head<2>());
      }
    }
  }
  // With the map (a fixed frame), the frames' grids add up to a map of the floor, given in
  // frames without a floor in view too.
  if (outputs.floor_grid && identify && options_.identity == Identity::kMap) {
    frame.floor_grid = floor_map_->grid;
  }
  if (outputs.keep_points) {
    const AlignedPoints points = extractor_.alignedPoints();
    frame.points.resize(points.size());
    for (std::size_t i = 0; i < points.size(); ++i) frame.points[i] = points[i];
  }
  frame.processed = true;
  ++counters_.frames;
  return frame;
}

std::vector<Placement> FramePipeline::findPlacements(const Frame& frame,
                                                     const PlacementQuery& query) const {
  if (!frame.processed || frame.points.size() != frame.result.point_labels.size() ||
      frame.points.empty()) {
    throw std::invalid_argument("placements need a frame processed with FrameOutputs::keep_points");
  }
  return hope::findPlacements(AlignedPoints(frame.points), frame.result.planes,
                              frame.result.point_labels, frame.result.local_origin,
                              options_.extraction, query);
}

}  // namespace hope
