// Reading a PointCloud2 in place: every size in the header comes from outside and is checked
// without overflow, so a hostile message is refused with a reason instead of read out of bounds.
#include <cstring>
#include <limits>
#include <string>

#include <gtest/gtest.h>

#include "hope/plane_colors.h"
#include "hope_ros/cloud_conversion.h"

namespace hope {
namespace test {

namespace {

// A valid 2-point unorganized cloud with PCL's 16-byte layout (x y z and padding).
sensor_msgs::PointCloud2 twoPoints() {
  pcl::PointCloud<pcl::PointXYZ> cloud;
  cloud.push_back(pcl::PointXYZ(1, 2, 3));
  cloud.push_back(pcl::PointXYZ(4, 5, 6));
  return hope_ros::cloudMessage(cloud, std_msgs::Header());
}

std::string problemOf(const sensor_msgs::PointCloud2& msg) {
  hope::PointsView view;
  return hope_ros::viewOf(msg, view);
}

bool mentions(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

}  // namespace

TEST(CloudConversion, ValidCloudIsReadInPlace) {
  const sensor_msgs::PointCloud2 msg = twoPoints();
  hope::PointsView view;
  ASSERT_EQ(hope_ros::viewOf(msg, view), "");
  ASSERT_EQ(view.count, 2u);
  EXPECT_EQ(view.data, msg.data.data());
  EXPECT_FLOAT_EQ(view.x(1), 4);
  EXPECT_FLOAT_EQ(view.z(0), 3);
}

TEST(CloudConversion, FieldOffsetThatWouldWrapIn32BitsIsRefused) {
  sensor_msgs::PointCloud2 msg = twoPoints();
  // offset + 4 wraps to 1 in 32-bit arithmetic, which is below point_step 16.
  msg.fields[2].offset = std::numeric_limits<std::uint32_t>::max() - 2;
  const std::string problem = problemOf(msg);
  EXPECT_TRUE(mentions(problem, "field 'z'")) << problem;
  EXPECT_TRUE(mentions(problem, "outside point_step")) << problem;
}

TEST(CloudConversion, RowStepThatWouldWrapIn32BitsIsRefused) {
  sensor_msgs::PointCloud2 msg = twoPoints();
  // width · point_step = 2^28 · 16 = 2^32 wraps to 0 in 32 bits: row_step 0 matched it.
  msg.width = 1u << 28;
  msg.row_step = 0;
  const std::string problem = problemOf(msg);
  EXPECT_TRUE(mentions(problem, "row_step")) << problem;
  // 2^30 x 2^30 points of 16 bytes: 2^64 bytes, 0 in 64-bit arithmetic, and the row check
  // 2^34 wraps to 0 in 32 bits. Both checks passed before; the read went gigabytes astray.
  msg.width = msg.height = 1u << 30;
  EXPECT_TRUE(mentions(problemOf(msg), "row_step"));
}

TEST(CloudConversion, HeaderClaimingMoreDataThanTheBufferIsRefused) {
  sensor_msgs::PointCloud2 msg = twoPoints();
  // 65535 · 65537 = 2^32 - 1 points: their byte count overflows 32 bits many times over.
  msg.width = 65535;
  msg.height = 65537;
  msg.row_step = msg.width * msg.point_step;
  const std::string problem = problemOf(msg);
  EXPECT_TRUE(mentions(problem, "the data holds 32 bytes")) << problem;
  // Largest header of all: every dimension at its maximum.
  msg.width = msg.height = std::numeric_limits<std::uint32_t>::max();
  msg.point_step = std::numeric_limits<std::uint32_t>::max();
  msg.row_step = std::numeric_limits<std::uint32_t>::max();
  EXPECT_FALSE(problemOf(msg).empty());
}

TEST(CloudConversion, ZeroPointStepAndMissingOrWrongFieldsAreRefused) {
  sensor_msgs::PointCloud2 msg = twoPoints();
  msg.point_step = 0;
  msg.row_step = 0;
  EXPECT_TRUE(mentions(problemOf(msg), "outside point_step"));
  msg = twoPoints();
  msg.fields.pop_back();
  EXPECT_TRUE(mentions(problemOf(msg), "no 'z' field"));
  msg = twoPoints();
  msg.fields[0].datatype = sensor_msgs::PointField::FLOAT64;
  EXPECT_TRUE(mentions(problemOf(msg), "not a single float32"));
  msg = twoPoints();
  msg.fields[1].count = 0;
  EXPECT_TRUE(mentions(problemOf(msg), "not a single float32"));
  msg = twoPoints();
  msg.is_bigendian = true;
  EXPECT_TRUE(mentions(problemOf(msg), "big-endian"));
  msg = twoPoints();
  msg.data.resize(31);
  EXPECT_TRUE(mentions(problemOf(msg), "the data holds 31 bytes"));
}

TEST(CloudConversion, EmptyCloudIsValid) {
  sensor_msgs::PointCloud2 msg = twoPoints();
  msg.width = 0;
  msg.row_step = 0;
  msg.data.clear();
  hope::PointsView view;
  EXPECT_EQ(hope_ros::viewOf(msg, view), "");
  EXPECT_EQ(view.count, 0u);
}

// The labeled cloud: the points in the reference frame (aligned + local origin), the colour of
// each point's plane id (grey for none) and its label (id + 1, 0 for none), in input order.
TEST(CloudConversion, LabeledCloudCarriesEachPointsPlaneColourAndLabel) {
  const std::vector<Eigen::Vector3f> aligned = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0.5f}};
  hope::Result result;
  result.local_origin = Eigen::Vector3d(1024, -512, 3);
  result.planes.resize(2);
  result.planes[0].id = 7;  // ids as the tracker gives them, not the plane's index
  result.planes[1].id = 2;
  result.point_labels = {0, -1, 1, 0};
  hope::PointsView view;
  view.count = aligned.size();
  view.width = 4;
  const sensor_msgs::PointCloud2 msg =
      hope_ros::labeledCloud(aligned, result, view, std_msgs::Header());
  ASSERT_EQ(msg.point_step, 20u);
  ASSERT_EQ(msg.data.size(), 4u * 20u);
  auto read = [&](std::size_t i, std::size_t offset) {
    std::uint32_t v;
    std::memcpy(&v, msg.data.data() + i * 20 + offset, 4);
    return v;
  };
  auto rgbOf = [](int id) {
    const hope::Rgb c = hope::planeColor(id);
    return (std::uint32_t(c.r) << 16) | (std::uint32_t(c.g) << 8) | c.b;
  };
  const std::uint32_t expected_rgb[4] = {rgbOf(7), (128u << 16) | (128u << 8) | 128u, rgbOf(2),
                                         rgbOf(7)};
  const std::uint32_t expected_label[4] = {8, 0, 3, 8};
  for (std::size_t i = 0; i < 4; ++i) {
    float xyz[3];
    std::memcpy(xyz, msg.data.data() + i * 20, 12);
    EXPECT_EQ(xyz[0], aligned[i].x() + 1024.f) << "point " << i;
    EXPECT_EQ(xyz[1], aligned[i].y() - 512.f) << "point " << i;
    EXPECT_EQ(xyz[2], aligned[i].z() + 3.f) << "point " << i;
    EXPECT_EQ(read(i, 12), expected_rgb[i]) << "point " << i;
    EXPECT_EQ(read(i, 16), expected_label[i]) << "point " << i;
  }
  EXPECT_NE(rgbOf(7), rgbOf(2));  // the colours tell the planes apart

  // Labels for fewer points than the cloud has (none computed for the rest): those points are
  // on no plane, grey and label 0, and still carry their coordinates.
  result.point_labels = {1, 0};
  const sensor_msgs::PointCloud2 partly =
      hope_ros::labeledCloud(aligned, result, view, std_msgs::Header());
  ASSERT_EQ(partly.data.size(), 4u * 20u);
  const std::uint32_t partly_label[4] = {3, 8, 0, 0};
  for (std::size_t i = 0; i < 4; ++i) {
    float xyz[3];
    std::uint32_t label;
    std::memcpy(xyz, partly.data.data() + i * 20, 12);
    std::memcpy(&label, partly.data.data() + i * 20 + 16, 4);
    EXPECT_EQ(xyz[0], aligned[i].x() + 1024.f) << "point " << i;
    EXPECT_EQ(xyz[2], aligned[i].z() + 3.f) << "point " << i;
    EXPECT_EQ(label, partly_label[i]) << "point " << i;
  }
}

// The nodelet refills the message it published last: whatever that message held (another
// frame's points, another size, stale fields), the result is the fresh message, byte for byte.
TEST(CloudConversion, RefilledLabeledCloudEqualsAFreshOne) {
  const std::vector<Eigen::Vector3f> aligned = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0.5f}};
  hope::Result result;
  result.planes.resize(1);
  result.planes[0].id = 3;
  result.point_labels = {0, -1, 0, -1};
  hope::PointsView view;
  view.count = aligned.size();
  view.width = 2;
  view.height = 2;
  std_msgs::Header header;
  header.frame_id = "hope_gravity";
  header.stamp = ros::Time(12, 34);
  const sensor_msgs::PointCloud2 fresh = hope_ros::labeledCloud(aligned, result, view, header);
  for (const std::size_t stale_bytes : {std::size_t{80}, std::size_t{400}, std::size_t{0}}) {
    sensor_msgs::PointCloud2 reused;
    reused.data.assign(stale_bytes, 0xAB);  // the same size as the new cloud's (80) or not
    reused.fields.resize(7);
    reused.width = 99;
    reused.header.frame_id = "stale";
    hope_ros::fillLabeledCloud(aligned, result, view, header, reused);
    EXPECT_EQ(reused.data, fresh.data) << stale_bytes << " stale bytes";
    EXPECT_EQ(reused.fields.size(), 5u);
    EXPECT_EQ(reused.width, 2u);
    EXPECT_EQ(reused.height, 2u);
    EXPECT_EQ(reused.row_step, fresh.row_step);
    EXPECT_EQ(reused.header.frame_id, "hope_gravity");
    EXPECT_EQ(reused.header.stamp, header.stamp);
  }
}

}  // namespace test
}  // namespace hope
