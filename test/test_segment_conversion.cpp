// ~segment's answer and object_points as messages (no ROS master needed): on a room whose parts
// are known point by point (a floor, a table, a box on each), the planes and objects with their
// points, the height band, the box, and refusals that name what is wrong.
#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <vector>

#include <gtest/gtest.h>
#include <pcl/point_types.h>
#include <sensor_msgs/point_cloud2_iterator.h>
#include <Eigen/Geometry>

#include "hope/frame_pipeline.h"
#include "hope_ros/object_conversion.h"

namespace {

enum Part { kFloor = 1, kTable, kBook, kCup };

struct Room {
  pcl::PointCloud<pcl::PointXYZ> cloud;
  std::vector<int> part;  // per point
  void add(double x, double y, double z, int p) {
    cloud.push_back(
        pcl::PointXYZ(static_cast<float>(x), static_cast<float>(y), static_cast<float>(z)));
    part.push_back(p);
  }
  // A box's top and four sides, standing on `base` over [x0, x1] × [y0, y1], sampled every
  // 5 mm (a Kinect's spacing at about 2.5 m).
  void box(double x0, double x1, double y0, double y1, double base, double height, int p) {
    const double step = 0.005;
    for (double x = x0; x <= x1 + 1e-9; x += step) {
      for (double y = y0; y <= y1 + 1e-9; y += step) add(x, y, base + height, p);
    }
    for (double z = base + step; z < base + height; z += step) {
      for (double x = x0; x <= x1 + 1e-9; x += step) {
        add(x, y0, z, p);
        add(x, y1, z, p);
      }
      for (double y = y0; y <= y1 + 1e-9; y += step) {
        add(x0, y, z, p);
        add(x1, y, z, p);
      }
    }
  }
};

// The table top (x 0.2-1.0, y -0.3-0.3, at 0.75 m) over a 3 x 3 m floor with a hole under it
// (the top hides it from a camera above), and on the table a 0.2 x 0.1 x 0.15 book and a
// 0.06 x 0.06 x 0.1 cup (their tops too small to be planes).
constexpr double kTableZ = 0.75;
Room room() {
  Room r;
  for (double x = -1.5; x <= 1.5; x += 0.01) {
    for (double y = -1.5; y <= 1.5; y += 0.01) {
      if (x > 0.15 && x < 1.05 && y > -0.35 && y < 0.35) continue;
      r.add(x, y, 0.0, kFloor);
    }
  }
  for (double x = 0.2; x <= 1.0 + 1e-9; x += 0.01) {
    for (double y = -0.3; y <= 0.3 + 1e-9; y += 0.01) {
      if (x > 0.495 && x < 0.705 && y > -0.055 && y < 0.055) continue;  // under the book
      if (x > 0.245 && x < 0.315 && y > 0.145 && y < 0.215) continue;   // under the cup
      r.add(x, y, kTableZ, kTable);
    }
  }
  r.box(0.5, 0.7, -0.05, 0.05, kTableZ, 0.15, kBook);
  r.box(0.25, 0.31, 0.15, 0.21, kTableZ, 0.1, kCup);
  return r;
}

class SegmentAnswer : public ::testing::Test {
 protected:
  void SetUp() override {
    scene_ = room();
    hope::FrameOutputs outputs;
    outputs.keep_points = true;
    hope::FramePipeline pipeline;
    frame_ = pipeline.processAlone(
        hope::PointsView::of(scene_.cloud),
        hope::Orientation::identity().withViewpoint(Eigen::Vector3d(0, 0, 1.6)), outputs);
    ASSERT_TRUE(frame_.processed) << frame_.skipped;
    header_.frame_id = "odom";
    header_.stamp = ros::Time(12.5);
  }

  // The points of a cloud as the parts of the scene they were made as: each point is looked up
  // by its coordinates among the scene's.
  std::vector<int> partsOf(const sensor_msgs::PointCloud2& cloud) const {
    if (part_at_.empty()) {
      for (std::size_t i = 0; i < scene_.cloud.size(); ++i) {
        const pcl::PointXYZ& p = scene_.cloud[i];
        part_at_[{p.x, p.y, p.z}] = scene_.part[i];
      }
    }
    std::vector<int> parts;
    sensor_msgs::PointCloud2ConstIterator<float> x(cloud, "x"), y(cloud, "y"), z(cloud, "z");
    for (; x != x.end(); ++x, ++y, ++z) {
      const auto found = part_at_.find({*x, *y, *z});
      parts.push_back(found == part_at_.end() ? 0 : found->second);
    }
    return parts;
  }

  static double share(const std::vector<int>& parts, int part) {
    std::size_t n = 0;
    for (int p : parts) n += p == part;
    return parts.empty() ? 0.0 : static_cast<double>(n) / static_cast<double>(parts.size());
  }

  std::size_t count(int part) const {
    std::size_t n = 0;
    for (int p : scene_.part) n += p == part;
    return n;
  }

  Room scene_;
  mutable std::map<std::array<float, 3>, int> part_at_;  // a point's part, by its coordinates
  hope::Frame frame_;
  std_msgs::Header header_;
};

TEST_F(SegmentAnswer, EveryPlaneAndObjectComesWithItsOwnPoints) {
  const hope::Segment::Response r =
      hope_ros::segmentAnswer(hope::Segment::Request(), frame_, header_);
  ASSERT_TRUE(r.success) << r.message;
  EXPECT_EQ(r.header.frame_id, "odom");
  EXPECT_EQ(r.header.stamp, ros::Time(12.5));
  ASSERT_EQ(r.planes.size(), 2u);
  ASSERT_EQ(r.plane_points.size(), 2u);
  for (std::size_t i = 0; i < r.planes.size(); ++i) {
    const int truth = std::abs(r.planes[i].height - kTableZ) < 0.02 ? kTable : kFloor;
    const std::vector<int> parts = partsOf(r.plane_points[i]);
    EXPECT_EQ(r.plane_points[i].width, r.planes[i].num_points);
    EXPECT_EQ(r.plane_points[i].header.frame_id, "odom");
    // The table's points include the lowest rows of what stands on it (within its noise band
    // of r_z / 2): 7 % of them here.
    EXPECT_GE(share(parts, truth), truth == kTable ? 0.9 : 0.99)
        << "plane at " << r.planes[i].height;
    EXPECT_GE(static_cast<double>(parts.size()), 0.95 * static_cast<double>(count(truth)))
        << "plane at " << r.planes[i].height;
  }
  // The objects are the frame's (how the objects stage cuts them is its own tests' matter:
  // test_standing_objects), each answered with exactly its own points, all of one thing.
  ASSERT_EQ(r.objects.size(), frame_.result.objects.size());
  std::size_t on_things = 0, cups = 0;
  for (const hope::Object& o : r.objects) {
    const std::vector<int> parts = partsOf(o.points);
    EXPECT_EQ(o.points.width, o.num_points);
    const double book = share(parts, kBook), cup = share(parts, kCup);
    EXPECT_GE(std::max(book, cup), 0.99) << "object " << o.index;
    on_things += static_cast<std::size_t>(std::round((book + cup) * parts.size()));
    cups += cup > 0.5;
    // Its box holds its points (a box is what a grasp or a collision check takes).
    const Eigen::Vector3d centre(o.pose.position.x, o.pose.position.y, o.pose.position.z);
    const Eigen::Quaterniond q(o.pose.orientation.w, o.pose.orientation.x, o.pose.orientation.y,
                               o.pose.orientation.z);
    const Eigen::Vector3d half =
        0.5 * Eigen::Vector3d(o.box.dimensions[0], o.box.dimensions[1], o.box.dimensions[2]);
    std::size_t inside = 0;
    sensor_msgs::PointCloud2ConstIterator<float> x(o.points, "x"), y(o.points, "y"),
        z(o.points, "z");
    for (; x != x.end(); ++x, ++y, ++z) {
      const Eigen::Vector3d local = q.inverse() * (Eigen::Vector3d(*x, *y, *z) - centre);
      inside += (local.cwiseAbs() - half).maxCoeff() <= 1e-4;
    }
    EXPECT_GE(static_cast<double>(inside), 0.99 * o.num_points) << "object " << o.index;
  }
  EXPECT_EQ(cups, 1u) << "the cup is one object";
  EXPECT_GE(static_cast<double>(on_things), 0.9 * static_cast<double>(count(kBook) + count(kCup)));
}

TEST_F(SegmentAnswer, AHeightBandKeepsTheTableAndWhatStandsOnIt) {
  hope::Segment::Request request;
  request.limit_height = true;
  request.min_height = 0.7;
  request.max_height = 0.8;
  const hope::Segment::Response r = hope_ros::segmentAnswer(request, frame_, header_);
  ASSERT_TRUE(r.success) << r.message;
  ASSERT_EQ(r.planes.size(), 1u);
  EXPECT_NEAR(r.planes[0].height, kTableZ, 0.005);
  EXPECT_EQ(r.objects.size(), frame_.result.objects.size()) << "all of them stand on the table";
  for (const hope::Object& o : r.objects) EXPECT_EQ(o.plane_id, r.planes[0].id);
}

TEST_F(SegmentAnswer, ABoxKeepsThePlanesItMeetsAndTheObjectsInIt) {
  auto inBox = [&](double x0, double y0, double z0, double x1, double y1, double z1) {
    hope::Segment::Request request;
    request.limit_box = true;
    request.box_min.x = x0;
    request.box_min.y = y0;
    request.box_min.z = z0;
    request.box_max.x = x1;
    request.box_max.y = y1;
    request.box_max.z = z1;
    return hope_ros::segmentAnswer(request, frame_, header_);
  };
  // Around the book, from the table's height up: the table and the book, not the floor.
  hope::Segment::Response r = inBox(0.45, -0.1, 0.7, 0.75, 0.1, 1.0);
  ASSERT_TRUE(r.success) << r.message;
  ASSERT_EQ(r.planes.size(), 1u);
  EXPECT_NEAR(r.planes[0].height, kTableZ, 0.005);
  ASSERT_FALSE(r.objects.empty());
  for (const hope::Object& o : r.objects) EXPECT_GE(share(partsOf(o.points), kBook), 0.99);
  // Around the cup: the table and the cup.
  r = inBox(0.2, 0.1, 0.7, 0.35, 0.25, 1.0);
  ASSERT_TRUE(r.success) << r.message;
  ASSERT_EQ(r.objects.size(), 1u);
  EXPECT_GE(share(partsOf(r.objects[0].points), kCup), 0.99);
  // An empty corner of the table: the table, nothing on it.
  r = inBox(0.8, 0.15, 0.7, 1.0, 0.3, 1.0);
  ASSERT_TRUE(r.success) << r.message;
  ASSERT_EQ(r.planes.size(), 1u);
  EXPECT_NEAR(r.planes[0].height, kTableZ, 0.005);
  EXPECT_TRUE(r.objects.empty());
  // The floor away from the table: the floor only.
  r = inBox(-1.0, -1.0, -0.1, -0.5, -0.5, 0.1);
  ASSERT_TRUE(r.success) << r.message;
  ASSERT_EQ(r.planes.size(), 1u);
  EXPECT_NEAR(r.planes[0].height, 0.0, 0.005);
  EXPECT_TRUE(r.objects.empty());
  // Under the floor: nothing, said with the box.
  r = inBox(-1.0, -1.0, -0.5, 1.0, 1.0, -0.2);
  EXPECT_FALSE(r.success);
  EXPECT_NE(r.message.find("in the box"), std::string::npos) << r.message;
}

TEST_F(SegmentAnswer, NothingInTheBandIsARefusalThatSaysWhatWasThere) {
  hope::Segment::Request request;
  request.limit_height = true;
  request.min_height = 1.5;
  request.max_height = 2.0;
  const hope::Segment::Response r = hope_ros::segmentAnswer(request, frame_, header_);
  EXPECT_FALSE(r.success);
  EXPECT_TRUE(r.planes.empty());
  EXPECT_TRUE(r.plane_points.empty());
  EXPECT_TRUE(r.objects.empty());
  EXPECT_NE(r.message.find("between 1.50 and 2.00 m"), std::string::npos) << r.message;
  EXPECT_NE(r.message.find("0.75"), std::string::npos) << r.message;
}

TEST_F(SegmentAnswer, ObjectPointsNeedTheFramesPoints) {
  hope::ObjectArray objects;
  objects.objects.resize(frame_.result.objects.size());
  ASSERT_FALSE(objects.objects.empty());
  hope::Frame pointless = frame_;
  pointless.points.clear();
  EXPECT_THROW(hope_ros::attachObjectPoints(pointless, objects), std::invalid_argument);
  objects.objects.pop_back();
  EXPECT_THROW(hope_ros::attachObjectPoints(frame_, objects), std::invalid_argument);
}

TEST(SegmentRequest, ABadRequestNamesItsField) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  hope::Segment::Request r;
  EXPECT_EQ(hope_ros::checkSegmentRequest(r), "");
  EXPECT_DOUBLE_EQ(hope_ros::segmentTimeout(r), 5.0);
  r.timeout = 2.0;
  EXPECT_DOUBLE_EQ(hope_ros::segmentTimeout(r), 2.0);
  for (double bad : {-1.0, 301.0, nan}) {
    r.timeout = bad;
    EXPECT_NE(hope_ros::checkSegmentRequest(r).find("timeout"), std::string::npos) << bad;
  }
  r.timeout = 0;
  r.limit_height = true;
  r.min_height = 1.0;
  r.max_height = 0.5;
  EXPECT_NE(hope_ros::checkSegmentRequest(r).find("min_height"), std::string::npos);
  r.max_height = nan;
  EXPECT_NE(hope_ros::checkSegmentRequest(r).find("min_height"), std::string::npos);
  r.limit_height = false;  // the band's values are not read then
  EXPECT_EQ(hope_ros::checkSegmentRequest(r), "");
  r.limit_box = true;
  r.box_max.x = 1;
  r.box_max.y = 1;
  r.box_max.z = -1;  // below box_min.z
  EXPECT_NE(hope_ros::checkSegmentRequest(r).find("box_min"), std::string::npos);
}

}  // namespace
