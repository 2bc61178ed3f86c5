// The behaviours that matter, on scenes with a known answer.
#include <cmath>

#include "helpers.h"

namespace hope {
namespace test {

namespace {

constexpr double kSpacing = 0.01;  // 1 cm sampling: about 25 points per 5 cm voxel column

// Scans a single primitive (plus nothing else) from above.
template <class P, class... Args>
Result scanPrimitive(double half_size, Args&&... args) {
  synthetic::Scene scene;
  scene.add<P>(std::forward<Args>(args)...);
  const LabeledCloud scan =
      scene.scanFromAbove(-half_size, -half_size, half_size, half_size, kSpacing);
  return extractZUp(scan.cloud);
}

Result tiltedPlane(double angle) {
  synthetic::Scene scene;
  const Eigen::Matrix3d r = Eigen::AngleAxisd(angle, V3::UnitY()).toRotationMatrix();
  scene.add<synthetic::Rectangle>(V3(0, 0, 1.0), r * V3::UnitX(), r * V3::UnitY(), 0.6, 0.6, 0);
  const LabeledCloud scan = scene.scanFromAbove(-0.7, -0.7, 0.7, 0.7, kSpacing);
  return extractZUp(scan.cloud);
}

}  // namespace

TEST(Extractor, TwoStackedPlanesThreeRzApartAreTwoPlanesAtTheirHeights) {
  const Params params;  // r_xy 0.05, r_z 0.02
  LabeledCloud cloud;
  addSheet(cloud, 0, 0, 1, 1, 0.70, kSpacing, 0);
  addSheet(cloud, 0, 0, 1, 1, 0.70 + 3 * params.r_z, kSpacing, 1);
  const Result result = extractZUp(cloud.cloud, params);
  ASSERT_EQ(result.planes.size(), 2u) << describe(result);
  EXPECT_GE(planeNear(result, 0.70, 0.005), 0) << describe(result);
  EXPECT_GE(planeNear(result, 0.76, 0.005), 0) << describe(result);
}

TEST(Extractor, TwoSideBySideStepsThreeRzApartAreTwoPlanes) {
  LabeledCloud cloud;
  addSheet(cloud, 0, 0, 1, 1, 0.0, kSpacing, 0);
  addSheet(cloud, 1.0 + kSpacing, 0, 2, 1, 0.06, kSpacing, 1);
  const Result result = extractZUp(cloud.cloud);
  ASSERT_EQ(result.planes.size(), 2u) << describe(result);
  EXPECT_GE(planeNear(result, 0.0, 0.005), 0);
  EXPECT_GE(planeNear(result, 0.06, 0.005), 0);
}

TEST(Extractor, TablesAtOneHeightSeparatedByMoreThanTwoRxyAreTwoPlanes) {
  const Params params;
  const double gap = 2.2 * params.r_xy;
  LabeledCloud cloud;
  addSheet(cloud, 0, 0, 1, 1, 0.75, kSpacing, 0);
  addSheet(cloud, 1 + gap, 0, 2 + gap, 1, 0.75, kSpacing, 1);
  const Result result = extractZUp(cloud.cloud, params);
  ASSERT_EQ(result.planes.size(), 2u) << describe(result);
  EXPECT_NEAR(result.planes[0].height, 0.75, 0.002);
  EXPECT_NEAR(result.planes[1].height, 0.75, 0.002);
  // Each table keeps its own extent: neither bbox reaches across the gap.
  EXPECT_LT(std::min(result.planes[0].bbox[2], result.planes[1].bbox[2]), 1.0 + 1e-3);
  EXPECT_GT(std::max(result.planes[0].bbox[0], result.planes[1].bbox[0]), 1.0 + gap - 1e-3);
}

TEST(Extractor, TablesTouchingAtOneHeightAreOnePlane) {
  LabeledCloud cloud;
  addSheet(cloud, 0, 0, 1, 1, 0.75, kSpacing, 0);
  addSheet(cloud, 1 + kSpacing, 0, 2, 1, 0.75, kSpacing, 1);
  const Result result = extractZUp(cloud.cloud);
  ASSERT_EQ(result.planes.size(), 1u) << describe(result);
}

TEST(Extractor, PlaneTiltedJustBelowTheSlopeLimitIsKept) {
  const double limit = Params().maxSlope();  // atan(0.4) ≈ 0.3805 rad
  const Result result = tiltedPlane(limit - 0.05);
  ASSERT_GE(result.planes.size(), 1u) << describe(result);
  EXPECT_NEAR(result.planes[0].tilt, limit - 0.05, 0.01);
}

TEST(Extractor, PlaneTiltedJustAboveTheSlopeLimitIsRejected) {
  const double limit = Params().maxSlope();
  const Result result = tiltedPlane(limit + 0.05);
  EXPECT_EQ(result.planes.size(), 0u) << describe(result);
}

TEST(Extractor, SphereCapIsRejected) {
  const Result result = scanPrimitive<synthetic::Sphere>(0.6, V3(0, 0, 0), 0.5);
  EXPECT_EQ(result.planes.size(), 0u) << describe(result);
}

TEST(Extractor, ConeIsRejected) {
  const Result result = scanPrimitive<synthetic::Cone>(0.6, V3(0, 0, 0.5), 0.5, 0.5);
  EXPECT_EQ(result.planes.size(), 0u) << describe(result);
}

TEST(Extractor, LyingCylinderTopIsRejected) {
  const Result result = scanPrimitive<synthetic::Cylinder>(0.6, V3(0, -0.5, 0), V3(0, 0.5, 0), 0.3);
  EXPECT_EQ(result.planes.size(), 0u) << describe(result);
}

TEST(Extractor, TiltedSensorWithKnownQuaternionPutsTheFloorAtItsHeight) {
  // A floor at z = 0 seen by a sensor 1.2 m up, pitched down 40°, rolled 10°: express the
  // floor in the sensor frame, then let the extractor undo it.
  const Eigen::Quaterniond q = Eigen::AngleAxisd(0.3, V3::UnitZ()) *
                               Eigen::AngleAxisd(0.7, V3::UnitY()) *
                               Eigen::AngleAxisd(0.17, V3::UnitX());
  const V3 t(0.2, -0.1, 1.2);
  LabeledCloud world;
  addSheet(world, -1, -1, 1, 1, 0.0, kSpacing, 0);
  pcl::PointCloud<pcl::PointXYZ> sensor;
  for (const auto& p : world.cloud) {
    const V3 s = q.conjugate() * (V3(p.x, p.y, p.z) - t);
    sensor.push_back(pcl::PointXYZ(s.x(), s.y(), s.z()));
  }
  Extractor extractor;
  const Result result = extractor.extract(
      sensor, Orientation::fromPose(t.x(), t.y(), t.z(), q.x(), q.y(), q.z(), q.w()));
  ASSERT_EQ(result.planes.size(), 1u) << describe(result);
  EXPECT_NEAR(result.planes[0].height, 0.0, 0.002);
  EXPECT_LT(result.planes[0].tilt, 0.01);
  // Without the pose the same cloud has no horizontal plane at all (it is tilted 40°).
  EXPECT_EQ(extractor.extract(sensor, Orientation::identity()).planes.size(), 0u);
}

TEST(Extractor, LabelsCoverEveryInputPointInOrder) {
  LabeledCloud cloud;
  addSheet(cloud, 0, 0, 1, 1, 0.5, kSpacing, 0);
  cloud.cloud.push_back(pcl::PointXYZ(NAN, 0, 0));
  cloud.cloud.push_back(pcl::PointXYZ(0.5, 0.5, 3.0));  // a lone point far above
  const Result result = extractZUp(cloud.cloud);
  ASSERT_EQ(result.point_labels.size(), cloud.cloud.size());
  ASSERT_EQ(result.planes.size(), 1u);
  const std::size_t n = cloud.cloud.size();
  EXPECT_EQ(result.point_labels[n - 2], -1);
  EXPECT_EQ(result.point_labels[n - 1], -1);
  std::size_t labelled = 0;
  for (std::size_t i = 0; i + 2 < n; ++i) labelled += result.point_labels[i] == 0 ? 1 : 0;
  EXPECT_EQ(labelled, n - 2);
  EXPECT_EQ(result.planes[0].num_points, n - 2);
}

TEST(Extractor, PointLabelsLeftOutOnRequestWithTheSamePlanes) {
  LabeledCloud cloud;
  addSheet(cloud, 0, 0, 1, 1, 0.5, kSpacing, 0);
  addSheet(cloud, 0.2, 0.2, 0.6, 0.6, 0.9, kSpacing, 1);
  Extractor extractor;
  ExtractOutputs without_labels;
  without_labels.point_labels = false;
  const Result bare = extractor.extract(cloud.cloud, Orientation::identity(), without_labels);
  const Result full = extractor.extract(cloud.cloud, Orientation::identity());
  EXPECT_TRUE(bare.point_labels.empty());
  EXPECT_EQ(full.point_labels.size(), cloud.cloud.size());
  ASSERT_EQ(bare.planes.size(), 2u) << describe(bare);
  ASSERT_EQ(full.planes.size(), 2u) << describe(full);
  const auto heights = std::minmax(bare.planes[0].height, bare.planes[1].height);
  EXPECT_NEAR(heights.first, 0.5, 0.002);
  EXPECT_NEAR(heights.second, 0.9, 0.002);
  for (std::size_t k = 0; k < 2; ++k) {
    EXPECT_EQ(bare.planes[k].height, full.planes[k].height);
    EXPECT_EQ(bare.planes[k].num_points, full.planes[k].num_points);
    EXPECT_EQ(bare.planes[k].hull.size(), full.planes[k].hull.size());
  }
}
TEST(Extractor, PlaneDescriptionMatchesTheSheet) {
  LabeledCloud cloud;
  addSheet(cloud, -0.3, 0.2, 0.9, 1.0, 0.42, kSpacing, 0);
  const Result result = extractZUp(cloud.cloud);
  ASSERT_EQ(result.planes.size(), 1u);
  const HorizontalPlane& p = result.planes[0];
  EXPECT_NEAR(p.height, 0.42, 1e-4);
  EXPECT_NEAR(p.bbox[0], -0.3, 1e-3);
  EXPECT_NEAR(p.bbox[1], 0.2, 1e-3);
  EXPECT_NEAR(p.bbox[2], 0.9, 1e-3);
  EXPECT_NEAR(p.bbox[3], 1.0, 1e-3);
  EXPECT_NEAR(p.centroid.x(), 0.3, 1e-3);
  EXPECT_NEAR(p.centroid.y(), 0.6, 1e-3);
  EXPECT_NEAR(p.normal.z(), 1.0, 1e-6);
  EXPECT_NEAR(p.area, 1.2 * 0.8, 0.15);  // grid footprint: within a cell border
  // The hull is the rectangle: every vertex on its border, the same area, counter-clockwise.
  ASSERT_GE(p.hull.size(), 4u);
  double twice_area = 0;
  for (std::size_t i = 0; i < p.hull.size(); ++i) {
    const auto& a = p.hull[i];
    const auto& b = p.hull[(i + 1) % p.hull.size()];
    twice_area += a.x() * b.y() - b.x() * a.y();
    const double to_border = std::min({std::fabs(a.x() + 0.3), std::fabs(a.x() - 0.9),
                                       std::fabs(a.y() - 0.2), std::fabs(a.y() - 1.0)});
    EXPECT_LT(to_border, 1e-3);
    EXPECT_NEAR(a.z(), 0.42, 1e-4);
  }
  EXPECT_NEAR(0.5 * twice_area, 1.2 * 0.8, 3e-3);
}

TEST(Extractor, HeightBandAndMinimumAreaDropPlanes) {
  LabeledCloud cloud;
  addSheet(cloud, 0, 0, 2, 2, 0.0, 0.02, 0);
  addSheet(cloud, 0.5, 0.5, 0.8, 0.8, 0.75, kSpacing, 1);
  Params params;
  EXPECT_EQ(extractZUp(cloud.cloud, params).planes.size(), 2u);
  params.min_height = 0.3;
  Result banded = extractZUp(cloud.cloud, params);
  ASSERT_EQ(banded.planes.size(), 1u);
  EXPECT_NEAR(banded.planes[0].height, 0.75, 0.002);
  EXPECT_GE(banded.planes[0].hull.size(), 4u);  // the kept plane is measured in full
  // The dropped floor's points are on no plane; the table's are all on plane 0.
  ASSERT_EQ(banded.point_labels.size(), cloud.cloud.size());
  std::size_t floor_points = 0, table_points = 0;
  for (std::size_t i = 0; i < cloud.cloud.size(); ++i) {
    if (cloud.labels[i] == 0) {
      ++floor_points;
      EXPECT_EQ(banded.point_labels[i], -1) << "floor point " << i;
    } else {
      ++table_points;
      EXPECT_EQ(banded.point_labels[i], 0) << "table point " << i;
    }
  }
  EXPECT_GT(floor_points, 1000u);
  EXPECT_GT(table_points, 100u);
  params = Params();
  params.min_area = 0.5;
  Result big = extractZUp(cloud.cloud, params);
  ASSERT_EQ(big.planes.size(), 1u);
  EXPECT_NEAR(big.planes[0].height, 0.0, 0.002);
}

}  // namespace test
}  // namespace hope
