// One frame's whole policy, the same for every front-end (the nodelet, hope_extract and
// Python): the orientation (as its source gives it, from an accelerometer averaged over a
// window, from the scene with smoothing and a hold, or given and refined by the scene), the
// extraction (extractor.h), what stands on the planes (standing_objects.h), persistent ids (the
// improved or paper tracker, or a map of the surfaces in a fixed frame) and placements on a
// frame that was processed. A front-end converts its input, calls process() and publishes
// the Frame; it decides nothing else.
#pragma once

#include <cstdint>
#include <deque>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "hope/extractor.h"
#include "hope/orientation.h"
#include "hope/params.h"
#include "hope/plane_tracker.h"
#include "hope/points_view.h"
#include "hope/surface_map.h"

namespace hope {

class UpEstimator;
class UpSmoother;
class SurfaceGrouping;
class SceneOdometry;
struct FloorMap;

// Up from the scene (up_estimation.h).
enum class SceneLevelling {
  kOff,
  // Up estimated from each frame's own level surfaces; the given orientation only says where
  // the sensor is (its viewpoint). Heights are relative to the sensor.
  kEstimate,
  // The given orientation corrected by the scene, by at most LevellingParams::max_correction_deg
  // and only by more than its level surfaces can tell (UpEstimator::refine).
  kRefine,
};

// "off", "estimate" (the nodelet's orientation_source scene) or "refine"; throws
// std::invalid_argument for anything else.
SceneLevelling sceneLevellingFromString(const std::string& name);
const char* toString(SceneLevelling levelling);

// How ids persist across frames.
enum class Identity {
  kImproved,  // the improved tracker (plane_tracker.h), frame to frame
  kPaper,     // the paper's nearest-neighbour plane matching (§2.5)
  kMap,       // a map of the surfaces (surface_map.h): needs poses in a fixed frame
  // The same map in a frame the scene's own odometry keeps fixed (scene_odometry.h): for an
  // orientation alone (an IMU, an accelerometer, up from the scene, rotation-only poses).
  kOdometry,
  // What fits the input (defaultIdentity): the front-end that knows its input resolves it
  // (resolveIdentity); a FramePipeline given it unresolved takes kOdometry, since nothing tells
  // it that its orientations are poses in a fixed frame.
  kAuto,
};

// What a front-end is given of the sensor's pose, for the default identity.
enum class PoseInput {
  // Poses in a frame fixed in the world, whose positions change as the sensor moves (ground
  // truth, a SLAM system's poses, Python's pose= or transform=).
  kFixedFramePoses,
  // An orientation alone: an IMU, an accelerometer, a fixed rotation, up from the scene, tf
  // into a frame that may move with the robot, or poses whose position never changes.
  kOrientation,
};

// The identity that fits `input`: the surface map for poses in a fixed frame, the same map in
// the scene odometry's world otherwise. Each beats the improved tracker on every dev sequence
// at every frame rate tried (docs/id_rates.md: kitchen_dev with poses 87.4 % against 73.0 %,
// with the accelerometer 85.2 % against 70.4 %); the odometry works in any frame, so it is
// the default wherever the frame's fixedness is unknown.
Identity defaultIdentity(PoseInput input);
// kAuto replaced by defaultIdentity(input); any other identity is kept.
Identity resolveIdentity(Identity identity, PoseInput input);

// Whether `identity` keeps the surface map (kMap, kOdometry, and kAuto, which resolves to one).
bool keepsSurfaceMap(Identity identity);

// "auto", "improved", "paper", "map" or "odometry"; throws std::invalid_argument for anything
// else.
Identity identityFromString(const std::string& name);
const char* toString(Identity identity);

struct PipelineOptions {
  Params extraction;
  // What stands on the planes, computed in frames that ask for it (FrameOutputs::objects).
  bool objects = true;
  ObjectParams object_params;
  Identity identity = Identity::kAuto;
  SceneLevelling levelling = SceneLevelling::kOff;
  // The largest correction a refinement makes, degrees.
  double level_bound_deg = 5.0;
  // The share of each frame's up in the running one (UpSmoother): one view's depth noise does
  // not rock the reference frame; a turn of more than 10° starts it afresh. In (0, 1]. A
  // refinement's correction (in the reference frame, where it stays while the sensor moves)
  // takes this share in every frame; an estimate's up (in the sensor's frame, which turns with
  // it) takes it for frames 1/30 s apart and more for frames further apart,
  // 1 − (1 − share)^(30 Δt): a recording at 3 Hz is hardly smoothed.
  double level_smoothing = 0.3;
  // Estimate: a frame with nothing level in view (the camera facing a wall) keeps the last up
  // for this many seconds, since a sensor rarely turns much in a moment; after that frames are
  // skipped. 0 skips at once.
  double level_hold_s = 1.0;
  // An accelerometer's samples are averaged over this many seconds of stamps (the frame's own
  // included), so that the sensor's shake does not tilt the reference frame from frame to
  // frame: 3 frames of a 30 Hz camera, one of a slower one. A longer window lags a turning
  // sensor: on studyroom_dev (30 Hz, turning) 0.33 s cost 14 points of area-weighted IDF1
  // (docs/quality.md).
  double gravity_window_s = 0.1;
  // Obstacles (FrameOutputs::obstacles): the points more than obstacle_min_height and at most
  // obstacle_max_height above the floor under them, metres: above the floor's noise and a
  // threshold a robot drives over, below a ceiling it passes under.
  double obstacle_min_height = 0.05;
  double obstacle_max_height = 2.0;
  // The floor grid's cells (Frame::floor_grid), metres a side: a robot's footprint is a few
  // of them.
  double grid_resolution = 0.05;
  // The surface map (Identity::kMap) ends the id of a surface not seen in this many frames in
  // a row (SurfaceMapOptions::forget_after_frames): seen again, it takes a new one, as the
  // tracker's ids end after 30 missed frames. 0 keeps it however long (a table looked away
  // from keeps its id).
  int map_forget_frames = SurfaceMapOptions().forget_after_frames;
};

// Throws std::invalid_argument naming the option and its range (the extraction's, the
// objects' and the levelling's parameters included).
void validate(const PipelineOptions& options);

// What a frame computes besides its planes and ids; each costs time a caller that does not
// show it can save.
struct FrameOutputs {
  bool point_labels = true;  // Result::point_labels
  bool objects = true;       // Result::objects (when PipelineOptions::objects)
  // Keep the frame's aligned points (Frame::points, 12 bytes a point): findPlacements() answers
  // on the frame later from them, an overlay draws them. Point labels are made too.
  bool keep_points = false;
  // Frame::obstacles and Frame::floor_index: one pass over the points.
  bool obstacles = false;
  // Frame::floor_grid and Frame::floor_index: one pass over the points.
  bool floor_grid = false;
};

// The floor as a navigation grid, nav_msgs/OccupancyGrid's layout and values: cells of
// `resolution` metres in the reference frame, row by row (x along a row, rows along y) from the
// cell whose corner is `origin`. A cell is kOccupied when a point between the obstacle heights
// above the floor fell in it, kFree when only the floor's points (within obstacle_min_height,
// at least r_z, of it) did, kUnseen otherwise.
struct FloorGrid {
  static constexpr std::int8_t kUnseen = -1, kFree = 0, kOccupied = 100;
  double resolution = 0;
  Eigen::Vector2d origin = Eigen::Vector2d::Zero();  // x y of cell (0, 0)'s corner, metres
  double floor_height = 0;                           // the floor plane's height, metres
  int width = 0, height = 0;                         // cells along x, along y
  std::vector<std::int8_t> cells;                    // width × height, row-major
};

struct Frame {
  double stamp = 0;
  // False when the frame was skipped: `skipped` says why (nothing level in view and no up to
  // hold). A cloud that cannot be a scene throws std::invalid_argument instead.
  bool processed = false;
  std::string skipped;
  // The planes with their persistent ids (and age, last_seen), objects with their plane's id.
  Result result;
  std::vector<TrackEvent> events;
  // The orientation the frame was extracted with.
  Orientation orientation = Orientation::identity();
  // The scene's estimate or refinement, when levelling is on (its `applied` false: the given
  // orientation was kept); `level_held`: nothing level in view, the last up held.
  std::optional<UpEstimate> levelling;
  bool level_held = false;
  // The stamp went back (a looping bag, a reset clock): tracks, the gravity average and the
  // running up started afresh before this frame. The surface map stays: it holds places.
  bool time_jump = false;
  // FrameOutputs::keep_points: the points in the reference frame less Result::local_origin, one
  // per input point, in input order (findPlacements() reads them).
  std::vector<Eigen::Vector3f> points;
  // FrameOutputs::obstacles: the floor (the lowest plane seen from above with at least
  // 0.25 m², an index into result.planes; -1: none in view, and then no obstacles), and the
  // input indices of the points between PipelineOptions' obstacle heights above it, in order.
  int floor_index = -1;
  std::vector<std::uint32_t> obstacles;
  // FrameOutputs::floor_grid: this frame's grid (empty, width 0, without a floor in view); with
  // Identity::kMap, every frame's so far laid over each other in the fixed frame (a cell takes
  // the latest look, an occupied one freed after 3 free looks in a row; resetMap() and a new
  // grid_resolution start it afresh).
  FloorGrid floor_grid;
  // Milliseconds spent giving the planes their ids (the tracker's or the map's update).
  double identity_ms = 0;
  // Identity::kOdometry: whether the scene odometry aligned this frame with the last (false on
  // the first frame, which starts its world, and where it lost the scene: the map's own gates
  // then keep what it misplaces from taking an id), whether this frame started its world (the
  // first frame, and the first after a reset, a time jump or a new r_z), the share of the
  // frame's voxels that lie on the last frame's surfaces (OdometryParams::min_overlap), and its
  // milliseconds. The frame's planes and objects stay in the given orientation's frame; the map
  // holds them in the odometry's world, where world_from_frame carries this frame's (the
  // orientation's reference frame's) coordinates.
  struct Odometry {
    bool tracked = false;
    bool started = false;
    double overlap = 0;
    double ms = 0;
    Eigen::Isometry3d world_from_frame = Eigen::Isometry3d::Identity();
  };
  std::optional<Odometry> odometry;
};

// Counts since the pipeline was made, for diagnostics.
struct PipelineCounters {
  std::size_t frames = 0, skipped = 0, time_jumps = 0;
  // Levelling: frames whose up came from their scene, estimates refused with the last up held,
  // and refinements not applied (the given orientation kept).
  std::size_t levelled = 0, level_held = 0, uncorrected = 0;
};

class FramePipeline {
 public:
  // Throws std::invalid_argument for an option out of range (validate()).
  explicit FramePipeline(const PipelineOptions& options = PipelineOptions());
  ~FramePipeline();
  FramePipeline(const FramePipeline&) = delete;
  FramePipeline& operator=(const FramePipeline&) = delete;

  // One frame whose orientation its source gives: a pose, a tf transform, an IMU's quaternion,
  // a fixed rotation (with estimate levelling, only its viewpoint is used). `stamp` in
  // seconds. Throws std::invalid_argument for a cloud that cannot be a scene in metres.
  Frame process(const PointsView& cloud, double stamp, const Orientation& given,
                const FrameOutputs& outputs = FrameOutputs());
  // One frame whose orientation comes from an accelerometer: its specific force in the
  // cloud's frame (m/s², pointing up at rest), averaged with the samples of the last
  // gravity_window_s; the sensor at `viewpoint` (default: the origin). Throws
  // std::invalid_argument for a sample that cannot be gravity (not 1–30 m/s²).
  Frame processWithGravity(const PointsView& cloud, double stamp,
                           const Eigen::Vector3d& specific_force,
                           const FrameOutputs& outputs = FrameOutputs(),
                           const Eigen::Vector3d& viewpoint = Eigen::Vector3d::Zero());

  // One cloud on its own (hope_extract --input, Python's Extractor): levelled from its own scene
  // alone when levelling is on (a refusal skips it: Frame::skipped says why, there is no earlier
  // up to hold), its planes numbered in extraction order; no stamp, and the pipeline's tracks,
  // map, gravity average and running up are neither read nor changed.
  Frame processAlone(const PointsView& cloud, const Orientation& given,
                     const FrameOutputs& outputs = FrameOutputs());

  // Where `query`'s footprint fits on `frame`'s planes: a frame processed with
  // FrameOutputs::keep_points (placement.h). Throws std::invalid_argument otherwise, or for a bad
  // footprint or plane index.
  std::vector<Placement> findPlacements(const Frame& frame, const PlacementQuery& query) const;

  // New options between frames. The tracker restarts when the identity changes; the map when
  // its cells (r_xy) or extension gate (r_z) change, ids going on. Returns what was restarted,
  // for the front-end to say; throws std::invalid_argument (nothing changes) for a bad option.
  std::vector<std::string> setOptions(const PipelineOptions& options);
  const PipelineOptions& options() const { return options_; }

  // The map's entries (Identity::kMap; Identity::kOdometry: in the odometry's world, the first
  // frame's), oldest first; forgetting them (and the floor grid's map), ids going on.
  std::vector<HorizontalPlane> mapSurfaces() const;
  std::size_t mapSize() const;
  void resetMap();
  // Tracks, the gravity average and the running up start afresh (the map stays, but for
  // Identity::kOdometry, whose world starts afresh with it).
  void restart();

  const PipelineCounters& counters() const { return counters_; }
  // The running up (estimate: in the sensor's frame; refine: in the reference frame), when
  // there is one.
  std::optional<Eigen::Vector3d> smoothedUp() const;

 private:
  // The orientation levelled from the scene as options_.levelling says; false when the frame
  // is to be skipped (`frame.skipped` then says why).
  bool level(const PointsView& cloud, Orientation& orientation, Frame& frame);
  // `identify`: the planes take persistent ids from the tracker or the map.
  Frame extractAndIdentify(const PointsView& cloud, Frame frame, const Orientation& orientation,
                           const FrameOutputs& outputs, bool identify = true);
  void noteStamp(double stamp, Frame& frame);

  PipelineOptions options_;
  Extractor extractor_;
  std::unique_ptr<UpEstimator> up_estimator_;
  std::unique_ptr<UpSmoother> up_smoother_;
  std::optional<double> last_level_stamp_;  // the last frame whose own scene gave up
  PlaneTracker tracker_;
  SurfaceMap map_;
  std::unique_ptr<FloorMap> floor_map_;        // Identity::kMap: the frames' floor grids, overlaid
  std::unique_ptr<SurfaceGrouping> surfaces_;  // the pieces of one surface (surface_id)
  std::unique_ptr<SceneOdometry> odometry_;    // Identity::kOdometry: the map's fixed frame
  struct GravitySample {
    double stamp;
    Eigen::Vector3d force;
  };
  std::deque<GravitySample> gravity_;
  std::optional<double> last_stamp_;
  // The map's check of its input: the first frame's sensor pose, whether the sensor has moved
  // since, and whether the warning was given (mapInputWarning()).
  std::optional<Eigen::Isometry3d> first_map_pose_;
  bool map_sensor_moved_ = false, map_warned_ = false;
  // A warning, once, when the map's poses turn the sensor but never move it (an orientation
  // written as a pose, a tf whose translation is fixed): the map needs a fixed frame.
  std::optional<std::string> mapInputWarning(const Orientation& orientation);
  PipelineCounters counters_;
};

}  // namespace hope
