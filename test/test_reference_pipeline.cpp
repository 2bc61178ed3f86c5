// The exactness test of the speed work: the extractor against the paper's pipeline written the
// plain way, kept here and not in the product. The reference rotates every point with the
// plain formula, checks the grid against the plain std::map grid (reference_grid.h), takes each
// voxel's neighbourhood voxel by voxel (NormalNeighbourhood::moments, not the column-by-column
// pass) and its normal one voxel at a time (planeNormal, not the two-lane Newton steps), and
// measures every plane from all of its points: bbox by a loop over them, hull by convexHull2D
// over them (not the cell hull of the rim voxels), labels by a loop over the points' voxels.
// The stages that were not optimized (candidates, Z clustering, the refinement, the
// description from voxels) are the library's own. The paper's pipeline (no fragment merge, no
// scan-gap bridging) is what is compared: the merge is hope's departure, checked by its own
// tests and by test_threads. Inputs: the demo room seen by the camera, the TUM frame, the
// pattern object at the paper's fine setting and a 1 M-point unorganized scan.
#include <cmath>
#include <string>

#include <gtest/gtest.h>

#include "helpers.h"
#include "hope/convex_hull.h"
#include "hope/depth_image.h"
#include "hope/extractor.h"
#include "hope/horizontal_candidates.h"
#include "hope/normal_estimation.h"
#include "hope/pca_refinement.h"
#include "hope/plane_description.h"
#include "hope/synthetic/paper_scenes.h"
#include "hope/synthetic/scene.h"
#include "hope/z_clustering.h"
#include "reference_grid.h"
#include "scene_inputs.h"

namespace hope {
namespace test {
namespace {

struct ReferenceResult {
  std::vector<HorizontalPlane> planes;
  std::vector<std::int32_t> labels;
};

// The paper's pipeline, stage by stage, the plain way (see the file's comment).
ReferenceResult referencePipeline(const pcl::PointCloud<pcl::PointXYZ>& cloud,
                                  const Orientation& orientation, const Params& params) {
  // Alignment: q = R·p + (t − origin), each coordinate as r_i0·x + r_i1·y + r_i2·z + t_i in
  // float; a point with a non-finite coordinate after the transform becomes NaN.
  const Eigen::Vector3d origin = localOrigin(orientation);
  const Eigen::Matrix3f r = orientation.sensorToReference().linear().cast<float>();
  const Eigen::Vector3f t = (orientation.sensorToReference().translation() - origin).cast<float>();
  const float nan = std::numeric_limits<float>::quiet_NaN();
  std::vector<Eigen::Vector3f> aligned;
  aligned.reserve(cloud.size());
  for (const pcl::PointXYZ& p : cloud.points) {
    Eigen::Vector3f q;
    for (int i = 0; i < 3; ++i) q[i] = r(i, 0) * p.x + r(i, 1) * p.y + r(i, 2) * p.z + t[i];
    aligned.push_back(q.allFinite() ? q : Eigen::Vector3f(nan, nan, nan));
  }

  VoxelGrid grid;
  grid.build(aligned, params.r_xy, params.r_z);
  expectSameAsReference(grid, aligned, params.r_xy, params.r_z);

  // Normals voxel by voxel.
  const NormalNeighbourhood neighbourhood(grid, params.normal_radius_factor);
  std::vector<Eigen::Vector3f> normals(grid.numVoxels(), Eigen::Vector3f(nan, nan, nan));
  for (std::size_t v = 0; v < grid.numVoxels(); ++v) {
    const NormalNeighbourhood::Moments m = neighbourhood.moments(v);
    Eigen::Vector3f n;
    if (m.count < 3 || !planeNormal(m.covariance(), n)) continue;
    n.normalize();
    normals[v] = n.z() < 0 ? Eigen::Vector3f(-n) : n;
  }

  std::vector<std::uint8_t> is_candidate;
  selectHorizontalCandidates(normals, params.gamma(), is_candidate);
  const auto clusters = zClustering(grid, is_candidate, params.r_z, params.min_cluster_voxels);

  const std::vector<std::int32_t> voxel_of_point = grid.pointVoxel();
  ReferenceResult result;
  std::vector<std::int32_t> plane_of_voxel(grid.numVoxels(), -1);
  for (const std::vector<std::uint32_t>& cluster : clusters) {
    const RefinementVerdict verdict = refineWithPCA(normals, cluster, params.gamma());
    if (!verdict.horizontal || footprintMinorVariance(grid, cluster) < kMinFootprintVariance) {
      continue;
    }
    HorizontalPlane plane = describePlane(grid, aligned, cluster, Detail::kVoxels);
    if (plane.tilt > params.maxSlope()) continue;
    const double height = plane.height + origin.z();
    if (height < params.min_height || height > params.max_height || plane.area < params.min_area) {
      continue;
    }
    plane.mean_normal_tilt = verdict.mean_tilt;
    plane.group_angle = verdict.group_angle;
    // Measured in full from every point of its voxels.
    std::vector<std::uint8_t> member(grid.numVoxels(), 0);
    for (std::uint32_t v : cluster) member[v] = 1;
    std::vector<Eigen::Vector2d> points;
    for (std::size_t i = 0; i < aligned.size(); ++i) {
      if (voxel_of_point[i] >= 0 && member[static_cast<std::size_t>(voxel_of_point[i])]) {
        points.emplace_back(aligned[i].x(), aligned[i].y());
      }
    }
    Eigen::Vector2d lo(HUGE_VAL, HUGE_VAL), hi(-HUGE_VAL, -HUGE_VAL);
    for (const Eigen::Vector2d& q : points) {
      lo = lo.cwiseMin(q);
      hi = hi.cwiseMax(q);
    }
    plane.bbox = {lo.x(), lo.y(), hi.x(), hi.y()};
    plane.hull.clear();
    for (const Eigen::Vector2d& h : convexHull2D(points)) {
      plane.hull.emplace_back(h.x(), h.y(), plane.height);
    }
    plane.translate(origin);
    for (std::uint32_t v : cluster) {
      plane_of_voxel[v] = static_cast<std::int32_t>(result.planes.size());
    }
    result.planes.push_back(std::move(plane));
  }
  result.labels.resize(aligned.size());
  for (std::size_t i = 0; i < aligned.size(); ++i) {
    const std::int32_t v = voxel_of_point[i];
    result.labels[i] = v < 0 ? -1 : plane_of_voxel[static_cast<std::size_t>(v)];
  }
  return result;
}

// The extractor, with the paper's pipeline, on one and on two threads, against the reference:
// the same planes (count, height within 1e-6 m, point and voxel counts, bbox, hull, normal)
// and the same label for every point. Returns the extractor's result on one thread.
Result expectSameAsReferencePipeline(const pcl::PointCloud<pcl::PointXYZ>& cloud,
                                     const Orientation& orientation, Params params,
                                     const std::string& scene) {
  params.merge_fragments = false;
  params.bridge_scan_gaps = false;
  const ReferenceResult reference = referencePipeline(cloud, orientation, params);
  Result first;
  for (int threads : {1, 2}) {
    params.threads = threads;
    Extractor extractor(params);
    Result r = extractor.extract(cloud, orientation);
    const std::string what = scene + ", " + std::to_string(threads) + " thread(s)";
    EXPECT_EQ(r.point_labels, reference.labels) << what;
    EXPECT_EQ(r.planes.size(), reference.planes.size()) << what << ": " << describe(r);
    for (std::size_t k = 0; k < std::min(r.planes.size(), reference.planes.size()); ++k) {
      const HorizontalPlane& a = r.planes[k];
      const HorizontalPlane& b = reference.planes[k];
      const std::string plane = what + ", plane " + std::to_string(k);
      EXPECT_NEAR(a.height, b.height, 1e-6) << plane;
      EXPECT_EQ(a.num_points, b.num_points) << plane;
      EXPECT_EQ(a.num_voxels, b.num_voxels) << plane;
      EXPECT_EQ(a.area, b.area) << plane;
      for (int c = 0; c < 4; ++c) EXPECT_EQ(a.bbox[c], b.bbox[c]) << plane << ", bbox " << c;
      EXPECT_LT((a.normal - b.normal).norm(), 1e-12) << plane;
      EXPECT_EQ(a.mean_normal_tilt, b.mean_normal_tilt) << plane;
      EXPECT_EQ(a.hull.size(), b.hull.size()) << plane;
      for (std::size_t h = 0; h < std::min(a.hull.size(), b.hull.size()); ++h) {
        EXPECT_LT((a.hull[h] - b.hull[h]).norm(), 1e-9) << plane << ", hull vertex " << h;
      }
    }
    if (threads == 1) first = std::move(r);
  }
  return first;
}

}  // namespace

TEST(ReferencePipeline, DemoRoomCameraView) {
  const auto scene = synthetic::demoRoom();
  const auto camera = synthetic::demoCamera();
  const auto cloud = depthToCloud(scene.render(camera).depth, camera.intrinsics, 1.0);
  const Result r = expectSameAsReferencePipeline(cloud, poseOf(camera.pose), Params(), "demo room");
  // The scene's true horizontal surfaces, each found (not a comparison of two empty results).
  for (double height : {0.0, 0.75, 0.45, 0.17, 0.34, 0.80}) {
    EXPECT_GE(planeNear(r, height, 0.01), 0) << "no plane at " << height << ": " << describe(r);
  }
}

TEST(ReferencePipeline, TumFrame) {
  const std::optional<TumFrame> tum = tumFrameWithLastPose();
  if (!tum) GTEST_SKIP() << "TUM data not found under " << sharedData("tum_fr1_desk");
  const Result r =
      expectSameAsReferencePipeline(tum->cloud, tum->orientation, Params(), "TUM frame");
  // The desk top, 0.78 m above the floor in the ground truth's frame (test_tum).
  EXPECT_GE(planeNear(r, 0.78, 0.03), 0) << describe(r);
}

TEST(ReferencePipeline, PatternObjectAtThePapersFineSetting) {
  const auto camera = synthetic::patternObjectCamera();
  const auto frame =
      synthetic::patternObjectScene().render(camera, synthetic::SensorNoise::kinectLike());
  Params params;
  params.r_xy = 0.009;
  params.r_z = 0.002;
  const Result r = expectSameAsReferencePipeline(depthToCloud(frame.depth, camera.intrinsics, 1.0),
                                                 poseOf(camera.pose), params, "pattern object");
  EXPECT_GE(r.planes.size(), 10u) << describe(r);  // many small steps: a busy comparison
}

TEST(ReferencePipeline, MillionPointUnorganizedScan) {
  // The demo room scanned from above every 6 mm over 6 x 6 m: 1.0 M points, z up, read in place.
  const auto scan = synthetic::demoRoom().scanFromAbove(-1.0, -3.0, 5.0, 3.0, 0.006, 0.002);
  ASSERT_GE(scan.cloud.size(), 1000000u);
  const Result r = expectSameAsReferencePipeline(scan.cloud, Orientation::identity(), Params(),
                                                 "1 M-point scan");
  EXPECT_GE(planeNear(r, 0.0, 0.01), 0) << describe(r);   // floor
  EXPECT_GE(planeNear(r, 0.75, 0.01), 0) << describe(r);  // table top
}

}  // namespace test
}  // namespace hope
