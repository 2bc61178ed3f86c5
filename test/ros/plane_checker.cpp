// The rostest side: listens to the hope nodelet's outputs while a bag replays and checks them
// against the scene's known answer. Parameters (private):
//   expected_heights [m…]  planes that must be found (each within `tolerance`)
//   tolerance (0.03), min_arrays (2), timeout (60 s), expected_frame (frame of the outputs)
//   expected_count: the exact number of planes (when given)
//   check_outputs (true): markers with text and a labeled cloud with a label field must arrive
//   send_malformed (false): publish broken clouds on `cloud_topic` first; hope must live on
//   reconfigure_min_height: set min_height through dynamic_reconfigure, then no plane below
//   required_bag: skip (with a message) when this file does not exist
//   reconfigure_rejected (false): ask for a height band hope refuses; the reported config and
//     the parameter server must keep the band in effect
//   paused_clock (false): publish /clock once and a cloud no transform exists for; hope must
//     keep answering dynamic_reconfigure (its callback thread never waits for tf)
//   diagnostics_after_jump (false): after /clock jumps back (the bag loops), /diagnostics
//     must still come, twice within 5 s
#include <chrono>
#include <cstring>
#include <fstream>
#include <future>
#include <limits>
#include <mutex>
#include <set>

#include <diagnostic_msgs/DiagnosticArray.h>
#include <dynamic_reconfigure/Reconfigure.h>
#include <gtest/gtest.h>
#include <ros/ros.h>
#include <rosgraph_msgs/Clock.h>
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
  if (!pnh.getParam("expected_heights", expected)) {
    GTEST_SKIP() << "no ~expected_heights: this launch checks something else";
  }
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

  // Enough arrays, the last two in continuous time (not straddling a restart of the bag).
  auto enough = [&] {
    const auto& a = received.arrays;
    return static_cast<int>(a.size()) >= std::max(min_arrays, 2) &&
           a[a.size() - 2].header.stamp < a.back().header.stamp;
  };
  ASSERT_TRUE(waitFor(enough, timeout))
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
    // Persistent ids are checked on the latest two consecutive arrays in continuous time: when
    // the looping bag starts over, hope restarts its tracks (new ids).
    std::lock_guard<std::mutex> lock(received.mutex);
    const auto& arrays = received.arrays;
    std::size_t k = arrays.size() - 1;
    while (k > 0 && !(arrays[k - 1].header.stamp < arrays[k].header.stamp)) --k;
    ASSERT_GT(k, 0u);  // the wait above ensured the last two are in continuous time
    std::size_t compared = 0;
    for (const auto& p : arrays[k - 1].planes) {
      if (p.num_points < 2000) continue;  // big planes only: small ones may come and go
      for (const auto& q : arrays[k].planes) {
        if (std::fabs(p.height - q.height) < 0.01 && q.num_points >= 2000) {
          EXPECT_EQ(p.id, q.id) << "plane at " << p.height << " m changed its id";
          ++compared;
        }
      }
    }
    EXPECT_GT(compared, 0u) << "no big plane seen in two consecutive frames";
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

TEST(HopeNodelet, RefusedReconfigurationIsNotReported) {
  ros::NodeHandle nh, pnh("~");
  if (!pnh.param("reconfigure_rejected", false)) GTEST_SKIP() << "not asked for";
  const std::string hope_ns = pnh.param<std::string>("hope_ns", "/hope");
  ASSERT_TRUE(ros::service::waitForService(hope_ns + "/set_parameters", 30000));
  dynamic_reconfigure::Reconfigure srv;
  for (const auto& [name, value] : {std::make_pair("min_height", 5.0), {"max_height", 1.0}}) {
    dynamic_reconfigure::DoubleParameter p;
    p.name = name;
    p.value = value;
    srv.request.config.doubles.push_back(p);
  }
  ASSERT_TRUE(ros::service::call(hope_ns + "/set_parameters", srv));
  double reported_min = 5, reported_max = 1;
  for (const auto& d : srv.response.config.doubles) {
    if (d.name == "min_height") reported_min = d.value;
    if (d.name == "max_height") reported_max = d.value;
  }
  // min_height 5 > max_height 1 is no band: hope keeps the band it had, and says so.
  EXPECT_LE(reported_min, reported_max);
  EXPECT_NE(reported_min, 5.0);
  double on_server = 5;
  ASSERT_TRUE(nh.getParam(hope_ns + "/min_height", on_server));
  EXPECT_EQ(on_server, reported_min);
}

TEST(HopeNodelet, PausedClockAndMissingTransformBlockNothing) {
  ros::NodeHandle nh, pnh("~");
  if (!pnh.param("paused_clock", false)) GTEST_SKIP() << "not asked for";
  const std::string hope_ns = pnh.param<std::string>("hope_ns", "/hope");
  ros::Publisher clock = nh.advertise<rosgraph_msgs::Clock>("/clock", 1, true);
  ros::Publisher clouds = nh.advertise<sensor_msgs::PointCloud2>(
      pnh.param<std::string>("cloud_topic", "/camera/depth/points"), 10);
  rosgraph_msgs::Clock now;
  now.clock = ros::Time(100.0);
  clock.publish(now);  // and never again: sim time stands still
  ASSERT_TRUE(ros::service::waitForService(hope_ns + "/set_parameters", 30000));
  ros::WallDuration(1.0).sleep();  // let hope connect to the clouds
  for (int i = 0; i < 3; ++i) {
    sensor_msgs::PointCloud2 c =
        cloudWith({"x", "y", "z"}, sensor_msgs::PointField::FLOAT32, 4, 1, 48);
    c.header.frame_id = "frame_without_tf";
    c.header.stamp = ros::Time(100.0);
    clouds.publish(c);
    ros::WallDuration(0.2).sleep();
  }
  // Before the fix, the nodelet's one callback thread waited inside lookupTransform for a
  // timeout that sim time never reached, and this call never returned.
  auto reply = std::async(std::launch::async, [&] {
    dynamic_reconfigure::Reconfigure srv;
    dynamic_reconfigure::DoubleParameter p;
    p.name = "min_area";
    p.value = 0.01;
    srv.request.config.doubles.push_back(p);
    return ros::service::call(hope_ns + "/set_parameters", srv);
  });
  ASSERT_EQ(reply.wait_for(std::chrono::seconds(10)), std::future_status::ready)
      << "dynamic_reconfigure did not answer within 10 s while a cloud waited for tf";
  EXPECT_TRUE(reply.get());
}

TEST(HopeNodelet, DiagnosticsGoOnAfterTimeJumpsBack) {
  ros::NodeHandle nh, pnh("~");
  if (!pnh.param("diagnostics_after_jump", false)) GTEST_SKIP() << "not asked for";
  std::mutex mutex;
  ros::Time last_clock;
  ros::WallTime jumped;  // wall time of the last jump back of /clock
  std::vector<ros::WallTime> reports;
  ros::Subscriber clock = nh.subscribe<rosgraph_msgs::Clock>(
      "/clock", 100,
      boost::function<void(const rosgraph_msgs::Clock::ConstPtr&)>(
          [&](const rosgraph_msgs::Clock::ConstPtr& m) {
            std::lock_guard<std::mutex> lock(mutex);
            if (m->clock < last_clock) jumped = ros::WallTime::now();
            last_clock = m->clock;
          }));
  ros::Subscriber diagnostics = nh.subscribe<diagnostic_msgs::DiagnosticArray>(
      "/diagnostics", 10,
      boost::function<void(const diagnostic_msgs::DiagnosticArray::ConstPtr&)>(
          [&](const diagnostic_msgs::DiagnosticArray::ConstPtr& m) {
            for (const auto& status : m->status) {
              if (status.name.find("processing") == std::string::npos) continue;
              std::lock_guard<std::mutex> lock(mutex);
              reports.push_back(ros::WallTime::now());
            }
          }));
  ros::AsyncSpinner spinner(2);
  spinner.start();
  // Wait for a jump back of /clock, then for two reports after it.
  const ros::WallTime until = ros::WallTime::now() + ros::WallDuration(60.0);
  ros::WallTime after;
  int later = 0;
  while (ros::ok() && ros::WallTime::now() < until) {
    {
      std::lock_guard<std::mutex> lock(mutex);
      if (after.isZero() && !jumped.isZero()) after = jumped;
      later = 0;
      for (const auto& r : reports) later += !after.isZero() && r > after ? 1 : 0;
      if (later >= 2) break;
    }
    ros::WallDuration(0.1).sleep();
  }
  ASSERT_FALSE(after.isZero()) << "the bag never looped (no jump back of /clock)";
  EXPECT_GE(later, 2) << "diagnostics stopped after the clock went back";
}

}  // namespace

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "hope_plane_checker");
  return RUN_ALL_TESTS();
}
