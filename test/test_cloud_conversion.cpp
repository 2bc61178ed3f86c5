// Reading a PointCloud2 in place: every size in the header comes from outside and is checked
// without overflow, so a hostile message is refused with a reason instead of read out of bounds.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <set>
#include <string>

#include <gtest/gtest.h>
#include <pcl_conversions/pcl_conversions.h>

#include "hope/extractor.h"
#include "hope/plane_colors.h"
#include "hope_ros/cloud_conversion.h"
#include "hope_ros/frame_gaps.h"

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
// each point's plane id (grey for none), its label (id + 1, 0 for none) and its object (object
// index + 1, 0 for none), in input order.
TEST(CloudConversion, LabeledCloudCarriesEachPointsPlaneColourLabelAndObject) {
  const std::vector<Eigen::Vector3f> aligned = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0.5f}};
  hope::Result result;
  result.local_origin = Eigen::Vector3d(1024, -512, 3);
  result.planes.resize(2);
  result.planes[0].id = 7;  // ids as the tracker gives them, not the plane's index
  result.planes[1].id = 2;
  result.point_labels = {0, -1, 1, 0};
  result.point_objects = {-1, 1, -1, 0};  // point 3 above plane 0 is object 0, point 1 object 1
  hope::PointsView view;
  view.count = aligned.size();
  view.width = 4;
  const sensor_msgs::PointCloud2 msg =
      hope_ros::labeledCloud(aligned, result, view, std_msgs::Header());
  ASSERT_EQ(msg.point_step, 24u);
  ASSERT_EQ(msg.data.size(), 4u * 24u);
  ASSERT_EQ(msg.fields.size(), 6u);
  EXPECT_EQ(msg.fields[5].name, "object");
  EXPECT_EQ(msg.fields[5].offset, 20u);
  auto read = [&](std::size_t i, std::size_t offset) {
    std::uint32_t v;
    std::memcpy(&v, msg.data.data() + i * 24 + offset, 4);
    return v;
  };
  auto rgbOf = [](int id) {
    const hope::Rgb c = hope::planeColor(id);
    return (std::uint32_t(c.r) << 16) | (std::uint32_t(c.g) << 8) | c.b;
  };
  const std::uint32_t expected_rgb[4] = {rgbOf(7), (128u << 16) | (128u << 8) | 128u, rgbOf(2),
                                         rgbOf(7)};
  const std::uint32_t expected_label[4] = {8, 0, 3, 8};
  const std::uint32_t expected_object[4] = {0, 2, 0, 1};
  for (std::size_t i = 0; i < 4; ++i) {
    float xyz[3];
    std::memcpy(xyz, msg.data.data() + i * 24, 12);
    EXPECT_EQ(xyz[0], aligned[i].x() + 1024.f) << "point " << i;
    EXPECT_EQ(xyz[1], aligned[i].y() - 512.f) << "point " << i;
    EXPECT_EQ(xyz[2], aligned[i].z() + 3.f) << "point " << i;
    EXPECT_EQ(read(i, 12), expected_rgb[i]) << "point " << i;
    EXPECT_EQ(read(i, 16), expected_label[i]) << "point " << i;
    EXPECT_EQ(read(i, 20), expected_object[i]) << "point " << i;
  }
  EXPECT_NE(rgbOf(7), rgbOf(2));  // the colours tell the planes apart

  // Labels for fewer points than the cloud has (none computed for the rest): those points are
  // on no plane, grey and label 0, and still carry their coordinates.
  // Without objects (not asked for) every point's object is 0.
  result.point_labels = {1, 0};
  result.point_objects.clear();
  const sensor_msgs::PointCloud2 partly =
      hope_ros::labeledCloud(aligned, result, view, std_msgs::Header());
  ASSERT_EQ(partly.data.size(), 4u * 24u);
  const std::uint32_t partly_label[4] = {3, 8, 0, 0};
  for (std::size_t i = 0; i < 4; ++i) {
    float xyz[3];
    std::uint32_t label, object;
    std::memcpy(xyz, partly.data.data() + i * 24, 12);
    std::memcpy(&label, partly.data.data() + i * 24 + 16, 4);
    std::memcpy(&object, partly.data.data() + i * 24 + 20, 4);
    EXPECT_EQ(object, 0u) << "point " << i;
    EXPECT_EQ(xyz[0], aligned[i].x() + 1024.f) << "point " << i;
    EXPECT_EQ(xyz[2], aligned[i].z() + 3.f) << "point " << i;
    EXPECT_EQ(label, partly_label[i]) << "point " << i;
  }
}

// The nodelet refills the message it published last: whatever that message held (another
// frame's points, another size, stale fields), the result is the fresh message, byte for byte.
// shape_msgs/Plane in the message: a x + b y + c z + d = 0 holds on the plane's points, and
// (a, b, c) is the true tilted normal of a table top 0.75 m up, turned 2° about x.
TEST(CloudConversion, APlaneMessageCarriesItsStandardCoefficients) {
  const double tilt = 2.0 * M_PI / 180.0;
  pcl::PointCloud<pcl::PointXYZ> cloud;
  for (double x = -0.5; x <= 0.5; x += 0.01) {
    for (double y = -0.4; y <= 0.4; y += 0.01) {
      cloud.push_back(pcl::PointXYZ(static_cast<float>(x), static_cast<float>(y),
                                    static_cast<float>(0.75 + y * std::tan(tilt))));
    }
  }
  hope::Extractor extractor;
  const hope::Result result = extractor.extract(
      cloud, hope::Orientation::identity().withViewpoint(Eigen::Vector3d(0, 0, 2)));
  const hope::PlaneArray msg = hope_ros::toMessage(result, std_msgs::Header());
  ASSERT_EQ(msg.planes.size(), 1u);
  const auto& c = msg.planes[0].coef.coef;
  EXPECT_NEAR(c[0], 0.0, 1e-3);
  EXPECT_NEAR(c[1], -std::sin(tilt), 1e-3);
  EXPECT_NEAR(c[2], std::cos(tilt), 1e-3);
  EXPECT_NEAR(c[3], -0.75 * std::cos(tilt), 1e-3);
  double worst = 0;
  for (const pcl::PointXYZ& q : cloud) {
    worst = std::max(worst, std::abs(c[0] * q.x + c[1] * q.y + c[2] * q.z + c[3]));
  }
  EXPECT_LT(worst, 1e-4) << "the coefficients hold on every point of the plane";
}

// ~obstacles' cloud: the chosen points in the input's own frame, x y z and the input's rgb.
TEST(CloudConversion, SelectedPointsKeepTheirCoordinatesColourAndOrder) {
  pcl::PointCloud<pcl::PointXYZRGB> cloud(2, 2);
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    cloud[i].x = static_cast<float>(i);
    cloud[i].y = 10.0f + static_cast<float>(i);
    cloud[i].z = 20.0f + static_cast<float>(i);
    cloud[i].r = static_cast<std::uint8_t>(50 * i);
  }
  sensor_msgs::PointCloud2 input;
  pcl::toROSMsg(cloud, input);
  input.header.frame_id = "camera";
  const sensor_msgs::PointCloud2 out = hope_ros::selectedPoints(input, {3, 1});
  EXPECT_EQ(out.header.frame_id, "camera");
  ASSERT_EQ(out.width, 2u);
  ASSERT_EQ(out.height, 1u);
  ASSERT_EQ(out.fields.size(), 4u);
  EXPECT_EQ(out.fields[3].name, "rgb");
  EXPECT_EQ(out.point_step, 16u);
  pcl::PointCloud<pcl::PointXYZRGB> back;
  pcl::fromROSMsg(out, back);
  ASSERT_EQ(back.size(), 2u);
  EXPECT_EQ(back[0].x, 3.0f);
  EXPECT_EQ(back[0].z, 23.0f);
  EXPECT_EQ(back[0].r, 150);
  EXPECT_EQ(back[1].y, 11.0f);
  EXPECT_EQ(back[1].r, 50);
  // Without colour: x y z only.
  const sensor_msgs::PointCloud2 plain = hope_ros::selectedPoints(twoPoints(), {1});
  ASSERT_EQ(plain.fields.size(), 3u);
  EXPECT_EQ(plain.point_step, 12u);
  float z;
  std::memcpy(&z, plain.data.data() + 8, 4);
  EXPECT_EQ(z, 6.0f);
}

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
    EXPECT_EQ(reused.fields.size(), 6u);
    EXPECT_EQ(reused.width, 2u);
    EXPECT_EQ(reused.height, 2u);
    EXPECT_EQ(reused.row_step, fresh.row_step);
    EXPECT_EQ(reused.header.frame_id, "hope_gravity");
    EXPECT_EQ(reused.header.stamp, header.stamp);
  }
}

}  // namespace test
}  // namespace hope

// 150 frames at 30 Hz with seq 0 in every header (as tum_to_bag.py and many drivers write),
// played so that 8 of them never arrive: 8 dropped, though seq says nothing. The stamps carry
// a camera's jitter (up to a fifth of a period either way).
TEST(FrameGaps, DropsAreCountedFromTheStampsWhenSeqDoesNotAdvance) {
  const double period = 1.0 / 30;
  const std::set<int> lost = {5, 40, 41, 77, 100, 101, 102, 149};
  std::mt19937 random(7);
  std::uniform_real_distribution<double> jitter(-0.2 * period, 0.2 * period);
  hope_ros::FrameGapCounter gaps;
  for (int f = 0; f < 150; ++f) {
    if (!lost.count(f)) gaps.arrive(0, 1305031459.0 + f * period + jitter(random));
  }
  // The last frame lost is the last one: nothing after it shows the gap.
  EXPECT_EQ(gaps.dropped(), lost.size() - 1);
}

// The same stream without losses: a jittery camera drops nothing.
TEST(FrameGaps, AJitteryStreamWithoutLossesDropsNothing) {
  const double period = 1.0 / 30;
  std::mt19937 random(11);
  std::uniform_real_distribution<double> jitter(-0.2 * period, 0.2 * period);
  hope_ros::FrameGapCounter gaps;
  for (int f = 0; f < 300; ++f) gaps.arrive(0, 100.0 + f * period + jitter(random));
  EXPECT_EQ(gaps.dropped(), 0u);
}

// A publisher that numbers its messages: the gaps in seq, whatever the stamps say (here the
// stamps are all equal, as from a node that stamps with a fixed time).
TEST(FrameGaps, SeqGapsAreCountedWhenSeqAdvances) {
  hope_ros::FrameGapCounter gaps;
  for (std::uint32_t seq : {10u, 11u, 12u, 15u, 16u, 20u}) gaps.arrive(seq, 5.0);
  EXPECT_EQ(gaps.dropped(), 2u + 3u);
}

// After restart() (unsubscribed for a while, or a bag that started over) the first frame
// counts nothing, however far its stamp or seq lies from the last one before.
TEST(FrameGaps, NothingIsCountedAcrossARestart) {
  hope_ros::FrameGapCounter gaps;
  for (int f = 0; f < 10; ++f) gaps.arrive(0, f * 0.1);
  gaps.restart();
  EXPECT_EQ(gaps.arrive(0, 100.0), 0u);
  for (int f = 1; f < 10; ++f) gaps.arrive(0, 100.0 + f * 0.1);
  EXPECT_EQ(gaps.dropped(), 0u);
}

// A cloud delivered twice (the frame and stamp of the last one accepted) is one frame: the repeat
// is counted and skipped; the next stamp, or another sensor's frame at the same stamp, is new.
TEST(RepeatedClouds, TheSameFrameAndStampAgainIsARepeat) {
  hope_ros::RepeatedClouds repeated;
  EXPECT_FALSE(repeated.repeat("camera_depth_optical_frame", 1300000000.033333));
  EXPECT_TRUE(repeated.repeat("camera_depth_optical_frame", 1300000000.033333));
  EXPECT_FALSE(repeated.repeat("camera_depth_optical_frame", 1300000000.066667));
  EXPECT_TRUE(repeated.repeat("camera_depth_optical_frame", 1300000000.066667));
  EXPECT_FALSE(repeated.repeat("second_camera", 1300000000.066667)) << "another sensor's frame";
  EXPECT_FALSE(repeated.repeat("camera_depth_optical_frame", 1300000000.066667))
      << "not the last one accepted";
  EXPECT_EQ(repeated.count(), 2u);
}

namespace {

hope::HorizontalPlane planeAt(int id, double x, double y, double height, double half_size) {
  hope::HorizontalPlane p;
  p.id = id;
  p.height = height;
  p.centroid = Eigen::Vector3d(x, y, height);
  p.bbox = {{x - half_size, y - half_size, x + half_size, y + half_size}};
  p.area = 4 * half_size * half_size;
  for (const double dx : {-half_size, half_size}) {
    for (const double dy : {-half_size, half_size}) {
      p.hull.emplace_back(x + dx, y + (dx < 0 ? dy : -dy), height);
    }
  }
  return p;
}

}  // namespace

// Crowded planes (book and box tops on a table, a few centimetres apart in height and a
// decimetre apart in x and y) get labels that no view can show on top of each other: any two
// labels whose texts could overlap horizontally are at least a text height apart vertically.
// Every label stands clear of its own plane's fill (its text's lower edge above the plane).
TEST(PlaneMarkers, LabelsOfCrowdedPlanesDoNotOverlapAndStandAboveTheirPlanes) {
  std::vector<hope::HorizontalPlane> planes = {
      planeAt(0, 0.0, 0.0, 0.75, 0.8),    // the table
      planeAt(1, 0.1, 0.05, 0.80, 0.1),   // a book on it
      planeAt(2, -0.1, 0.1, 0.85, 0.08),  // a box
      planeAt(3, 0.05, -0.1, 0.82, 0.06),
      planeAt(4, 3.0, 3.0, 0.75, 0.5),  // far away: no reason to move
      planeAt(5, 0.0, 0.0, 0.0, 2.0),   // the floor, below the table
  };
  const std::vector<Eigen::Vector3d> at = hope_ros::labelPositions(planes);
  ASSERT_EQ(at.size(), planes.size());
  for (std::size_t k = 0; k < planes.size(); ++k) {
    EXPECT_GE(at[k].z() - 0.5 * hope_ros::kLabelHeight, planes[k].height + 0.02) << "label " << k;
    for (std::size_t q = 0; q < k; ++q) {
      const double width = hope_ros::kLabelCharWidth * 9;  // "1: 0.80 m"
      const bool near = (at[k].head<2>() - at[q].head<2>()).norm() < width;
      if (near) {
        EXPECT_GE(std::fabs(at[k].z() - at[q].z()), hope_ros::kLabelHeight)
            << "labels " << q << " and " << k;
      }
    }
  }
  // The far plane's label sits right above it.
  EXPECT_NEAR(at[4].x(), 3.0, 1e-12);
  EXPECT_LT(at[4].z(), 0.75 + hope_ros::kLabelHeight);
  // The floor's centroid lies under the table: its label goes to a part of the floor that no
  // higher plane covers, still on the floor (inside its box).
  EXPECT_FALSE(std::fabs(at[5].x()) <= 0.8 && std::fabs(at[5].y()) <= 0.8)
      << "the floor's label is under the table: " << at[5].transpose();
  EXPECT_LE(std::fabs(at[5].x()), 2.0);
  EXPECT_LE(std::fabs(at[5].y()), 2.0);
  // Crowding raised some labels: four labels within a decimetre were the point of this test.
  int raised = 0;
  for (std::size_t k = 0; k < 4; ++k)
    raised += at[k].z() > planes[k].height + hope_ros::kLabelHeight;
  EXPECT_GE(raised, 2);
}

// The view RViz orbits: the middle of the planes' boxes in x and y, halfway between the lowest
// and the highest plane; none without planes.
TEST(PlaneMarkers, SceneCentreIsTheMiddleOfWhatThePlanesCover) {
  EXPECT_FALSE(hope_ros::sceneCentre({}).has_value());
  const auto centre =
      hope_ros::sceneCentre({planeAt(0, 0.0, 0.0, 0.0, 2.0), planeAt(1, 5.0, 1.0, 0.8, 0.5)});
  ASSERT_TRUE(centre.has_value());
  EXPECT_NEAR(centre->x(), (-2.0 + 5.5) / 2, 1e-12);
  EXPECT_NEAR(centre->y(), (-2.0 + 2.0) / 2, 1e-12);
  EXPECT_NEAR(centre->z(), 0.4, 1e-12);
}
