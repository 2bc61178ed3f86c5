// Bad input: a clear error or an empty result, never a crash, a hang or garbage.
#include <cmath>
#include <limits>
#include <stdexcept>

#include "helpers.h"
#include "hope/depth_image.h"

namespace hope {
namespace test {

namespace {

std::string errorOf(const Params& params) {
  try {
    Extractor extractor(params);
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST(BadInput, InvalidParametersAreRejectedNamingTheParameter) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  Params p;
  p.r_xy = 0;
  EXPECT_NE(errorOf(p).find("r_xy"), std::string::npos);
  p.r_xy = -0.05;
  EXPECT_NE(errorOf(p).find("r_xy"), std::string::npos);
  p.r_xy = nan;
  EXPECT_NE(errorOf(p).find("r_xy"), std::string::npos);
  p.r_xy = 50;  // centimetres passed as metres
  EXPECT_NE(errorOf(p).find("millimetres or centimetres"), std::string::npos);
  p = Params();
  p.r_z = 0;
  EXPECT_NE(errorOf(p).find("r_z"), std::string::npos);
  p.r_z = std::numeric_limits<double>::infinity();
  EXPECT_NE(errorOf(p).find("r_z"), std::string::npos);
  p = Params();
  p.normal_radius_factor = 0.5;
  EXPECT_NE(errorOf(p).find("normal_radius_factor"), std::string::npos);
  p = Params();
  p.min_cluster_voxels = 2;
  EXPECT_NE(errorOf(p).find("min_cluster_voxels"), std::string::npos);
  p = Params();
  p.min_height = 1.0;
  p.max_height = 0.5;
  EXPECT_NE(errorOf(p).find("min_height"), std::string::npos);
  p = Params();
  p.min_area = -1;
  EXPECT_NE(errorOf(p).find("min_area"), std::string::npos);
  p = Params();
  p.threads = -1;
  EXPECT_EQ(errorOf(p), "parameter threads = -1 is out of range [0, 1024] (0 takes every core)");
  p.threads = 5000;
  EXPECT_NE(errorOf(p).find("threads = 5000"), std::string::npos);
  p.threads = 0;  // every core
  EXPECT_EQ(errorOf(p), "");
  EXPECT_EQ(errorOf(Params()), "");
}

TEST(BadInput, EmptyAllNanSinglePointAndNoHorizontalSurfaceGiveEmptyResults) {
  Extractor extractor;
  pcl::PointCloud<pcl::PointXYZ> cloud;
  Result r = extractor.extract(cloud, Orientation::identity());
  EXPECT_TRUE(r.planes.empty());
  EXPECT_TRUE(r.point_labels.empty());

  pcl::PointCloud<pcl::PointXYZ> nans(64, 48, pcl::PointXYZ(NAN, NAN, NAN));  // organized
  r = extractor.extract(nans, Orientation::identity());
  EXPECT_TRUE(r.planes.empty());
  EXPECT_EQ(r.point_labels.size(), nans.size());
  EXPECT_EQ(r.finite_points, 0u);

  cloud.push_back(pcl::PointXYZ(1, 2, 3));
  r = extractor.extract(cloud, Orientation::identity());
  EXPECT_TRUE(r.planes.empty());
  EXPECT_EQ(r.point_labels, std::vector<std::int32_t>{-1});

  // A wall: vertical, so nothing horizontal.
  LabeledCloud wall;
  synthetic::Rectangle rect(V3(0, 0, 1), V3::UnitX(), V3::UnitZ(), 1, 1, 0);
  synthetic::sampleRectangle(rect, 0.01, 0, wall);
  r = extractor.extract(wall.cloud, Orientation::identity());
  EXPECT_TRUE(r.planes.empty()) << describe(r);
}

TEST(BadInput, NanLadenOrganizedCloudStillFindsItsPlane) {
  // A 100 × 100 organized sheet with every third point missing, like an RGB-D frame.
  pcl::PointCloud<pcl::PointXYZ> cloud(100, 100);
  for (int r = 0; r < 100; ++r) {
    for (int c = 0; c < 100; ++c) {
      cloud.at(c, r) = (r * 100 + c) % 3 == 0 ? pcl::PointXYZ(NAN, NAN, NAN)
                                              : pcl::PointXYZ(c * 0.01f, r * 0.01f, 0.9f);
    }
  }
  const Result result = extractZUp(cloud);
  ASSERT_EQ(result.planes.size(), 1u);
  EXPECT_NEAR(result.planes[0].height, 0.9, 1e-4);
  EXPECT_EQ(result.point_labels[0], -1);
  EXPECT_EQ(result.point_labels[1], 0);
}

TEST(BadInput, HugeCoordinatesAreAClearErrorAndMillimetresAWarning) {
  LabeledCloud cloud;
  addSheet(cloud, 0, 0, 1, 1, 0, 0.01, 0);
  cloud.cloud.push_back(pcl::PointXYZ(1e7f, 0, 0));  // a wild outlier
  Extractor extractor;
  EXPECT_THROW(extractor.extract(cloud.cloud, Orientation::identity()), std::invalid_argument);

  // The same sheet in millimetres: the extractor still answers but says why it looks wrong.
  LabeledCloud mm;
  addSheet(mm, 0, 0, 2000, 2000, 750, 20, 0);
  const Result r = extractor.extract(mm.cloud, Orientation::identity());
  ASSERT_EQ(r.warnings.size(), 1u);
  EXPECT_NE(r.warnings[0].find("millimetres"), std::string::npos);

  // Points at 1e30 overflow when transformed; they are skipped like NaN.
  pcl::PointCloud<pcl::PointXYZ> overflow = cloud.cloud;
  overflow.back() = pcl::PointXYZ(3e38f, 3e38f, 3e38f);
  const Result o = extractor.extract(overflow, Orientation::fromRollPitchYaw(0.3, 0.2, 0.1));
  EXPECT_EQ(o.finite_points, overflow.size() - 1);
}

TEST(BadInput, PoseFarFromTheOriginKeepsItsMillimetres) {
  // The demo room seen from a pose in UTM-like map coordinates (500 km east, 5,000 km north,
  // 300 m up): in float, aligned points there lose everything below half a metre, and no
  // plane was found. Every true surface must come out at its true height + 300 m.
  const auto scene = synthetic::demoRoom();
  const auto camera = synthetic::demoCamera();
  const auto cloud = depthToCloud(scene.render(camera).depth, camera.intrinsics, 1.0);
  const Eigen::Quaterniond q(camera.pose.linear());
  const Eigen::Vector3d t = camera.pose.translation();
  const Eigen::Vector3d offset(500000.0, 5000000.0, 300.0);
  const Eigen::Vector3d far = t + offset;
  Extractor extractor;
  const Result near_result = extractor.extract(
      cloud, Orientation::fromPose(t.x(), t.y(), t.z(), q.x(), q.y(), q.z(), q.w()));
  const Result result = extractor.extract(
      cloud, Orientation::fromPose(far.x(), far.y(), far.z(), q.x(), q.y(), q.z(), q.w()));
  EXPECT_TRUE(result.warnings.empty()) << result.warnings.front();
  const std::vector<double> truth = {0.0, 0.75, 0.45, 0.17, 0.34, 0.80};
  // As many planes as the same view near the origin (where every true surface is found).
  ASSERT_EQ(result.planes.size(), near_result.planes.size()) << describe(result);
  for (double height : truth) {
    const int k = planeNear(result, height + offset.z(), 0.01);
    ASSERT_GE(k, 0) << "no plane at " << height << " + 300 m: " << describe(result);
    // The same plane as seen near the origin, moved by the offset to the millimetre.
    const int n = planeNear(near_result, height, 0.01);
    ASSERT_GE(n, 0);
    const HorizontalPlane& p = result.planes[k];
    const HorizontalPlane& r = near_result.planes[n];
    EXPECT_NEAR(p.height - offset.z(), r.height, 1e-3);
    EXPECT_NEAR(p.centroid.x() - offset.x(), r.centroid.x(), 1e-3);
    EXPECT_NEAR(p.centroid.y() - offset.y(), r.centroid.y(), 1e-3);
    EXPECT_NEAR(p.bbox[0] - offset.x(), r.bbox[0], 1e-3);
    EXPECT_NEAR(p.bbox[3] - offset.y(), r.bbox[3], 1e-3);
    ASSERT_FALSE(p.hull.empty());
    EXPECT_NEAR(p.hull[0].z() - offset.z(), r.height, 1e-3);
    EXPECT_NEAR(static_cast<double>(p.num_points), static_cast<double>(r.num_points),
                0.01 * static_cast<double>(r.num_points));
  }
}

TEST(BadInput, InconsistentOrganizedHeaderIsReadAsUnorganized) {
  LabeledCloud cloud;
  addSheet(cloud, 0, 0, 1, 1, 0.5, 0.01, 0);
  cloud.cloud.width = 7;  // lies about its shape
  cloud.cloud.height = 3;
  const PointsView view = PointsView::of(cloud.cloud);
  EXPECT_EQ(view.height, 1u);
  EXPECT_EQ(view.width, cloud.cloud.size());
  EXPECT_EQ(extractZUp(cloud.cloud).planes.size(), 1u);
}

}  // namespace test
}  // namespace hope
