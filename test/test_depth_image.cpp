// The RGB-D path: depth image + intrinsics → organized cloud.
#include <stdexcept>

#include <opencv2/core.hpp>

#include "helpers.h"
#include "hope/depth_image.h"

namespace hope {
namespace test {

TEST(DepthImage, SixteenBitDepthWithScaleBackProjectsThroughThePinhole) {
  cv::Mat depth(4, 6, CV_16UC1, cv::Scalar(10000));  // 2 m at TUM's 5000 per metre
  depth.at<std::uint16_t>(1, 2) = 0;                 // no measurement
  const PinholeIntrinsics k{500, 400, 2, 1};
  const auto cloud = depthToCloud(depth, k, 5000);
  ASSERT_EQ(cloud.width, 6u);
  ASSERT_EQ(cloud.height, 4u);
  EXPECT_FLOAT_EQ(cloud.at(2, 0).z, 2.0f);  // principal column: straight ahead in x
  EXPECT_FLOAT_EQ(cloud.at(2, 0).x, 0.0f);
  EXPECT_TRUE(std::isnan(cloud.at(2, 1).z));  // the zeroed pixel
  EXPECT_FLOAT_EQ(cloud.at(5, 3).x, (5 - 2) * 2.0f / 500);
  EXPECT_FLOAT_EQ(cloud.at(5, 3).y, (3 - 1) * 2.0f / 400);
  EXPECT_FALSE(cloud.is_dense);
}

// Intrinsics that cannot be the camera of the image, and a depth scale that puts every depth
// under 1 mm or beyond 10 km, are refused with the reason instead of giving a cloud of
// non-finite or meaningless points.
TEST(DepthImage, IntrinsicsAndScaleThatDoNotFitTheImageAreRefused) {
  const cv::Mat depth(240, 320, CV_16UC1, cv::Scalar(10000));  // 2 m at 5000 per metre
  auto refusal = [&](const PinholeIntrinsics& k, double scale) {
    try {
      depthToCloud(depth, k, scale);
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  const PinholeIntrinsics fits{260, 260, 160, 120};
  EXPECT_EQ(refusal(fits, 5000), "accepted");
  // A 640 x 480 camera's intrinsics on a 320 x 240 image: the principal point is outside.
  EXPECT_NE(refusal(PinholeIntrinsics::tumFreiburg1(), 5000).find("principal point is outside"),
            std::string::npos);
  EXPECT_NE(refusal({1e-300, 1e-300, 160, 120}, 5000).find("the image would span"),
            std::string::npos);
  EXPECT_NE(refusal({1e6, 1e6, 160, 120}, 5000).find("the image would span"), std::string::npos);
  EXPECT_NE(refusal(fits, 1e300).find("depth scale 1e+300 puts this image's depths"),
            std::string::npos);
  EXPECT_NE(refusal(fits, 1e-300).find("depth scale 1e-300 puts this image's depths"),
            std::string::npos);
  EXPECT_EQ(refusal(fits, 1), "accepted");  // 10 km: the far limit itself
}

TEST(DepthImage, ZeroDepthBecomesNaNAndFloatDepthIsMetres) {
  cv::Mat depth(2, 2, CV_32FC1, cv::Scalar(1.5f));
  depth.at<float>(0, 1) = 0.f;
  depth.at<float>(1, 0) = std::numeric_limits<float>::quiet_NaN();
  const auto cloud = depthToCloud(depth, PinholeIntrinsics{100, 100, 0, 0}, 5000);
  EXPECT_FLOAT_EQ(cloud.at(0, 0).z, 1.5f);
  EXPECT_TRUE(std::isnan(cloud.at(1, 0).z));
  EXPECT_TRUE(std::isnan(cloud.at(0, 1).z));
  EXPECT_FLOAT_EQ(cloud.at(1, 1).x, 1.5f / 100);
}

TEST(DepthImage, ImageOneRowOrOneColumnHighBackProjects) {
  // Found by fuzzing: PCL's 2-D accessor throws for a cloud one row high.
  for (const cv::Size size : {cv::Size(5, 1), cv::Size(1, 5), cv::Size(1, 1)}) {
    cv::Mat depth(size, CV_16UC1, cv::Scalar(3000));
    const auto cloud = depthToCloud(depth, PinholeIntrinsics{100, 100, 0, 0}, 1000);
    ASSERT_EQ(cloud.size(), static_cast<std::size_t>(size.area()));
    EXPECT_EQ(cloud.width, static_cast<std::uint32_t>(size.width));
    EXPECT_EQ(cloud.height, static_cast<std::uint32_t>(size.height));
    for (const auto& p : cloud) EXPECT_FLOAT_EQ(p.z, 3.0f);
    EXPECT_FLOAT_EQ(cloud.back().x, 3.0f * (size.width - 1) / 100);
  }
}

TEST(DepthImage, WrongTypesAndIntrinsicsAreClearErrors) {
  const PinholeIntrinsics good = PinholeIntrinsics::tumFreiburg1();
  EXPECT_THROW(depthToCloud(cv::Mat(), good, 5000), std::invalid_argument);
  EXPECT_THROW(depthToCloud(cv::Mat(4, 4, CV_8UC3), good, 5000), std::invalid_argument);
  EXPECT_THROW(depthToCloud(cv::Mat(4, 4, CV_16UC1), good, 0), std::invalid_argument);
  EXPECT_THROW(depthToCloud(cv::Mat(4, 4, CV_16UC1), PinholeIntrinsics{0, 500, 1, 1}, 5000),
               std::invalid_argument);
  EXPECT_THROW(depthToColoredCloud(cv::Mat(4, 4, CV_16UC1), cv::Mat(3, 4, CV_8UC3), good, 5000),
               std::invalid_argument);
}

TEST(DepthImage, RenderedDemoRoomFindsTheTableFloorAndStepsAndNoSlopedThing) {
  const auto scene = synthetic::demoRoom();
  const auto camera = synthetic::demoCamera();
  const auto frame = scene.render(camera);
  const auto cloud = depthToCloud(frame.depth, camera.intrinsics, 1.0);
  const Eigen::Quaterniond q(camera.pose.linear());
  const V3 t = camera.pose.translation();
  Extractor extractor;
  const Result result = extractor.extract(
      cloud, Orientation::fromPose(t.x(), t.y(), t.z(), q.x(), q.y(), q.z(), q.w()));
  for (double height : {0.0, 0.75, 0.45, 0.17, 0.34, 0.80}) {
    EXPECT_GE(planeNear(result, height, 0.01), 0)
        << "no plane at " << height << " m: " << describe(result);
  }
  // Every plane found is one of the true ones: the ramp, ball, cone and tube gave nothing.
  for (const HorizontalPlane& p : result.planes) {
    bool known = false;
    for (double height : {0.0, 0.75, 0.45, 0.17, 0.34, 0.80})
      known = known || std::fabs(p.height - height) < 0.01;
    EXPECT_TRUE(known) << "unexpected plane at " << p.height << " m: " << describe(result);
  }
}

}  // namespace test
}  // namespace hope
