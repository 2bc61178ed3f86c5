// Params::threads splits the passes over points and voxels across threads; the output must not
// depend on it. Each scene is extracted with 1, 2 and 3 threads (3: shares that do not divide
// evenly) and every plane field, every hull vertex and every point label must be identical.
// Also the in-place read of a z-up cloud against the aligned copy (NoCopy).
#include <cmath>
#include <string>

#include <gtest/gtest.h>

#include "helpers.h"
#include "hope/depth_image.h"
#include "hope/extractor.h"
#include "hope/synthetic/lidar.h"
#include "hope/synthetic/paper_scenes.h"
#include "hope/synthetic/scene.h"
#include "scene_inputs.h"

namespace hope {
namespace test {
namespace {

void expectSamePlane(const HorizontalPlane& a, const HorizontalPlane& b, const std::string& what) {
  EXPECT_EQ(a.id, b.id) << what;
  EXPECT_EQ(a.height, b.height) << what;
  EXPECT_EQ(a.num_points, b.num_points) << what;
  EXPECT_EQ(a.num_voxels, b.num_voxels) << what;
  EXPECT_EQ(a.num_parts, b.num_parts) << what;
  EXPECT_EQ(a.area, b.area) << what;
  EXPECT_EQ(a.tilt, b.tilt) << what;
  EXPECT_EQ(a.mean_normal_tilt, b.mean_normal_tilt) << what;
  EXPECT_EQ(a.group_angle, b.group_angle) << what;
  EXPECT_EQ(a.facing, b.facing) << what;
  for (int k = 0; k < 4; ++k) EXPECT_EQ(a.bbox[k], b.bbox[k]) << what << " bbox " << k;
  EXPECT_EQ(a.centroid, b.centroid) << what;
  EXPECT_EQ(a.normal, b.normal) << what;
  ASSERT_EQ(a.hull.size(), b.hull.size()) << what;
  for (std::size_t k = 0; k < a.hull.size(); ++k) EXPECT_EQ(a.hull[k], b.hull[k]) << what;
  ASSERT_EQ(a.outline.size(), b.outline.size()) << what;
  for (std::size_t r = 0; r < a.outline.size(); ++r) EXPECT_EQ(a.outline[r], b.outline[r]) << what;
}

// Extracts `cloud` with 1, 2 and 3 threads and requires identical results; returns the
// one-thread result for the caller's ground-truth checks.
Result expectSameForAnyThreads(const pcl::PointCloud<pcl::PointXYZ>& cloud,
                               const Orientation& orientation, Params params,
                               const std::string& scene) {
  params.threads = 1;
  Extractor single(params);
  const Result reference = single.extract(cloud, orientation);
  for (int threads : {2, 3}) {
    params.threads = threads;
    Extractor parallel(params);
    // Twice: the second call runs on buffers left by the first, as in a running node.
    for (int call = 0; call < 2; ++call) {
      const Result r = parallel.extract(cloud, orientation);
      const std::string what =
          scene + ", " + std::to_string(threads) + " threads, call " + std::to_string(call + 1);
      EXPECT_EQ(r.planes.size(), reference.planes.size()) << what;
      if (r.planes.size() != reference.planes.size()) continue;
      for (std::size_t k = 0; k < r.planes.size(); ++k) {
        expectSamePlane(r.planes[k], reference.planes[k], what + ", plane " + std::to_string(k));
      }
      EXPECT_EQ(r.point_labels, reference.point_labels) << what;
      EXPECT_EQ(r.finite_points, reference.finite_points) << what;
      EXPECT_EQ(r.voxels, reference.voxels) << what;
    }
  }
  return reference;
}

}  // namespace

TEST(Threads, DemoRoomCameraViewIsTheSameForAnyNumberOfThreads) {
  const auto scene = synthetic::demoRoom();
  const auto camera = synthetic::demoCamera();
  const auto cloud = depthToCloud(scene.render(camera).depth, camera.intrinsics, 1.0);
  const Result r = expectSameForAnyThreads(cloud, poseOf(camera.pose), Params(), "demo room");
  // The scene's true horizontal surfaces, each found.
  for (double height : {0.0, 0.75, 0.45, 0.17, 0.34, 0.80}) {
    EXPECT_GE(planeNear(r, height, 0.01), 0) << "no plane at " << height << ": " << describe(r);
  }
}

TEST(Threads, MillionPointUnorganizedScanIsTheSameForAnyNumberOfThreads) {
  // The demo room scanned from above every 6 mm over 6 x 6 m: 1.0 M points, z up.
  const auto scan = synthetic::demoRoom().scanFromAbove(-1.0, -3.0, 5.0, 3.0, 0.006, 0.002);
  ASSERT_GE(scan.cloud.size(), 1000000u);
  const Result r =
      expectSameForAnyThreads(scan.cloud, Orientation::identity(), Params(), "1 M-point scan");
  EXPECT_GE(planeNear(r, 0.0, 0.01), 0) << describe(r);   // floor
  EXPECT_GE(planeNear(r, 0.75, 0.01), 0) << describe(r);  // table top
}

TEST(Threads, PatternObjectAtTheFineSettingIsTheSameForAnyNumberOfThreads) {
  const auto camera = synthetic::patternObjectCamera();
  const auto frame =
      synthetic::patternObjectScene().render(camera, synthetic::SensorNoise::kinectLike());
  Params params;
  params.r_xy = 0.009;
  params.r_z = 0.002;
  const Result r = expectSameForAnyThreads(depthToCloud(frame.depth, camera.intrinsics, 1.0),
                                           poseOf(camera.pose), params, "pattern object");
  EXPECT_GE(r.planes.size(), 10u) << describe(r);  // many small steps: a busy comparison
}

TEST(Threads, LidarScanIsTheSameForAnyNumberOfThreads) {
  const auto scan = synthetic::scanWithLidar(
      synthetic::lidarStreet(), synthetic::LidarModel::hdl64(), synthetic::lidarStreetPose());
  Params params;
  params.r_xy = 0.3;
  params.r_z = 0.1;
  const Result r = expectSameForAnyThreads(
      scan.toCloud(), Orientation::identity().withViewpoint(Eigen::Vector3d::Zero()), params,
      "HDL-64E street");
  EXPECT_GE(r.planes.size(), 2u) << describe(r);  // road, sidewalk, platform, ...
}

TEST(Threads, TumFrameIsTheSameForAnyNumberOfThreads) {
  const std::optional<TumFrame> tum = tumFrameWithLastPose();
  if (!tum) GTEST_SKIP() << "TUM data not found under " << sharedData("tum_fr1_desk");
  const Result r = expectSameForAnyThreads(tum->cloud, tum->orientation, Params(), "TUM frame");
  // The desk top, 0.78 m above the floor in the ground truth's frame (test_tum).
  EXPECT_GE(planeNear(r, 0.78, 0.03), 0) << describe(r);
}

// A z-up cloud with no rotation and no translation is read in place: the aligned points the
// extractor exposes are the input's own memory, and the planes and labels are those of the
// copying path (forced here by a layout whose x is not at the start of each point).
TEST(NoCopy, ZUpCloudIsReadInPlaceWithTheSameResultAsTheAlignedCopy) {
  const auto scan = synthetic::demoRoom().scanFromAbove(-1.0, -3.0, 5.0, 3.0, 0.01, 0.002);
  Extractor in_place;
  const Result direct = in_place.extract(scan.cloud, Orientation::identity());
  EXPECT_EQ(in_place.alignedPoints().data,
            reinterpret_cast<const std::uint8_t*>(&scan.cloud.points[0]));
  EXPECT_EQ(in_place.alignedPoints().size(), scan.cloud.size());

  const ShiftedCopy shifted(scan.cloud);
  const PointsView view = shifted.view();
  Extractor copying;
  const Result copied = copying.extract(view, Orientation::identity());
  EXPECT_NE(copying.alignedPoints().data, view.data);  // the aligned copy

  ASSERT_EQ(direct.planes.size(), copied.planes.size()) << describe(direct);
  for (std::size_t k = 0; k < direct.planes.size(); ++k) {
    expectSamePlane(direct.planes[k], copied.planes[k], "plane " + std::to_string(k));
  }
  EXPECT_EQ(direct.point_labels, copied.point_labels);
  // The truth: floor and table top.
  EXPECT_GE(planeNear(direct, 0.0, 0.01), 0) << describe(direct);
  EXPECT_GE(planeNear(direct, 0.75, 0.01), 0) << describe(direct);
}

}  // namespace test
}  // namespace hope
