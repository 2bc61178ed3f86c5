// The rostest side: listens to the hope nodelet's outputs while a bag replays and checks them
// against the scene's known answer. Parameters (private):
//   expected_heights [m…]  planes that must be found (each within `tolerance`)
//   tolerance (0.03), min_arrays (2), timeout (60 s), expected_frame (frame of the outputs)
//   expected_count: the exact number of planes (when given)
//   check_outputs (true): markers with text and a labeled cloud with a label field must arrive
//   send_malformed (false): publish broken clouds on `cloud_topic` first; hope must live on
//   reconfigure_min_height: set min_height through dynamic_reconfigure, then no plane below
//   required_bag: skip (with a message) when this file does not exist
#include <cstring>
#include <fstream>
#include <limits>
#include <mutex>
#include <set>

#include <dynamic_reconfigure/Reconfigure.h>
#include <gtest/gtest.h>
#include <ros/ros.h>
#include <sensor_msgs/PointCloud2.h>
#include <visualization_msgs/MarkerArray.h>

#include "hope/PlaneArray.h"

namespace {

struct Received {
  std::mutex mutex;
  std::vector<hope::PlaneArray> arrays;
  visualization_msgs::MarkerArray markers;
  bool have_markers = false;
  sensor_msgs::PointCloud2 cloud;
  bool have_cloud = false;
};

Received received;

// Waits until `done()` or the timeout; false on timeout.
template <class Done>
bool waitFor(Done done, double timeout) {
  const ros::WallTime until = ros::WallTime::now() + ros::WallDuration(timeout);
  while (ros::ok() && ros::WallTime::now() < until) {
    {
      std::lock_guard<std::mutex> lock(received.mutex);
      if (done()) return true;
    }
    ros::WallDuration(0.05).sleep();
  }
  return false;
}

sensor_msgs::PointCloud2 cloudWith(const std::vector<std::string>& names, std::uint8_t type,
                                   std::uint32_t width, std::uint32_t height, std::size_t bytes) {
  sensor_msgs::PointCloud2 c;
  c.header.frame_id = "camera_depth_optical_frame";
  c.header.stamp = ros::Time::now();
  c.width = width;
  c.height = height;
  std::uint32_t offset = 0;
  for (const auto& n : names) {
    sensor_msgs::PointField f;
    f.name = n;
    f.offset = offset;
    f.datatype = type;
    f.count = 1;
    offset += type == sensor_msgs::PointField::FLOAT64 ? 8 : 4;
    c.fields.push_back(f);
  }
  c.point_step = offset;
  c.row_step = c.point_step * width;
  c.data.assign(bytes, 0);
  return c;
}

void sendMalformed(ros::Publisher& pub) {
  std::vector<sensor_msgs::PointCloud2> bad;
  bad.push_back(cloudWith({"x", "y"}, sensor_msgs::PointField::FLOAT32, 10, 1, 80));  // no z
  bad.push_back(cloudWith({"x", "y", "z"}, sensor_msgs::PointField::FLOAT64, 10, 1, 240));
  bad.push_back(cloudWith({"x", "y", "z"}, sensor_msgs::PointField::FLOAT32, 100, 1, 12));  // short
  auto nan_cloud = cloudWith({"x", "y", "z"}, sensor_msgs::PointField::FLOAT32, 8, 8, 8 * 8 * 12);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  for (std::size_t i = 0; i + 4 <= nan_cloud.data.size(); i += 4)
    std::memcpy(&nan_cloud.data[i], &nan, 4);
  bad.push_back(nan_cloud);
  bad.push_back(cloudWith({"x", "y", "z"}, sensor_msgs::PointField::FLOAT32, 0, 0, 0));  // empty
  for (int round = 0; round < 3; ++round) {
    for (auto& c : bad) {
      c.header.stamp = ros::Time::now();
      pub.publish(c);
      ros::WallDuration(0.05).sleep();
    }
  }
}

TEST(HopeNodelet, FindsTheKnownPlanes) {
  ros::NodeHandle nh, pnh("~");
  std::string required_bag;
  if (pnh.getParam("required_bag", required_bag) && !std::ifstream(required_bag).good()) {
    GTEST_SKIP() << "no " << required_bag << " (../shared/data absent): skipped";
  }
  std::vector<double> expected;
  pnh.getParam("expected_heights", expected);
  const double tolerance = pnh.param("tolerance", 0.03);
  const int min_arrays = pnh.param("min_arrays", 2);
  const double timeout = pnh.param("timeout", 60.0);
  const bool check_outputs = pnh.param("check_outputs", true);
  const std::string expected_frame = pnh.param<std::string>("expected_frame", "");
  const std::string hope_ns = pnh.param<std::string>("hope_ns", "/hope");

  ros::Subscriber planes =
      nh.subscribe<hope::PlaneArray>(hope_ns + "/planes", 10,
                                     boost::function<void(const hope::PlaneArray::ConstPtr&)>(
                                         [](const hope::PlaneArray::ConstPtr& m) {
                                           // Empty arrays (from the broken or all-NaN clouds) prove
                                           // nothing about the scene.
                                           if (m->planes.empty()) return;
                                           std::lock_guard<std::mutex> lock(received.mutex);
                                           received.arrays.push_back(*m);
                                         }));
  ros::Subscriber markers, cloud;
  if (check_outputs) {
    markers = nh.subscribe<visualization_msgs::MarkerArray>(
        hope_ns + "/markers", 1,
        boost::function<void(const visualization_msgs::MarkerArray::ConstPtr&)>(
            [](const visualization_msgs::MarkerArray::ConstPtr& m) {
              if (m->markers.size() < 2) return;  // only the DELETEALL: an empty frame
              std::lock_guard<std::mutex> lock(received.mutex);
              received.markers = *m;
              received.have_markers = true;
            }));
    cloud = nh.subscribe<sensor_msgs::PointCloud2>(
        hope_ns + "/labeled_cloud", 1,
        boost::function<void(const sensor_msgs::PointCloud2::ConstPtr&)>(
            [](const sensor_msgs::PointCloud2::ConstPtr& m) {
              if (m->width * m->height == 0) return;
              std::lock_guard<std::mutex> lock(received.mutex);
              received.cloud = *m;
              received.have_cloud = true;
            }));
  }
  ros::AsyncSpinner spinner(2);
  spinner.start();

  if (pnh.param("send_malformed", false)) {
    ros::Publisher bad = nh.advertise<sensor_msgs::PointCloud2>(
        pnh.param<std::string>("cloud_topic", "/camera/depth/points"), 10);
    ros::WallDuration(1.0).sleep();  // let hope connect
    sendMalformed(bad);
  }

  ASSERT_TRUE(
      waitFor([&] { return static_cast<int>(received.arrays.size()) >= min_arrays; }, timeout))
      << "fewer than " << min_arrays << " PlaneArray messages with planes on " << hope_ns
      << "/planes";
  hope::PlaneArray last;
  {
    std::lock_guard<std::mutex> lock(received.mutex);
    last = received.arrays.back();
  }
  std::string found;
  for (const auto& p : last.planes)
    found += " " + std::to_string(p.id) + "@" + std::to_string(p.height);
  int expected_count;
  if (pnh.getParam("expected_count", expected_count)) {
    EXPECT_EQ(static_cast<int>(last.planes.size()), expected_count) << "planes:" << found;
  }
  if (!expected_frame.empty()) {
    EXPECT_EQ(last.header.frame_id, expected_frame);
  }
  for (double h : expected) {
    bool hit = false;
    for (const auto& p : last.planes) hit = hit || std::fabs(p.height - h) <= tolerance;
    EXPECT_TRUE(hit) << "no plane at " << h << " m; planes:" << found;
  }
  // Ids are unique in a frame and persistent: the previous array's planes keep theirs.
  std::set<int> ids;
  for (const auto& p : last.planes) EXPECT_TRUE(ids.insert(p.id).second) << "id twice:" << found;
  {
    std::lock_guard<std::mutex> lock(received.mutex);
    const auto& before = received.arrays[received.arrays.size() - 2];
    for (const auto& p : before.planes) {
      if (p.num_points < 2000) continue;  // big planes only: small ones may come and go
      for (const auto& q : last.planes) {
        if (std::fabs(p.height - q.height) < 0.01 && q.num_points >= 2000) {
          EXPECT_EQ(p.id, q.id) << "plane at " << p.height << " m changed its id";
        }
      }
    }
  }

  if (check_outputs) {
    ASSERT_TRUE(waitFor([] { return received.have_markers && received.have_cloud; }, 10.0))
        << "no markers or labeled cloud";
    std::lock_guard<std::mutex> lock(received.mutex);
    int texts = 0;
    for (const auto& m : received.markers.markers)
      texts += m.type == visualization_msgs::Marker::TEXT_VIEW_FACING ? 1 : 0;
    EXPECT_GE(texts, 1);
    EXPECT_EQ(received.markers.markers.front().action, visualization_msgs::Marker::DELETEALL);
    bool has_label = false;
    for (const auto& f : received.cloud.fields) has_label = has_label || f.name == "label";
    EXPECT_TRUE(has_label);
    EXPECT_GT(received.cloud.width * received.cloud.height, 0u);
  }

  double min_height;
  if (pnh.getParam("reconfigure_min_height", min_height)) {
    dynamic_reconfigure::Reconfigure srv;
    dynamic_reconfigure::DoubleParameter p;
    p.name = "min_height";
    p.value = min_height;
    srv.request.config.doubles.push_back(p);
    ASSERT_TRUE(ros::service::call(hope_ns + "/set_parameters", srv)) << "reconfigure failed";
    std::size_t seen;
    {
      std::lock_guard<std::mutex> lock(received.mutex);
      seen = received.arrays.size();
    }
    // Two more frames: the first may have started before the change.
    ASSERT_TRUE(waitFor([&] { return received.arrays.size() >= seen + 2; }, timeout))
        << "no frames after reconfiguring";
    std::lock_guard<std::mutex> lock(received.mutex);
    const auto& after = received.arrays.back();
    EXPECT_FALSE(after.planes.empty());
    for (const auto& q : after.planes)
      EXPECT_GE(q.height, min_height) << "the new band was ignored";
  }
}

}  // namespace

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "hope_plane_checker");
  return RUN_ALL_TESTS();
}
