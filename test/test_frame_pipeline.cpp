// The frame pipeline's policy, against scenes with a known answer: ids kept over a rendered
// sequence, an accelerometer averaged over its window, up from the scene held while nothing
// level is in view, a restart when time goes back, placements on a frame asked later.
#include <cmath>
#include <map>
#include <set>

#include <gtest/gtest.h>

#include "hope/depth_image.h"
#include "hope/frame_pipeline.h"
#include "hope/synthetic/sequences.h"

namespace hope {
namespace {

constexpr double kDegree = M_PI / 180.0;

struct RenderedCloud {
  pcl::PointCloud<pcl::PointXYZ> cloud;
  std::vector<int> truth;  // surface per point
  synthetic::Camera camera;
};

RenderedCloud renderFrame(const synthetic::TrackingScene& scene, const synthetic::Camera& camera) {
  const auto frame = scene.render(camera, Eigen::Vector2d(100, 100), synthetic::SensorNoise());
  RenderedCloud r;
  r.cloud = depthToCloud(frame.depth, camera.intrinsics, 1.0);
  r.truth.assign(frame.labels.begin<std::int32_t>(), frame.labels.end<std::int32_t>());
  r.camera = camera;
  return r;
}

std::vector<RenderedCloud> renderPan(int frames, int width) {
  const synthetic::TrackingScene scene;
  const auto sequence = synthetic::makeTrackingSequence("pan", frames, width);
  std::vector<RenderedCloud> out;
  for (const auto& f : sequence.frames) out.push_back(renderFrame(scene, f.camera));
  return out;
}

// The id of the plane holding most of `surface`'s points, or -1.
int idOfSurface(const Frame& frame, const std::vector<int>& truth, int surface) {
  std::map<int, std::size_t> points_of_plane;
  for (std::size_t i = 0; i < truth.size(); ++i) {
    if (truth[i] == surface && frame.result.point_labels[i] >= 0) {
      ++points_of_plane[frame.result.point_labels[i]];
    }
  }
  int best = -1;
  std::size_t most = 0;
  for (const auto& [plane, n] : points_of_plane) {
    if (n > most) most = n, best = frame.result.planes[plane].id;
  }
  return best;
}

// For each plane of the frame, the true surface most of its points lie on (-1: none).
std::vector<int> trueSurfaceOfEachPlane(const Frame& frame, const std::vector<int>& truth) {
  std::vector<std::map<int, std::size_t>> counts(frame.result.planes.size());
  for (std::size_t i = 0; i < truth.size(); ++i) {
    const int plane = frame.result.point_labels[i];
    if (plane >= 0) ++counts[plane][truth[i]];
  }
  std::vector<int> surface(counts.size(), -1);
  for (std::size_t k = 0; k < counts.size(); ++k) {
    std::size_t most = 0;
    for (const auto& [s, n] : counts[k]) {
      if (n > most) most = n, surface[k] = s;
    }
  }
  return surface;
}

// Up in the reference frame that `orientation` gives the camera: the angle between the
// reference frame's z and the world's.
double tiltErrorDeg(const Orientation& orientation, const synthetic::Camera& camera) {
  const Eigen::Vector3d true_up_in_sensor =
      camera.pose.linear().transpose() * Eigen::Vector3d::UnitZ();
  const Eigen::Vector3d up = orientation.sensorToReference().linear() * true_up_in_sensor;
  return std::acos(std::min(1.0, up.z())) / kDegree;
}

// The map with poses, the tracker with poses, and the map with the orientation alone (the
// poses' rotation: the odometry finds where the sensor is).
TEST(FramePipeline, TheMapAndTheTrackerKeepTheFloorsAndTablesIdOverAPan) {
  const std::vector<RenderedCloud> frames = renderPan(8, 320);
  // kAuto, the default, with an orientation alone: a pipeline told nothing of a fixed frame
  // takes the odometry.
  for (Identity identity :
       {Identity::kMap, Identity::kImproved, Identity::kOdometry, Identity::kAuto}) {
    PipelineOptions options;
    options.identity = identity;
    FramePipeline pipeline(options);
    const bool odometry = identity == Identity::kOdometry || identity == Identity::kAuto;
    EXPECT_EQ(pipeline.options().identity, odometry ? Identity::kOdometry : identity);
    std::set<int> floor_ids, table_ids, floor_surface_ids;
    for (std::size_t f = 0; f < frames.size(); ++f) {
      Eigen::Isometry3d rotation_only = frames[f].camera.pose;
      rotation_only.translation().setZero();
      const Frame frame = pipeline.process(
          PointsView::of(frames[f].cloud), f / 30.0,
          Orientation::fromTransform(odometry ? rotation_only : frames[f].camera.pose));
      EXPECT_EQ(frame.odometry.has_value(), odometry);
      if (frame.odometry) {
        EXPECT_EQ(frame.odometry->started, f == 0) << "frame " << f;
        EXPECT_EQ(frame.odometry->tracked, f > 0) << "frame " << f;
      }
      ASSERT_TRUE(frame.processed) << frame.skipped;
      floor_ids.insert(idOfSurface(frame, frames[f].truth, 0));
      table_ids.insert(idOfSurface(frame, frames[f].truth, 1));
      for (const StandingObject& o : frame.result.objects) {
        EXPECT_EQ(o.plane_id, frame.result.planes[o.plane_index].id)
            << "an object names its plane's persistent id";
      }
      // Planes that share a surface id lie on one true surface (the scene's truth: the surface
      // most of each plane's points lie on), and planes on the floor share one surface id, the
      // same in every frame.
      const std::vector<int> truth_of = trueSurfaceOfEachPlane(frame, frames[f].truth);
      ASSERT_FALSE(frame.result.planes.empty());
      for (std::size_t k = 0; k < frame.result.planes.size(); ++k) {
        const HorizontalPlane& p = frame.result.planes[k];
        for (std::size_t j = 0; j < frame.result.planes.size(); ++j) {
          const HorizontalPlane& q = frame.result.planes[j];
          if (q.surface_id != p.surface_id) continue;
          EXPECT_EQ(truth_of[j], truth_of[k])
              << "planes " << p.id << " (" << p.height << " m) and " << q.id << " (" << q.height
              << " m) share surface " << p.surface_id;
        }
        if (truth_of[k] == 0) floor_surface_ids.insert(p.surface_id);
      }
    }
    EXPECT_EQ(floor_surface_ids.size(), 1u) << toString(identity) << ": one surface id, the floor";
    EXPECT_EQ(floor_ids.size(), 1u) << toString(identity) << ": one id for the floor";
    EXPECT_FALSE(floor_ids.count(-1)) << toString(identity) << ": the floor is in every frame";
    EXPECT_EQ(table_ids.size(), 1u) << toString(identity);
    EXPECT_FALSE(table_ids.count(-1)) << toString(identity) << ": the table is in every frame";
    EXPECT_NE(*floor_ids.begin(), *table_ids.begin());
    EXPECT_EQ(pipeline.counters().frames, frames.size());
    EXPECT_EQ(pipeline.mapSize() > 0, keepsSurfaceMap(identity));
  }
}

// ~obstacles' points against the scene's truth: every point of a thing standing on the floor
// between 5 cm and 2 m up (the world's z, the floor at 0) and nothing else, over a pan.
TEST(FramePipeline, ObstaclesAreTheThingsBetweenTheBandsHeightsAboveTheFloor) {
  const std::vector<RenderedCloud> frames = renderPan(4, 320);
  FramePipeline pipeline;
  const PipelineOptions& o = pipeline.options();
  FrameOutputs outputs;
  outputs.obstacles = true;
  for (std::size_t f = 0; f < frames.size(); ++f) {
    const RenderedCloud& r = frames[f];
    // A reference frame whose origin is not on the floor: the floor's height must be found.
    const Eigen::Isometry3d reference = Eigen::Translation3d(0.3, -0.2, 1.3) * r.camera.pose;
    const Frame frame = pipeline.process(PointsView::of(r.cloud), f / 30.0,
                                         Orientation::fromTransform(reference), outputs);
    ASSERT_TRUE(frame.processed);
    ASSERT_GE(frame.floor_index, 0);
    EXPECT_EQ(frame.result.planes[frame.floor_index].id, idOfSurface(frame, r.truth, 0))
        << "the floor is the plane of the floor";
    std::vector<std::uint8_t> found(r.cloud.size(), 0);
    for (std::uint32_t i : frame.obstacles) found[i] = 1;
    std::size_t truth = 0, hits = 0;
    for (std::size_t i = 0; i < r.cloud.size(); ++i) {
      if (!r.cloud[i].getVector3fMap().allFinite()) continue;
      const double z = (r.camera.pose * r.cloud[i].getVector3fMap().cast<double>()).z();
      const bool obstacle =
          r.truth[i] != 0 && z > o.obstacle_min_height && z <= o.obstacle_max_height;
      truth += obstacle;
      hits += obstacle && found[i];
    }
    ASSERT_GT(truth, 1000u) << "frame " << f << " sees the table and the boxes";
    EXPECT_GE(static_cast<double>(hits), 0.99 * truth) << "recall, frame " << f;
    EXPECT_GE(static_cast<double>(hits), 0.99 * frame.obstacles.size()) << "precision, frame " << f;
  }
  // A band from 0.5 m (live, between frames): the stair block (0.17 and 0.34 m) leaves it, the
  // table's legs above 0.5 m and its top stay.
  PipelineOptions higher = pipeline.options();
  higher.obstacle_min_height = 0.5;
  pipeline.setOptions(higher);
  const RenderedCloud& r = frames[0];
  const Frame frame = pipeline.process(PointsView::of(r.cloud), 1.0,
                                       Orientation::fromTransform(r.camera.pose), outputs);
  ASSERT_FALSE(frame.obstacles.empty());
  for (std::uint32_t i : frame.obstacles) {
    const double z = (r.camera.pose * r.cloud[i].getVector3fMap().cast<double>()).z();
    EXPECT_GT(z, 0.5 - 1e-3);
  }
  // With the floor grid as well, the grid's pass collects them: the same points, in order.
  FrameOutputs both = outputs;
  both.floor_grid = true;
  const Frame with_grid = pipeline.processAlone(PointsView::of(r.cloud),
                                                Orientation::fromTransform(r.camera.pose), both);
  EXPECT_EQ(with_grid.obstacles, frame.obstacles);
  EXPECT_GT(with_grid.floor_grid.width, 0);
}

// ~floor_grid against the scene's truth over a pan, the reference origin off the floor: cells
// where a standing thing's points fall (between the obstacle heights, by the world's z) are
// occupied, cells where only the floor was seen are free, cells nothing fell in are unseen.
TEST(FramePipeline, TheFloorGridIsTheFloorSeenFreeAndTheThingsStandingOnIt) {
  const std::vector<RenderedCloud> frames = renderPan(4, 320);
  FramePipeline pipeline;
  const PipelineOptions& o = pipeline.options();
  FrameOutputs outputs;
  outputs.floor_grid = true;
  const Eigen::Vector3d offset(0.3, -0.2, 1.3);
  for (std::size_t f = 0; f < frames.size(); ++f) {
    const RenderedCloud& r = frames[f];
    const Eigen::Isometry3d reference = Eigen::Translation3d(offset) * r.camera.pose;
    const Frame frame = pipeline.process(PointsView::of(r.cloud), f / 30.0,
                                         Orientation::fromTransform(reference), outputs);
    ASSERT_TRUE(frame.processed);
    ASSERT_GE(frame.floor_index, 0);
    const FloorGrid& grid = frame.floor_grid;
    ASSERT_GT(grid.width, 0);
    ASSERT_EQ(grid.cells.size(), static_cast<std::size_t>(grid.width) * grid.height);
    EXPECT_DOUBLE_EQ(grid.resolution, o.grid_resolution);
    EXPECT_NEAR(grid.floor_height, offset.z(), 0.01) << "the floor 1.3 m above the origin";
    // The truth per cell: 1 a floor point fell in it, 2 a standing thing's point did.
    std::vector<std::uint8_t> truth(grid.cells.size(), 0);
    std::size_t outside = 0;
    for (std::size_t i = 0; i < r.cloud.size(); ++i) {
      const Eigen::Vector3f p = r.cloud[i].getVector3fMap();
      if (!p.allFinite()) continue;
      const Eigen::Vector3d world = r.camera.pose * p.cast<double>();
      const bool floor = r.truth[i] == 0;
      const bool standing =
          !floor && world.z() > o.obstacle_min_height && world.z() <= o.obstacle_max_height;
      if (!floor && !standing) continue;
      const Eigen::Vector3d in_reference = world + offset;
      const long x = static_cast<long>(
          std::floor((in_reference.x() - grid.origin.x()) / grid.resolution + 1e-9));
      const long y = static_cast<long>(
          std::floor((in_reference.y() - grid.origin.y()) / grid.resolution + 1e-9));
      if (x < 0 || y < 0 || x >= grid.width || y >= grid.height) {
        ++outside;
        continue;
      }
      std::uint8_t& t = truth[static_cast<std::size_t>(y) * grid.width + x];
      t = std::max<std::uint8_t>(t, standing ? 2 : 1);
    }
    EXPECT_EQ(outside, 0u) << "the grid spans every floor and standing point";
    std::size_t floor_cells = 0, free_floor = 0, thing_cells = 0, occupied_things = 0;
    std::size_t empty_cells = 0, unseen_empty = 0;
    for (std::size_t c = 0; c < truth.size(); ++c) {
      if (truth[c] == 1) ++floor_cells, free_floor += grid.cells[c] == FloorGrid::kFree;
      if (truth[c] == 2) ++thing_cells, occupied_things += grid.cells[c] == FloorGrid::kOccupied;
      if (truth[c] == 0) ++empty_cells, unseen_empty += grid.cells[c] == FloorGrid::kUnseen;
    }
    ASSERT_GT(floor_cells, 500u) << "frame " << f;
    ASSERT_GT(thing_cells, 100u) << "frame " << f;
    ASSERT_GT(empty_cells, 100u) << "frame " << f << ": the things' shadows";
    EXPECT_GE(static_cast<double>(free_floor), 0.98 * floor_cells) << "frame " << f;
    EXPECT_GE(static_cast<double>(occupied_things), 0.99 * thing_cells) << "frame " << f;
    EXPECT_GE(static_cast<double>(unseen_empty), 0.99 * empty_cells) << "frame " << f;
  }
  // Coarser cells, live: the same area in a quarter as many cells, or fewer.
  PipelineOptions coarser = pipeline.options();
  coarser.grid_resolution = 0.1;
  pipeline.setOptions(coarser);
  const Frame frame = pipeline.process(PointsView::of(frames[0].cloud), 1.0,
                                       Orientation::fromTransform(frames[0].camera.pose), outputs);
  EXPECT_DOUBLE_EQ(frame.floor_grid.resolution, 0.1);
  EXPECT_GT(frame.floor_grid.width, 0);
  // Without asking, no grid.
  const Frame without = pipeline.process(PointsView::of(frames[0].cloud), 1.1,
                                         Orientation::fromTransform(frames[0].camera.pose));
  EXPECT_EQ(without.floor_grid.width, 0);
  EXPECT_TRUE(without.floor_grid.cells.empty());
}

// With the map (poses in a fixed frame), the frames' grids add up: after a pan, the grid holds
// every cell any frame saw (against the truth of all frames: a standing thing's cells occupied,
// the floor's free, the rest unseen; nothing moves), more than the first frame alone;
// resetMap() forgets it.
TEST(FramePipeline, WithTheMapTheFloorGridAddsUpThePansFrames) {
  const std::vector<RenderedCloud> frames = renderPan(6, 320);
  PipelineOptions options;
  options.identity = Identity::kMap;
  FramePipeline pipeline(options);
  FrameOutputs outputs;
  outputs.floor_grid = true;
  const double cell = options.grid_resolution;
  // The truth per absolute cell (x, y): 1 the floor was seen there, 2 a standing thing.
  std::map<std::pair<long, long>, int> truth;
  FloorGrid first, last;
  for (std::size_t f = 0; f < frames.size(); ++f) {
    const RenderedCloud& r = frames[f];
    const Frame frame = pipeline.process(PointsView::of(r.cloud), f / 30.0,
                                         Orientation::fromTransform(r.camera.pose), outputs);
    ASSERT_TRUE(frame.processed);
    if (f == 0) first = frame.floor_grid;
    last = frame.floor_grid;
    for (std::size_t i = 0; i < r.cloud.size(); ++i) {
      const Eigen::Vector3f p = r.cloud[i].getVector3fMap();
      if (!p.allFinite()) continue;
      const Eigen::Vector3d world = r.camera.pose * p.cast<double>();
      const bool floor = r.truth[i] == 0;
      if (!floor &&
          (world.z() <= options.obstacle_min_height || world.z() > options.obstacle_max_height)) {
        continue;
      }
      int& t = truth[{static_cast<long>(std::floor(world.x() / cell + 1e-9)),
                      static_cast<long>(std::floor(world.y() / cell + 1e-9))}];
      t = std::max(t, floor ? 1 : 2);
    }
  }
  ASSERT_GT(first.width, 0);
  const auto seen = [](const FloorGrid& g) {
    return std::count_if(g.cells.begin(), g.cells.end(),
                         [](std::int8_t c) { return c != FloorGrid::kUnseen; });
  };
  EXPECT_GT(seen(last), seen(first)) << "the pan adds cells";
  std::size_t floor_cells = 0, free = 0, thing_cells = 0, occupied = 0, empty = 0, unseen = 0;
  const long x0 = std::lround(last.origin.x() / cell), y0 = std::lround(last.origin.y() / cell);
  for (int y = 0; y < last.height; ++y) {
    for (int x = 0; x < last.width; ++x) {
      const auto it = truth.find({x0 + x, y0 + y});
      const int t = it == truth.end() ? 0 : it->second;
      const std::int8_t c = last.cells[static_cast<std::size_t>(y) * last.width + x];
      if (t == 1) ++floor_cells, free += c == FloorGrid::kFree;
      if (t == 2) ++thing_cells, occupied += c == FloorGrid::kOccupied;
      if (t == 0) ++empty, unseen += c == FloorGrid::kUnseen;
    }
  }
  EXPECT_GE(static_cast<double>(free), 0.98 * floor_cells);
  EXPECT_GE(static_cast<double>(occupied), 0.99 * thing_cells);
  EXPECT_GE(static_cast<double>(unseen), 0.99 * empty);
  EXPECT_GT(floor_cells, 2000u);
  pipeline.resetMap();
  const Frame again = pipeline.process(PointsView::of(frames[0].cloud), 1.0,
                                       Orientation::fromTransform(frames[0].camera.pose), outputs);
  EXPECT_EQ(again.floor_grid.width, first.width) << "resetMap() forgets the grid's map";
  EXPECT_EQ(again.floor_grid.cells, first.cells);
}

TEST(FramePipeline, AnAccelerometerIsAveragedOverItsWindowOfSeconds) {
  const std::vector<RenderedCloud> frames = renderPan(2, 160);
  const synthetic::Camera& camera = frames[0].camera;
  const Eigen::Vector3d g = 9.81 * (camera.pose.linear().transpose() * Eigen::Vector3d::UnitZ());
  // The camera shaken sideways, ±3 m/s² on alternate frames (17° off gravity each).
  const Eigen::Vector3d shake = 3.0 * g.unitOrthogonal();
  PipelineOptions options;
  options.gravity_window_s = 0.33;  // ten frames at 30 Hz
  FramePipeline averaged(options);
  options.gravity_window_s = 0;  // each sample alone
  FramePipeline alone(options);
  FrameOutputs planes_only;
  planes_only.objects = false;
  double averaged_error = 0, alone_error = 0;
  for (int f = 0; f < 20; ++f) {
    const Eigen::Vector3d sample = g + (f % 2 ? shake : Eigen::Vector3d(-shake));
    const auto view = PointsView::of(frames[0].cloud);
    averaged_error = tiltErrorDeg(
        averaged.processWithGravity(view, f / 30.0, sample, planes_only).orientation, camera);
    alone_error = tiltErrorDeg(
        alone.processWithGravity(view, f / 30.0, sample, planes_only).orientation, camera);
  }
  EXPECT_NEAR(alone_error, std::atan(3.0 / 9.81) / kDegree, 0.1) << "one sample: its own tilt";
  EXPECT_LT(averaged_error, 0.1) << "ten samples, five shaken each way, cancel";
  // A sample older than the window no longer counts: a frame 1 s later sees its own only.
  const Frame later = averaged.processWithGravity(PointsView::of(frames[0].cloud), 20.0 / 30 + 1,
                                                  g + shake, planes_only);
  EXPECT_NEAR(tiltErrorDeg(later.orientation, camera), std::atan(3.0 / 9.81) / kDegree, 0.1);
  EXPECT_THROW(averaged.processWithGravity(PointsView::of(frames[0].cloud), 2, g * 1e-3),
               std::invalid_argument)
      << "milli-g is not m/s²";
}

// A wall seen head-on from 2 m: nothing level.
pcl::PointCloud<pcl::PointXYZ> wallAhead() {
  pcl::PointCloud<pcl::PointXYZ> wall;
  for (double x = -1; x <= 1; x += 0.01) {
    for (double y = -0.8; y <= 0.8; y += 0.01) wall.push_back(pcl::PointXYZ(x, y, 2.0));
  }
  return wall;
}

TEST(FramePipeline, UpFromTheSceneHoldsWhileNothingIsLevelThenSkips) {
  const std::vector<RenderedCloud> frames = renderPan(2, 320);
  PipelineOptions options;
  options.levelling = SceneLevelling::kEstimate;
  options.level_hold_s = 2.5 / 30;  // two frames at 30 Hz
  FramePipeline pipeline(options);
  const Orientation at_origin = Orientation::identity().withViewpoint(Eigen::Vector3d::Zero());
  const Frame level = pipeline.process(PointsView::of(frames[0].cloud), 0, at_origin);
  ASSERT_TRUE(level.processed) << level.skipped;
  ASSERT_TRUE(level.levelling);
  EXPECT_LT(tiltErrorDeg(level.orientation, frames[0].camera), 1.0);
  const auto wall = wallAhead();
  for (int f = 1; f <= 3; ++f) {
    const Frame facing_wall = pipeline.process(PointsView::of(wall), f / 30.0, at_origin);
    if (f <= 2) {
      EXPECT_TRUE(facing_wall.processed) << "frame " << f << " holds the last up";
      EXPECT_TRUE(facing_wall.level_held);
      EXPECT_LT(tiltErrorDeg(facing_wall.orientation, frames[0].camera), 1.0);
    } else {
      EXPECT_FALSE(facing_wall.processed) << "past the hold, the frame is skipped";
      EXPECT_FALSE(facing_wall.skipped.empty());
    }
  }
  EXPECT_EQ(pipeline.counters().levelled, 1u);
  EXPECT_EQ(pipeline.counters().level_held, 2u);
  EXPECT_EQ(pipeline.counters().skipped, 1u);
  // Without an earlier up there is nothing to hold.
  FramePipeline fresh(options);
  EXPECT_FALSE(fresh.process(PointsView::of(wall), 0, at_origin).processed);
}

TEST(FramePipeline, ARefinementCorrectsAGivenOrientationTiltedBy2Degrees) {
  const std::vector<RenderedCloud> frames = renderPan(3, 320);
  PipelineOptions options;
  options.levelling = SceneLevelling::kRefine;
  FramePipeline pipeline(options);
  const Eigen::Isometry3d tilt(Eigen::AngleAxisd(2 * kDegree, Eigen::Vector3d::UnitX()));
  for (std::size_t f = 0; f < frames.size(); ++f) {
    const Orientation given = Orientation::fromTransform(tilt * frames[f].camera.pose);
    ASSERT_NEAR(tiltErrorDeg(given, frames[f].camera), 2.0, 1e-6);
    const Frame frame = pipeline.process(PointsView::of(frames[f].cloud), f / 30.0, given);
    ASSERT_TRUE(frame.levelling);
    EXPECT_TRUE(frame.levelling->applied) << frame.levelling->note;
    EXPECT_LT(tiltErrorDeg(frame.orientation, frames[f].camera), 0.3) << "frame " << f;
  }
}

TEST(FramePipeline, TimeGoingBackRestartsTheTracksAndNeverReusesAnId) {
  const std::vector<RenderedCloud> frames = renderPan(2, 160);
  FramePipeline pipeline;
  std::set<int> first_ids;
  for (int f = 0; f < 2; ++f) {
    const Frame frame = pipeline.process(PointsView::of(frames[f].cloud), 10.0 + f,
                                         Orientation::fromTransform(frames[f].camera.pose));
    EXPECT_FALSE(frame.time_jump);
    for (const auto& p : frame.result.planes) first_ids.insert(p.id);
  }
  ASSERT_FALSE(first_ids.empty());
  const Frame replay = pipeline.process(PointsView::of(frames[0].cloud), 10.0,
                                        Orientation::fromTransform(frames[0].camera.pose));
  EXPECT_TRUE(replay.time_jump);
  EXPECT_EQ(pipeline.counters().time_jumps, 1u);
  ASSERT_FALSE(replay.result.planes.empty());
  for (const auto& p : replay.result.planes) {
    EXPECT_FALSE(first_ids.count(p.id)) << "id " << p.id << " given twice";
  }
}

// The scene odometry's world ends with the time it was built in and with the map: a frame
// after a time jump or resetMap() starts a new one (Frame::Odometry::started, its pose the
// identity), which the front-ends do not count as a frame the odometry lost.
TEST(FramePipeline, TheOdometryStartsANewWorldAfterATimeJumpAndAReset) {
  const std::vector<RenderedCloud> frames = renderPan(8, 320);
  PipelineOptions options;
  options.identity = Identity::kOdometry;
  FramePipeline pipeline(options);
  const auto run = [&](int f, double stamp) {
    Eigen::Isometry3d rotation_only = frames[f].camera.pose;
    rotation_only.translation().setZero();
    const Frame frame = pipeline.process(PointsView::of(frames[f].cloud), stamp,
                                         Orientation::fromTransform(rotation_only));
    EXPECT_TRUE(frame.odometry) << "frame " << f;
    return frame.odometry.value_or(Frame::Odometry());
  };
  std::vector<Frame::Odometry> first_pass;
  for (int f = 0; f < 3; ++f) {
    first_pass.push_back(run(f, 10.0 + f / 30.0));
    EXPECT_EQ(first_pass.back().started, f == 0) << "frame " << f;
    EXPECT_EQ(first_pass.back().tracked, f > 0) << "frame " << f;
  }
  // The bag looped: the same frames again, the same steps from a new world.
  for (int f = 0; f < 3; ++f) {
    const Frame::Odometry again = run(f, 10.0 + f / 30.0);
    EXPECT_EQ(again.started, f == 0) << "frame " << f << " after the time jump";
    EXPECT_EQ(again.tracked, first_pass[f].tracked) << "frame " << f;
    EXPECT_TRUE(again.world_from_frame.isApprox(first_pass[f].world_from_frame, 1e-9))
        << "frame " << f;
  }
  pipeline.resetMap();
  EXPECT_TRUE(run(3, 10.0 + 3 / 30.0).started) << "resetMap() starts a new world";
  EXPECT_FALSE(run(4, 10.0 + 4 / 30.0).started);
}

// A depth image 160 pixels wide (a robot's downscaled depth: about two samples to a 3 cm voxel's
// side at 2 m) panning over the scene: the odometry aligns every frame with the last, and the
// floor and the table keep their ids. Its overlap once counted the voxel centroids within a
// voxel of each other, which samples this sparse seldom are: two frames in three were said
// not to be aligned (and other starting turns were tried on them for nothing).
TEST(FramePipeline, TheOdometryFollowsAPanSeenAt160Pixels) {
  const std::vector<RenderedCloud> frames = renderPan(12, 160);
  PipelineOptions options;
  options.identity = Identity::kOdometry;
  FramePipeline pipeline(options);
  std::set<int> floor_ids, table_ids;
  for (std::size_t f = 0; f < frames.size(); ++f) {
    Eigen::Isometry3d rotation_only = frames[f].camera.pose;
    rotation_only.translation().setZero();
    const Frame frame = pipeline.process(PointsView::of(frames[f].cloud), f / 30.0,
                                         Orientation::fromTransform(rotation_only));
    ASSERT_TRUE(frame.odometry) << "frame " << f;
    EXPECT_EQ(frame.odometry->tracked, f > 0)
        << "frame " << f << ", overlap " << frame.odometry->overlap;
    floor_ids.insert(idOfSurface(frame, frames[f].truth, 0));
    table_ids.insert(idOfSurface(frame, frames[f].truth, 1));
  }
  EXPECT_EQ(floor_ids.size(), 1u);
  EXPECT_FALSE(floor_ids.count(-1)) << "the floor is in every frame";
  EXPECT_EQ(table_ids.size(), 1u);
  EXPECT_FALSE(table_ids.count(-1)) << "the table is in every frame";
}

// The map needs the sensor's pose in a fixed frame. Poses that turn the sensor by more than 10°
// but never move it (an orientation written as a pose, a tf with a fixed translation) are said
// once, in the frame's warnings (every front-end shows them); poses that move it are not; the
// tracker does not need them.
TEST(FramePipeline, TheMapWarnsOnceWhenItsPosesTurnTheSensorButNeverMoveIt) {
  const std::vector<RenderedCloud> frames = renderPan(2, 160);
  auto warningsOver = [&](Identity identity, bool moving) {
    PipelineOptions options;
    options.identity = identity;
    FramePipeline pipeline(options);
    int warned = 0;
    for (int f = 0; f < 6; ++f) {
      // Turned 4° a frame about the world's vertical: 20° by the last.
      Eigen::Isometry3d pose =
          Eigen::AngleAxisd(4.0 * f * kDegree, Eigen::Vector3d::UnitZ()) * frames[0].camera.pose;
      pose.translation() = moving ? Eigen::Vector3d(0.05 * f, 0.0, 1.5) : Eigen::Vector3d::Zero();
      const Frame frame = pipeline.process(PointsView::of(frames[0].cloud), f / 30.0,
                                           Orientation::fromTransform(pose));
      EXPECT_TRUE(frame.processed) << frame.skipped;
      for (const std::string& w : frame.result.warnings) {
        warned += w.find("its position never changed") != std::string::npos;
      }
    }
    return warned;
  };
  EXPECT_EQ(warningsOver(Identity::kMap, false), 1);
  EXPECT_EQ(warningsOver(Identity::kMap, true), 0);
  EXPECT_EQ(warningsOver(Identity::kImproved, false), 0);
}

TEST(FramePipeline, PlacementsAreAnsweredOnTheFrameAskedAfterLaterFrames) {
  const std::vector<RenderedCloud> frames = renderPan(2, 640);
  FramePipeline pipeline;
  FrameOutputs keep;
  keep.keep_points = true;
  const Frame first = pipeline.process(PointsView::of(frames[0].cloud), 0,
                                       Orientation::fromTransform(frames[0].camera.pose), keep);
  PlacementQuery query;
  query.footprint.width = 0.2;
  query.footprint.depth = 0.2;
  const std::vector<Placement> at_once = pipeline.findPlacements(first, query);
  ASSERT_FALSE(at_once.empty()) << "a 20 cm square fits on the floor";
  pipeline.process(PointsView::of(frames[1].cloud), 1.0 / 30,
                   Orientation::fromTransform(frames[1].camera.pose), keep);
  const std::vector<Placement> later = pipeline.findPlacements(first, query);
  ASSERT_EQ(later.size(), at_once.size());
  for (std::size_t k = 0; k < later.size(); ++k) {
    EXPECT_EQ(later[k].centre, at_once[k].centre);
  }
  const Frame without = pipeline.process(PointsView::of(frames[1].cloud), 2.0 / 30,
                                         Orientation::fromTransform(frames[1].camera.pose));
  EXPECT_THROW(pipeline.findPlacements(without, query), std::invalid_argument);
}

// map_forget_frames reaches the map: with a memory of 2 frames, the floor and the table keep
// their ids across 1 frame of another place (the same view 50 m away: nothing of them is
// seen), and take new ones after 2; without a memory (0) they are kept after 40.
TEST(FramePipeline, TheMapForgetsASurfaceOutOfViewLongerThanItsMemory) {
  const std::vector<RenderedCloud> frames = renderPan(2, 160);
  const RenderedCloud& view = frames[0];
  Eigen::Isometry3d elsewhere = view.camera.pose;
  elsewhere.translation().x() += 50;
  for (int memory : {2, 0}) {
    PipelineOptions options;
    options.identity = Identity::kMap;
    options.map_forget_frames = memory;
    FramePipeline pipeline(options);
    double stamp = 0;
    const auto ids = [&]() {
      const Frame frame = pipeline.process(PointsView::of(view.cloud), stamp += 1,
                                           Orientation::fromTransform(view.camera.pose));
      EXPECT_TRUE(frame.processed) << frame.skipped;
      return std::make_pair(idOfSurface(frame, view.truth, 0), idOfSurface(frame, view.truth, 1));
    };
    const auto away = [&](int frames_away) {
      for (int f = 0; f < frames_away; ++f) {
        pipeline.process(PointsView::of(view.cloud), stamp += 1,
                         Orientation::fromTransform(elsewhere));
      }
    };
    const auto first = ids();
    ASSERT_GE(first.first, 0);
    ASSERT_GE(first.second, 0);
    away(1);
    EXPECT_EQ(ids(), first) << "memory " << memory << ": unseen in 1 frame";
    away(memory > 0 ? 2 : 40);
    const auto later = ids();
    if (memory > 0) {
      EXPECT_NE(later.first, first.first) << "floor unseen in 2 frames: a 2-frame memory passed";
      EXPECT_NE(later.second, first.second) << "table unseen in 2 frames";
    } else {
      EXPECT_EQ(later, first) << "no memory limit: kept after 40 frames away";
    }
  }
}

TEST(FramePipeline, NewOptionsRestartTheMapOnlyWhenItsCellsChangeAndBadOnesChangeNothing) {
  const std::vector<RenderedCloud> frames = renderPan(2, 160);
  PipelineOptions options;
  options.identity = Identity::kMap;
  FramePipeline pipeline(options);
  pipeline.process(PointsView::of(frames[0].cloud), 0,
                   Orientation::fromTransform(frames[0].camera.pose));
  const std::size_t entries = pipeline.mapSize();
  ASSERT_GT(entries, 0u);
  options.objects = false;
  EXPECT_TRUE(pipeline.setOptions(options).empty());
  EXPECT_EQ(pipeline.mapSize(), entries);
  PipelineOptions bad = options;
  bad.extraction.r_xy = -1;
  EXPECT_THROW(pipeline.setOptions(bad), std::invalid_argument);
  EXPECT_EQ(pipeline.options().extraction.r_xy, options.extraction.r_xy);
  options.extraction.r_xy = 0.04;
  const auto notes = pipeline.setOptions(options);
  ASSERT_EQ(notes.size(), 1u);
  EXPECT_NE(notes[0].find("surface map restarted"), std::string::npos) << notes[0];
  EXPECT_EQ(pipeline.mapSize(), 0u);
  pipeline.process(PointsView::of(frames[0].cloud), 0.1,
                   Orientation::fromTransform(frames[0].camera.pose));
  ASSERT_GT(pipeline.mapSize(), 0u);
  options.map_forget_frames = 5;  // another memory: the map starts afresh, and says why
  const auto memory_notes = pipeline.setOptions(options);
  ASSERT_EQ(memory_notes.size(), 1u);
  EXPECT_NE(memory_notes[0].find("map_forget_frames"), std::string::npos) << memory_notes[0];
  EXPECT_EQ(pipeline.mapSize(), 0u);
  EXPECT_THROW(
      pipeline.processWithGravity(PointsView::of(frames[0].cloud), 1, Eigen::Vector3d(0, -9.81, 0)),
      std::invalid_argument)
      << "a map needs poses";
  PipelineOptions smoothing = PipelineOptions();
  smoothing.level_smoothing = 0;
  EXPECT_THROW(FramePipeline{smoothing}, std::invalid_argument);
  EXPECT_EQ(identityFromString("map"), Identity::kMap);
  EXPECT_THROW(identityFromString("nearest"), std::invalid_argument);
  // auto: the map where the input is poses in a fixed frame, the odometry otherwise; every
  // front-end resolves it with this rule.
  EXPECT_EQ(identityFromString("auto"), Identity::kAuto);
  EXPECT_STREQ(toString(Identity::kAuto), "auto");
  EXPECT_EQ(PipelineOptions().identity, Identity::kAuto);
  EXPECT_EQ(defaultIdentity(PoseInput::kFixedFramePoses), Identity::kMap);
  EXPECT_EQ(defaultIdentity(PoseInput::kOrientation), Identity::kOdometry);
  EXPECT_EQ(resolveIdentity(Identity::kAuto, PoseInput::kFixedFramePoses), Identity::kMap);
  EXPECT_EQ(resolveIdentity(Identity::kImproved, PoseInput::kFixedFramePoses), Identity::kImproved);
  PipelineOptions automatic = pipeline.options();
  automatic.identity = Identity::kAuto;
  pipeline.setOptions(automatic);
  EXPECT_EQ(pipeline.options().identity, Identity::kOdometry);
  EXPECT_EQ(sceneLevellingFromString("refine"), SceneLevelling::kRefine);
}

}  // namespace
}  // namespace hope
