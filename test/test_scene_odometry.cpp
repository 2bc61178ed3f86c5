// The scene odometry (scene_odometry.h) against motions known by construction (the demo room
// rendered from two poses) and against a real sequence's motion-capture poses (kitchen_dev),
// with nothing but gravity given.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <functional>
#include <map>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>

#include "helpers.h"
#include "hope/depth_image.h"
#include "hope/frame_pipeline.h"
#include "hope/orientation.h"
#include "hope/scene_odometry.h"
#include "hope/synthetic/lidar.h"
#include "hope/synthetic/scene.h"

namespace hope {
namespace {

constexpr double kDegree = M_PI / 180.0;

// The orientation an accelerometer would give a camera posed at `pose` (optical frame in a
// z-up world): gravity alone, so the reference frame's heading follows the camera.
Eigen::Isometry3d gravityOnly(const Eigen::Matrix3d& camera_rotation) {
  const Eigen::Vector3d up = camera_rotation.transpose() * Eigen::Vector3d::UnitZ();
  return Orientation::fromGravity(up.x(), up.y(), up.z()).sensorToReference();
}

// The motion taking the second frame's gravity-aligned points into the first's, from the true
// poses: p_w = R_i G_iᵀ f_i + t_i for each frame's gravity-aligned point f_i.
Eigen::Isometry3d trueStep(const Eigen::Isometry3d& first, const Eigen::Isometry3d& second) {
  const Eigen::Matrix3d g1 = gravityOnly(first.linear()).linear();
  const Eigen::Matrix3d g2 = gravityOnly(second.linear()).linear();
  Eigen::Isometry3d step = Eigen::Isometry3d::Identity();
  step.linear() = g1 * first.linear().transpose() * second.linear() * g2.transpose();
  step.translation() =
      g1 * first.linear().transpose() * (second.translation() - first.translation());
  return step;
}

double angleDeg(const Eigen::Matrix3d& r) { return Eigen::AngleAxisd(r).angle() / kDegree; }

TEST(SceneOdometry, TheDemoRoomSeenFromTwoPosesGivesTheMotionBetweenThem) {
  const synthetic::Scene room = synthetic::demoRoom();
  const synthetic::Camera first = synthetic::demoCamera();
  // A hand-held camera a third of a second later: 8 cm sideways, 3 cm down, turned 6°.
  synthetic::Camera second = synthetic::demoCameraTurned(6 * kDegree);
  second.pose.translation() += Eigen::Vector3d(0.06, 0.05, -0.03);
  SceneOdometry odometry;
  std::uint32_t seed = 1;
  std::vector<OdometryStep> steps;
  for (const synthetic::Camera& camera : {first, second}) {
    synthetic::SensorNoise noise = synthetic::SensorNoise::kinectLike();
    noise.seed = seed++;
    const auto cloud = depthToCloud(room.render(camera, noise).depth, camera.intrinsics, 1.0);
    steps.push_back(odometry.update(PointsView::of(cloud), gravityOnly(camera.pose.linear())));
  }
  EXPECT_FALSE(steps[0].tracked) << "the first frame starts the world";
  EXPECT_TRUE(steps[0].started);
  EXPECT_FALSE(steps[1].started);
  EXPECT_TRUE(steps[0].world_from_frame.isApprox(Eigen::Isometry3d::Identity()));
  ASSERT_TRUE(steps[1].tracked) << "overlap " << steps[1].overlap;
  const Eigen::Isometry3d truth = trueStep(first.pose, second.pose);
  const Eigen::Isometry3d error = truth.inverse() * steps[1].world_from_frame;
  EXPECT_LT(error.translation().norm(), 0.01)
      << "found " << steps[1].world_from_frame.translation().transpose() << ", true "
      << truth.translation().transpose();
  EXPECT_LT(angleDeg(error.linear()), 0.3);
  // Only a turn about the vertical: gravity fixed the rest.
  EXPECT_NEAR(steps[1].world_from_frame.linear()(2, 2), 1.0, 1e-12);
}

// A spinning LiDAR (128 beams) on a robot in the synthetic room, driven 30 cm forward and 15
// cm sideways while turning 5°, through the frame pipeline with lidar.launch's r_xy 0.3 m and
// r_z 0.1 m (the odometry's finest voxel 1.5 r_z = 15 cm): its scans, unorganized and sparse
// with range, give the motion (the sensor is level, so its frame is the gravity-aligned one).
TEST(SceneOdometry, ALidarOnARobotGivesItsMotionInTheRoom) {
  const synthetic::Scene room = synthetic::lidarRoom();
  const Eigen::Isometry3d first = synthetic::lidarRoomPose();
  Eigen::Isometry3d second = first;
  second.linear() = Eigen::AngleAxisd(5 * kDegree, Eigen::Vector3d::UnitZ()) * first.linear();
  second.translation() += first.linear() * Eigen::Vector3d(0.30, 0.15, 0.0);
  PipelineOptions options;
  options.extraction.r_xy = 0.3;
  options.extraction.r_z = 0.1;
  options.identity = Identity::kOdometry;
  options.objects = false;
  FramePipeline pipeline(options);
  std::vector<Frame> frames;
  std::uint32_t seed = 1;
  for (const Eigen::Isometry3d& pose : {first, second}) {
    const auto scan =
        synthetic::scanWithLidar(room, synthetic::LidarModel::ouster128(), pose, seed);
    pcl::PointCloud<pcl::PointXYZ> cloud;  // as a driver that drops the NaN returns sends it
    for (const auto& p : scan.toCloud()) {
      if (std::isfinite(p.x)) cloud.push_back(p);
    }
    frames.push_back(
        pipeline.process(PointsView::of(cloud), 0.1 * seed++,
                         Orientation::identity().withViewpoint(Eigen::Vector3d::Zero())));
  }
  ASSERT_TRUE(frames[1].odometry.has_value());
  ASSERT_TRUE(frames[1].odometry->tracked) << "overlap " << frames[1].odometry->overlap;
  // The second scan's points into the first's frame: the sensor's motion in the first's frame.
  const Eigen::Isometry3d truth = first.inverse() * second;
  const Eigen::Isometry3d found = frames[1].odometry->world_from_frame;
  const Eigen::Isometry3d error = truth.inverse() * found;
  std::printf("LiDAR step error: %.1f mm, %.3f deg\n", 1000 * error.translation().norm(),
              angleDeg(error.linear()));
  EXPECT_LT(error.translation().norm(), 0.02) << "found " << found.translation().transpose()
                                              << ", true " << truth.translation().transpose();
  EXPECT_LT(angleDeg(error.linear()), 0.2);
  // Every level surface of the room (floor, table, two boards, ceiling) keeps its id: the map
  // saw each from both places.
  ASSERT_EQ(frames[0].result.planes.size(), 5u);
  for (const HorizontalPlane& p : frames[0].result.planes) {
    const auto same = std::find_if(frames[1].result.planes.begin(), frames[1].result.planes.end(),
                                   [&](const HorizontalPlane& q) { return q.id == p.id; });
    ASSERT_NE(same, frames[1].result.planes.end()) << "the plane at " << p.height << " m";
    EXPECT_NEAR(same->height, p.height, 0.03);
  }
}

TEST(SceneOdometry, AFloorAloneLeavesTheShiftAlongItWhereItWasAndFindsTheHeight) {
  // A level floor tells the height and nothing of a shift along it or a turn: those stay as
  // they started (no motion), never a number the scene does not hold.
  synthetic::Scene floor;
  floor.add<synthetic::Box>(Eigen::Vector3d(-5, -5, -0.1), Eigen::Vector3d(5, 5, 0.0), 0);
  synthetic::Camera first = synthetic::Camera::lookingAt({0, 0, 1.5}, {1.5, 0.3, 0});
  synthetic::Camera second = first;
  second.pose.translation() += Eigen::Vector3d(0.05, 0.02, 0.04);
  SceneOdometry odometry;
  OdometryStep step;
  for (const synthetic::Camera& camera : {first, second}) {
    const auto cloud = depthToCloud(floor.render(camera).depth, camera.intrinsics, 1.0);
    step = odometry.update(PointsView::of(cloud), gravityOnly(camera.pose.linear()));
  }
  EXPECT_TRUE(step.world_from_frame.matrix().allFinite());
  EXPECT_NEAR(step.world_from_frame.translation().z(), 0.04, 0.005) << "the height it holds";
  EXPECT_LT(step.world_from_frame.translation().head<2>().norm(), 0.01);
  EXPECT_LT(angleDeg(step.world_from_frame.linear()), 0.1);
}

TEST(SceneOdometry, NoPointsAndBadParametersAreSaidNotGuessed) {
  SceneOdometry odometry;
  pcl::PointCloud<pcl::PointXYZ> empty, nan_only;
  nan_only.push_back(pcl::PointXYZ(NAN, 0.f, 1.f));
  nan_only.push_back(pcl::PointXYZ(INFINITY, 0.f, 1.f));
  for (int f = 0; f < 3; ++f) {
    const OdometryStep step =
        odometry.update(PointsView::of(f % 2 ? nan_only : empty), Eigen::Isometry3d::Identity());
    EXPECT_FALSE(step.tracked);
    EXPECT_TRUE(step.world_from_frame.matrix().allFinite());
    EXPECT_EQ(step.overlap, 0.0);
  }
  // Each bad parameter is refused by name.
  using Spoil = std::function<void(OdometryParams&)>;
  const std::vector<std::pair<std::string, Spoil>> bad = {
      {"cell", [](OdometryParams& p) { p.cell = -0.03; }},
      {"cell", [](OdometryParams& p) { p.cell = NAN; }},
      {"levels", [](OdometryParams& p) { p.levels = 0; }},
      {"iterations", [](OdometryParams& p) { p.iterations = 0; }},
      {"max_samples", [](OdometryParams& p) { p.max_samples = 1; }},
      {"level_tilt_deg", [](OdometryParams& p) { p.level_tilt_deg = 60; }},
      {"min_overlap", [](OdometryParams& p) { p.min_overlap = 1.5; }},
      {"noise", [](OdometryParams& p) {
         p.noise = RangeNoise{-1, 0, 0, 0};
       }}};
  for (const auto& [name, spoil] : bad) {
    OdometryParams params;
    spoil(params);
    try {
      SceneOdometry accepted(params);
      ADD_FAILURE() << name << " accepted";
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find(name), std::string::npos) << e.what();
    }
  }
}

// "timestamp a b c ..." lines (TUM text files), by stamp rounded to the millisecond.
std::map<long, std::vector<double>> readStamped(const std::string& path) {
  std::map<long, std::vector<double>> rows;
  std::ifstream in(path);
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream fields(line);
    double stamp, value;
    fields >> stamp;
    std::vector<double> values;
    while (fields >> value) values.push_back(value);
    rows[std::lround(stamp * 1000)] = values;
  }
  return rows;
}

TEST(SceneOdometry, KitchenDevStepsFollowTheMotionCapturePoses) {
  const std::string dir = test::sharedData("kitchen_dev");
  const auto poses = readStamped(dir + "/groundtruth.txt");
  const auto gravity = readStamped(dir + "/accelerometer.txt");
  std::ifstream depth_list(dir + "/depth.txt");
  if (poses.empty() || gravity.empty() || !depth_list) {
    GTEST_SKIP() << "kitchen_dev not found under " << dir;
  }
  PinholeIntrinsics k;
  {
    std::ifstream in(dir + "/intrinsics.txt");
    in >> k.fx >> k.fy >> k.cx >> k.cy;
  }
  SceneOdometry odometry;
  std::vector<double> shift_errors, turn_errors;
  Eigen::Isometry3d last_world_from_frame, last_truth;
  std::string line;
  bool first = true;
  while (std::getline(depth_list, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream fields(line);
    double stamp;
    std::string file;
    fields >> stamp >> file;
    const long key = std::lround(stamp * 1000);
    ASSERT_TRUE(poses.count(key) && gravity.count(key)) << "no pose or gravity at " << stamp;
    const std::vector<double>& p = poses.at(key);
    const std::vector<double>& g = gravity.at(key);
    Eigen::Isometry3d truth = Eigen::Isometry3d::Identity();
    truth.linear() = Eigen::Quaterniond(p[6], p[3], p[4], p[5]).normalized().toRotationMatrix();
    truth.translation() = Eigen::Vector3d(p[0], p[1], p[2]);
    cv::Mat raw = cv::imread(dir + "/" + file, cv::IMREAD_UNCHANGED);
    ASSERT_FALSE(raw.empty()) << file;
    const auto cloud = depthToCloud(raw, k, 5000.0);  // 5000 per metre (the folder's README)
    const Eigen::Isometry3d sensor_to_frame =
        Orientation::fromGravity(g[0], g[1], g[2]).sensorToReference();
    const OdometryStep step = odometry.update(PointsView::of(cloud), sensor_to_frame);
    // The camera's pose in the odometry's world, and its motion since the last frame, against
    // the true one (the first frames' worlds differ by a fixed transform, which cancels).
    const Eigen::Isometry3d world_from_sensor = step.world_from_frame * sensor_to_frame;
    if (!first) {
      const Eigen::Isometry3d found = last_world_from_frame.inverse() * world_from_sensor;
      const Eigen::Isometry3d moved = last_truth.inverse() * truth;
      const Eigen::Isometry3d error = moved.inverse() * found;
      shift_errors.push_back(error.translation().norm());
      turn_errors.push_back(angleDeg(error.linear()));
    }
    first = false;
    last_world_from_frame = world_from_sensor;
    last_truth = truth;
  }
  ASSERT_EQ(shift_errors.size(), 84u) << "kitchen_dev's 85 frames";
  const auto median = [](std::vector<double> v) {
    std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
    return v[v.size() / 2];
  };
  const auto percentile = [](std::vector<double> v, double share) {
    std::sort(v.begin(), v.end());
    return v[static_cast<std::size_t>(share * static_cast<double>(v.size() - 1))];
  };
  // The figures docs/quality.md quotes.
  std::printf(
      "kitchen_dev steps against the poses: median %.4f m %.2f deg, 90th percentile "
      "%.4f m %.2f deg, most %.4f m %.2f deg\n",
      median(shift_errors), median(turn_errors), percentile(shift_errors, 0.9),
      percentile(turn_errors, 0.9), percentile(shift_errors, 1.0), percentile(turn_errors, 1.0));
  // The camera moves a median 6.8 cm and 4° between these frames (a third of a second).
  EXPECT_LT(median(shift_errors), 0.015) << "metres";
  EXPECT_LT(median(turn_errors), 0.5) << "degrees";
  EXPECT_LT(*std::max_element(shift_errors.begin(), shift_errors.end()), 0.10);
  EXPECT_LT(*std::max_element(turn_errors.begin(), turn_errors.end()), 2.0);
}

}  // namespace
}  // namespace hope
