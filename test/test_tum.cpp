// Real data: TUM RGB-D freiburg1_desk with its ground-truth pose (../shared/data).
#include <cmath>
#include <fstream>
#include <sstream>

#include <opencv2/imgcodecs.hpp>

#include "helpers.h"
#include "hope/depth_image.h"

namespace hope {
namespace test {

namespace {

struct TumFrame {
  pcl::PointCloud<pcl::PointXYZ> cloud;
  Orientation pose = Orientation::identity();
};

// Skips the calling test (with a message) when the shared data is absent.
bool loadTum(TumFrame& frame) {
  const std::string dir = sharedData("tum_fr1_desk");
  const cv::Mat depth = cv::imread(dir + "/1305031459.274941.png", cv::IMREAD_ANYDEPTH);
  std::ifstream gt(dir + "/groundtruth.txt");
  if (depth.empty() || !gt) return false;
  std::string line;
  double stamp, tx, ty, tz, qx, qy, qz, qw;
  while (std::getline(gt, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream(line) >> stamp >> tx >> ty >> tz >> qx >> qy >> qz >> qw;
  }
  frame.cloud = depthToCloud(depth, PinholeIntrinsics::tumFreiburg1(), 5000);
  frame.pose = Orientation::fromPose(tx, ty, tz, qx, qy, qz, qw);
  return true;
}

}  // namespace

TEST(TumFr1Desk, DeskTopsAt78cmWithVerticalNormalsAndTheFloorNearZero) {
  TumFrame frame;
  if (!loadTum(frame)) GTEST_SKIP() << "TUM data not found under " << sharedData("tum_fr1_desk");
  Extractor extractor;  // r_xy 0.05, r_z 0.02
  const Result result = extractor.extract(frame.cloud, frame.pose);
  EXPECT_EQ(result.point_labels.size(), 640u * 480u);

  // The desk: every large plane within 10 cm of the desk tops' height is a desk top at
  // 0.78 ± 0.03 m. (A sill behind the desk, 0.91 m, is a surface of its own.)
  std::size_t desk_points = 0;
  for (const HorizontalPlane& p : result.planes) {
    if (std::fabs(p.height - 0.78) > 0.1 || p.area < 0.3) continue;
    EXPECT_NEAR(p.height, 0.78, 0.03) << describe(result);
    EXPECT_LT(p.tilt, 3.0 * M_PI / 180.0) << describe(result);
    desk_points += p.num_points;
  }
  EXPECT_GT(desk_points, 50000u) << "desk tops not found: " << describe(result);

  // The floor: the planes below 0.15 m, near 0.
  const int floor = planeNear(result, 0.0, 0.08);
  ASSERT_GE(floor, 0) << describe(result);
  EXPECT_LT(result.planes[floor].tilt, 5.0 * M_PI / 180.0);
}

TEST(TumFr1Desk, PrintedEq2SmearsTheDeskWhichIsWhyHopeUsesTheRosConvention) {
  TumFrame frame;
  if (!loadTum(frame)) GTEST_SKIP() << "TUM data not found under " << sharedData("tum_fr1_desk");
  // Eq 2 as printed is R transposed: the inverse rotation.
  Eigen::Isometry3d wrong = frame.pose.sensorToReference();
  wrong.linear() = wrong.linear().transpose().eval();
  Extractor extractor;
  const Result result = extractor.extract(frame.cloud, Orientation::fromTransform(wrong));
  EXPECT_LT(planeNear(result, 0.78, 0.03), 0) << describe(result);
}

}  // namespace test
}  // namespace hope
