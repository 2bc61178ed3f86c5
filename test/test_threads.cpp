// Params::threads splits the passes over points and voxels across threads; the output must not
// depend on it. Each scene is extracted with 1, 2 and 3 threads (3: shares that do not divide
// evenly) and every plane field, every hull vertex and every point label must be identical.
// Also the in-place read of a z-up cloud against the aligned copy (NoCopy).
#include <atomic>
#include <chrono>
#include <cmath>
#include <mutex>
#include <set>
#include <string>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "helpers.h"
#include "hope/depth_image.h"
#include "hope/extractor.h"
#include "hope/synthetic/lidar.h"
#include "hope/synthetic/paper_scenes.h"
#include "hope/synthetic/scene.h"
#include "scene_inputs.h"
// The pool is private to the core library; its behaviour is tested here directly.
#include "../src/core/worker_pool.h"

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

// The pool runs every task exactly once, whatever the number of helpers asked for.
TEST(WorkerPool, RunsEveryTaskExactlyOnce) {
  hope::parallel::WorkerPool& pool = hope::parallel::WorkerPool::shared();
  for (int helpers : {0, 1}) {
    for (std::size_t count : {std::size_t{0}, std::size_t{1}, std::size_t{2}, std::size_t{1000}}) {
      std::vector<std::atomic<int>> runs(count);
      pool.run(count, helpers, [&](std::size_t i) { runs[i].fetch_add(1); });
      for (std::size_t i = 0; i < count; ++i) {
        ASSERT_EQ(runs[i].load(), 1) << "task " << i << " of " << count << ", helpers " << helpers;
      }
    }
  }
}

// Two tasks that can only finish together (each waits for the other to have started) finish:
// with one helper the two run on two threads at once.
TEST(WorkerPool, OneHelperRunsATaskBesideTheCaller) {
  std::atomic<int> started{0};
  std::mutex mutex;
  std::set<std::thread::id> threads;
  hope::parallel::WorkerPool::shared().run(2, 1, [&](std::size_t) {
    {
      std::lock_guard<std::mutex> lock(mutex);
      threads.insert(std::this_thread::get_id());
    }
    started.fetch_add(1);
    const auto give_up = std::chrono::steady_clock::now() + std::chrono::seconds(20);
    while (started.load() < 2 && std::chrono::steady_clock::now() < give_up) {
      std::this_thread::yield();
    }
  });
  EXPECT_EQ(started.load(), 2);
  EXPECT_EQ(threads.size(), 2u);
}

// The caller never waits for a helper to start: while the only helper is held up (here: held
// inside the one task it claimed, as a helper the scheduler does not run is), the caller runs
// every other task itself, and the job ends as soon as the held task does.
TEST(WorkerPool, TheCallerRunsEveryTaskNoHelperHasStarted) {
  const std::thread::id caller = std::this_thread::get_id();
  std::atomic<int> by_caller{0}, by_helper{0};
  std::atomic<bool> release{false};
  std::atomic<int> done{0};
  const std::size_t count = 200;
  std::thread releaser([&] {
    // Lets the held task go once the caller has run every other task.
    const auto give_up = std::chrono::steady_clock::now() + std::chrono::seconds(20);
    while (done.load() < static_cast<int>(count) - 1 &&
           std::chrono::steady_clock::now() < give_up) {
      std::this_thread::yield();
    }
    release = true;
  });
  hope::parallel::WorkerPool::shared().run(count, 1, [&](std::size_t) {
    if (std::this_thread::get_id() == caller) {
      by_caller.fetch_add(1);
    } else {
      by_helper.fetch_add(1);
      // The helper holds its first task until the caller has done all the others.
      while (!release.load()) std::this_thread::yield();
    }
    done.fetch_add(1);
  });
  releaser.join();
  EXPECT_EQ(done.load(), static_cast<int>(count));
  // The helper took at most the one task it was held in (none if it woke late).
  EXPECT_LE(by_helper.load(), 1);
  EXPECT_GE(by_caller.load(), static_cast<int>(count) - 1);
}

// A job asked for while another thread's job runs (two extractors on two threads, or a task
// that splits its own work) runs on its caller alone, at once: callers never wait for each other.
TEST(WorkerPool, ANestedJobRunsOnItsCaller) {
  hope::parallel::WorkerPool& pool = hope::parallel::WorkerPool::shared();
  std::atomic<int> inner_runs{0};
  std::atomic<bool> inner_on_one_thread{true};
  pool.run(4, 1, [&](std::size_t) {
    const std::thread::id outer = std::this_thread::get_id();
    pool.run(8, 1, [&](std::size_t) {
      inner_runs.fetch_add(1);
      if (std::this_thread::get_id() != outer) inner_on_one_thread = false;
    });
  });
  EXPECT_EQ(inner_runs.load(), 32);
  EXPECT_TRUE(inner_on_one_thread.load());
}

// More threads asked for than there are cores start no more helpers than cores: a request for
// 1024 threads (the parameter's limit) must not start a thousand threads. The planes are the
// same (the shares are still 1024).
TEST(WorkerPool, NoMoreHelpersThanCores) {
  const hope::synthetic::Scene scene = hope::synthetic::demoRoom();
  const auto scan = scene.scanFromAbove(-1.0, -3.0, 5.0, 3.0, 0.01, 0.0);
  hope::Params one, many;
  many.threads = 1024;
  const hope::Result a = hope::Extractor(one).extract(scan.cloud, hope::Orientation::identity());
  const hope::Result b = hope::Extractor(many).extract(scan.cloud, hope::Orientation::identity());
  ASSERT_EQ(a.planes.size(), b.planes.size());
  for (std::size_t k = 0; k < a.planes.size(); ++k) {
    EXPECT_EQ(a.planes[k].height, b.planes[k].height);
    EXPECT_EQ(a.planes[k].num_points, b.planes[k].num_points);
  }
  const unsigned cores = std::max(1u, std::thread::hardware_concurrency());
  // (A test above asks the pool itself for one helper, which a one-core machine also starts.)
  EXPECT_LE(hope::parallel::WorkerPool::shared().startedThreads(), std::max(1u, cores - 1));
}
