// The rostest side: listens to the hope nodelet's outputs while a bag replays and checks them
// against the scene's known answer. Parameters (private):
//   expected_heights [m…]  planes that must be found (each within `tolerance`)
//   tolerance (0.03), min_arrays (2), timeout (60 s), expected_frame (frame of the outputs)
//   duration (0): listen this long (s) while the bag loops; every array received is checked
//   truth_file: per-frame ground truth (stamp height:pixels …) from hope_make_test_bags; then
//     every array is checked against its own frame's surfaces (height_offset is added to the
//     truth's world heights, e.g. -1.5 for heights relative to the camera; surfaces seen by
//     fewer than min_surface_pixels (2000) pixels need not be found)
//   check_outputs (true): markers with text and a labeled cloud with a label field must arrive
//   send_malformed (false): publish broken clouds on `cloud_topic` first; hope must live on
//   reconfigure_min_height: set min_height through dynamic_reconfigure, then no plane below
//   required_bag: skip (with a message) when this file does not exist
//   reconfigure_rejected (false): ask for a height band hope refuses; the reported config and
//     the parameter server must keep the band in effect
//   paused_clock (false): publish /clock once and a cloud no transform exists for; hope must
//     keep answering dynamic_reconfigure (its callback thread never waits for tf), and
//     ~segment must answer after its timeout that no cloud came
//   soak_seconds (0): play the clouds of `soak_bag` on `cloud_topic` that long at
//     `soak_rate_hz` (30), stamped now, with their tf (steady_player.h), and listen to all
//     three outputs; the player must keep 90 % of the rate or more, hope must answer every
//     cloud with a PlaneArray (no frame dropped), and the nodelet manager's resident memory
//     must grow by less than 5 % after the first fifth
//   diagnostics_after_jump (false): after /clock jumps back (the bag loops), /diagnostics
//     must still come, twice within 5 s
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <future>
#include <iterator>
#include <limits>
#include <map>
#include <mutex>
#include <set>
#include <sstream>

#include <diagnostic_msgs/DiagnosticArray.h>
#include <dynamic_reconfigure/Reconfigure.h>
#include <gtest/gtest.h>
#include <ros/ros.h>
#include <rosgraph_msgs/Clock.h>
#include <sensor_msgs/PointCloud2.h>
#include <visualization_msgs/MarkerArray.h>

#include "checker_wait.h"
#include "hope/PlaneArray.h"
#include "hope/Segment.h"
#include "steady_player.h"

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

// Waits until `done()` (under received.mutex) or the timeout; false on timeout.
template <class Done>
bool waitFor(Done done, double timeout) {
  return hope_test::waitFor(received.mutex, done, timeout);
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

// stamp → (height, pixels) of every surface the frame shows, from hope_make_test_bags.
using Truth = std::map<double, std::vector<std::pair<double, int>>>;
Truth readTruth(const std::string& path) {
  Truth truth;
  if (path.empty()) return truth;
  std::ifstream in(path);
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream fields(line);
    double stamp;
    fields >> stamp;
    std::string surface;
    while (fields >> surface) {
      const std::size_t colon = surface.find(':');
      truth[stamp].emplace_back(std::stod(surface.substr(0, colon)),
                                std::stoi(surface.substr(colon + 1)));
    }
  }
  return truth;
}

TEST(HopeNodelet, FindsTheKnownPlanes) {
  ros::NodeHandle nh, pnh("~");
  std::string required_bag;
  if (pnh.getParam("required_bag", required_bag) && !std::ifstream(required_bag).good()) {
    GTEST_SKIP() << "no " << required_bag << " (../shared/data absent): skipped";
  }
  std::vector<double> expected;
  const std::string truth_file = pnh.param<std::string>("truth_file", "");
  if (!pnh.getParam("expected_heights", expected) && truth_file.empty()) {
    GTEST_SKIP() << "no ~expected_heights or ~truth_file: this launch checks something else";
  }
  const Truth truth = readTruth(truth_file);
  ASSERT_TRUE(truth_file.empty() || !truth.empty()) << "no ground truth in " << truth_file;
  const double height_offset = pnh.param("height_offset", 0.0);
  const int min_surface_pixels = pnh.param("min_surface_pixels", 2000);
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
  // With `duration`, go on listening while the bag loops, then check every array received.
  const double duration = pnh.param("duration", 0.0);
  if (duration > 0) ros::WallDuration(duration).sleep();
  std::vector<hope::PlaneArray> arrays;
  {
    std::lock_guard<std::mutex> lock(received.mutex);
    arrays = received.arrays;
  }
  auto describe = [](const hope::PlaneArray& a) {
    std::string text = "at " + std::to_string(a.header.stamp.toSec()) + ":";
    for (const auto& p : a.planes)
      text += " " + std::to_string(p.id) + "@" + std::to_string(p.height);
    return text;
  };
  // Every array, not only the last: a frame where a surface is missing must fail every time,
  // not only when it happens to be the last one received. With a truth file, each array is
  // checked against the surfaces its own frame shows: every surface seen by at least
  // `min_surface_pixels` pixels has a plane at its height, and every plane lies at the height
  // of a surface the frame shows (none invented). A surface seen in several parts may give
  // several planes (the "one surface, one plane" merge is separate work).
  std::size_t wrong_frame = 0, missing = 0, invented = 0, twice = 0, without_truth = 0;
  std::string first_problem;
  for (const hope::PlaneArray& a : arrays) {
    std::string problem;
    if (!expected_frame.empty() && a.header.frame_id != expected_frame) ++wrong_frame;
    std::vector<std::pair<double, int>> surfaces;  // height, pixels
    if (!truth.empty()) {
      const auto it = truth.lower_bound(a.header.stamp.toSec() - 1e-3);
      if (it == truth.end() || std::fabs(it->first - a.header.stamp.toSec()) > 1e-3) {
        ++without_truth;
        continue;
      }
      for (const auto& s : it->second) surfaces.emplace_back(s.first + height_offset, s.second);
    } else {
      for (double h : expected) surfaces.emplace_back(h, min_surface_pixels);
    }
    for (const auto& surface : surfaces) {
      if (surface.second < min_surface_pixels) continue;
      bool hit = false;
      for (const auto& p : a.planes) hit = hit || std::fabs(p.height - surface.first) <= tolerance;
      if (!hit) {
        ++missing;
        problem += " no plane at " + std::to_string(surface.first) + " m";
      }
    }
    for (const auto& p : a.planes) {
      bool real = false;
      for (const auto& surface : surfaces) {
        real = real || std::fabs(p.height - surface.first) <= tolerance;
      }
      if (!real && !truth.empty()) {
        ++invented;
        problem += " plane " + std::to_string(p.id) + " at " + std::to_string(p.height) +
                   " m is no surface";
      }
    }
    std::set<int> ids;
    for (const auto& p : a.planes) {
      if (!ids.insert(p.id).second) {
        ++twice;
        problem += " id " + std::to_string(p.id) + " twice";
      }
    }
    if (!problem.empty() && first_problem.empty()) {
      first_problem = problem + " (" + describe(a) + ")";
    }
  }
  EXPECT_EQ(without_truth, 0u) << "arrays whose stamp is in no truth line of " << truth_file;
  EXPECT_EQ(wrong_frame, 0u) << "arrays not in " << expected_frame;
  EXPECT_EQ(missing, 0u) << "surfaces missing over " << arrays.size()
                         << " arrays; first: " << first_problem;
  EXPECT_EQ(invented, 0u) << "planes where there is no surface; first: " << first_problem;
  EXPECT_EQ(twice, 0u) << "ids given twice in one array; first: " << first_problem;

  // Ids persist between consecutive arrays in continuous time (when the looping bag starts
  // over, hope restarts its tracks). A plane and its counterpart are the mutually best
  // overlapping pair at the same height, so two parts of one surface are never compared with
  // each other, and a split or a merge (the larger part keeps the id) is judged by its larger
  // part.
  std::size_t compared = 0;
  for (std::size_t k = 1; k < arrays.size(); ++k) {
    if (!(arrays[k - 1].header.stamp < arrays[k].header.stamp)) continue;
    const auto& before = arrays[k - 1].planes;
    const auto& now = arrays[k].planes;
    auto overlap = [](const hope::Plane& a, const hope::Plane& b) {
      if (std::fabs(a.height - b.height) > 0.01) return 0.0;
      const double dx = std::min(a.x_max, b.x_max) - std::max(a.x_min, b.x_min);
      const double dy = std::min(a.y_max, b.y_max) - std::max(a.y_min, b.y_min);
      return std::max(dx, 0.0) * std::max(dy, 0.0);
    };
    auto best = [&](const hope::Plane& p, const std::vector<hope::Plane>& among) {
      int index = -1;
      double most = 0;
      for (std::size_t i = 0; i < among.size(); ++i) {
        const double o = overlap(p, among[i]);
        if (o > most) most = o, index = static_cast<int>(i);
      }
      return index;
    };
    for (std::size_t i = 0; i < before.size(); ++i) {
      const hope::Plane& p = before[i];
      if (p.num_points < 2000) continue;  // big planes only: small ones may come and go
      const int j = best(p, now);
      if (j < 0 || best(now[j], before) != static_cast<int>(i)) continue;
      EXPECT_EQ(p.id, now[j].id) << "plane at " << p.height << " m changed its id between "
                                 << describe(arrays[k - 1]) << " and " << describe(arrays[k]);
      ++compared;
    }
  }
  EXPECT_GT(compared, 0u) << "no big plane seen in two consecutive frames";

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
  // ~segment gets no cloud it can answer: after its timeout it says so, and why.
  auto segmented = std::async(std::launch::async, [&] {
    hope::Segment srv;
    srv.request.timeout = 2.0;
    const bool called = ros::service::call(hope_ns + "/segment", srv);
    return std::make_pair(called, srv.response);
  });
  ASSERT_EQ(segmented.wait_for(std::chrono::seconds(10)), std::future_status::ready)
      << "~segment did not answer within 10 s of a 2 s timeout";
  const auto [called, answer] = segmented.get();
  ASSERT_TRUE(called);
  EXPECT_FALSE(answer.success);
  EXPECT_EQ(answer.message.rfind("no cloud stamped after the request", 0), 0u) << answer.message;
  EXPECT_NE(answer.message.find("within 2 s"), std::string::npos) << answer.message;
  EXPECT_TRUE(answer.planes.empty());
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

TEST(HopeNodelet, DiagnosticsCountTheExpectedKey) {
  // e.g. "up from the scene: frames levelled": the key must appear with a count above zero.
  ros::NodeHandle nh, pnh("~");
  const std::string key = pnh.param<std::string>("expected_diagnostic", "");
  if (key.empty()) GTEST_SKIP() << "not asked for";
  std::mutex mutex;
  double best = -1;
  std::string seen;
  ros::Subscriber diagnostics = nh.subscribe<diagnostic_msgs::DiagnosticArray>(
      "/diagnostics", 10,
      boost::function<void(const diagnostic_msgs::DiagnosticArray::ConstPtr&)>(
          [&](const diagnostic_msgs::DiagnosticArray::ConstPtr& m) {
            for (const auto& status : m->status) {
              if (status.name.find("processing") == std::string::npos) continue;
              for (const auto& value : status.values) {
                if (value.key != key) continue;
                std::lock_guard<std::mutex> lock(mutex);
                seen = value.value;
                best = std::max(best, std::atof(value.value.c_str()));
              }
            }
          }));
  ros::AsyncSpinner spinner(2);
  spinner.start();
  const ros::WallTime until = ros::WallTime::now() + ros::WallDuration(60.0);
  while (ros::ok() && ros::WallTime::now() < until) {
    {
      std::lock_guard<std::mutex> lock(mutex);
      if (best > 0) break;
    }
    ros::WallDuration(0.1).sleep();
  }
  std::lock_guard<std::mutex> lock(mutex);
  EXPECT_GT(best, 0) << "diagnostics key '" << key << "' last read '" << seen << "'";
}

// Resident memory (kB) of the process whose command line holds `needle`, or -1.
long residentKb(const std::string& needle) {
  for (const auto& entry : std::filesystem::directory_iterator("/proc")) {
    const std::string pid = entry.path().filename();
    if (pid.find_first_not_of("0123456789") != std::string::npos) continue;
    std::ifstream cmdline(entry.path() / "cmdline");
    std::string args((std::istreambuf_iterator<char>(cmdline)), std::istreambuf_iterator<char>());
    for (char& c : args) c = c == '\0' ? ' ' : c;
    if (args.find(needle) == std::string::npos) continue;
    std::ifstream status(entry.path() / "status");
    std::string line;
    while (std::getline(status, line)) {
      if (line.rfind("VmRSS:", 0) == 0) return std::stol(line.substr(6));
    }
  }
  return -1;
}

// The machine's CPU time so far (jiffies, all CPUs) and the part of it a hypervisor gave to
// other guests ("steal", /proc/stat), or {0, 0} where unreadable.
std::pair<double, double> cpuTotalAndStolen() {
  std::ifstream stat("/proc/stat");
  std::string cpu;
  double total = 0, field = 0, stolen = 0;
  stat >> cpu;
  for (int k = 0; k < 8 && stat >> field; ++k) {
    total += field;
    if (k == 7) stolen = field;
  }
  return {total, stolen};
}

TEST(HopeNodelet, SoaksWithoutDroppingFramesOrGrowing) {
  ros::NodeHandle nh, pnh("~");
  const double seconds = pnh.param("soak_seconds", 0.0);
  if (seconds <= 0) GTEST_SKIP() << "not asked for";
  const double rate = pnh.param("soak_rate_hz", 30.0);
  const std::string hope_ns = pnh.param<std::string>("hope_ns", "/hope");
  const std::string manager = pnh.param<std::string>("manager_name", "__name:=manager");
  const std::string bag = pnh.param<std::string>("soak_bag", "");
  ASSERT_FALSE(bag.empty()) << "~soak_bag (the bag whose clouds are played) is not set";
  soak::SteadyPlayer player(bag, pnh.param<std::string>("cloud_topic", "/camera/depth/points"));
  std::mutex mutex;
  // Every PlaneArray (hope publishes one per processed frame, stamped as its cloud) is kept
  // with a deep queue; the labeled cloud and markers are subscribed as a user would. hope's
  // own account of what it processed, rejected and dropped comes on /diagnostics.
  std::vector<ros::Time> answered;  // stamps of the PlaneArrays
  std::size_t clouds_seen = 0, markers_seen = 0;
  std::string hope_status;
  // hope's counts of clouds its subscriber queue dropped and of clouds it refused, when reported.
  long hope_dropped = -1, hope_rejected = -1;
  auto count = [&](std::size_t& n) {
    std::lock_guard<std::mutex> lock(mutex);
    ++n;
  };
  ros::Subscriber s1 =
      nh.subscribe<hope::PlaneArray>(hope_ns + "/planes", 100,
                                     boost::function<void(const hope::PlaneArray::ConstPtr&)>(
                                         [&](const hope::PlaneArray::ConstPtr& a) {
                                           std::lock_guard<std::mutex> lock(mutex);
                                           answered.push_back(a->header.stamp);
                                         }));
  ros::Subscriber s2 = nh.subscribe<sensor_msgs::PointCloud2>(
      hope_ns + "/labeled_cloud", 1,
      boost::function<void(const sensor_msgs::PointCloud2::ConstPtr&)>(
          [&](const sensor_msgs::PointCloud2::ConstPtr&) { count(clouds_seen); }));
  ros::Subscriber s3 = nh.subscribe<visualization_msgs::MarkerArray>(
      hope_ns + "/markers", 1,
      boost::function<void(const visualization_msgs::MarkerArray::ConstPtr&)>(
          [&](const visualization_msgs::MarkerArray::ConstPtr&) { count(markers_seen); }));
  ros::Subscriber s4 = nh.subscribe<diagnostic_msgs::DiagnosticArray>(
      "/diagnostics", 10,
      boost::function<void(const diagnostic_msgs::DiagnosticArray::ConstPtr&)>(
          [&](const diagnostic_msgs::DiagnosticArray::ConstPtr& d) {
            for (const auto& s : d->status) {
              if (s.name.find("processing") == std::string::npos) continue;
              std::ostringstream text;
              text << s.message;
              long dropped = -1, rejected = -1;
              for (const auto& kv : s.values) {
                text << "; " << kv.key << " " << kv.value;
                if (kv.key.rfind("frames dropped", 0) == 0) dropped = std::stol(kv.value);
                if (kv.key == "frames rejected") rejected = std::stol(kv.value);
              }
              std::lock_guard<std::mutex> lock(mutex);
              hope_status = text.str();
              hope_dropped = dropped;
              hope_rejected = rejected;
            }
          }));
  ros::AsyncSpinner spinner(4);
  spinner.start();
  // hope subscribes once an output has a listener.
  const ros::WallTime connect_until = ros::WallTime::now() + ros::WallDuration(30.0);
  while (ros::WallTime::now() < connect_until && s1.getNumPublishers() == 0)
    ros::WallDuration(0.1).sleep();
  ASSERT_GT(s1.getNumPublishers(), 0u) << "no publisher of " << hope_ns << "/planes";
  player.start(nh, rate);
  // Warm-up: the first fifth (at least 10 s); then memory must stay flat.
  const double warm_up = std::max(10.0, seconds / 5);
  ASSERT_GE(seconds - warm_up, 10.0) << "~soak_seconds leaves less than 10 s after the warm-up";
  ros::WallDuration(warm_up).sleep();
  // The window: the clouds published from here on. hope's counts are those of its last
  // report, up to a second old, so a drop in the warm-up's last second counts as the window's
  // (the check errs towards failing).
  const soak::SteadyPlayer::Progress start = player.progress();
  long dropped_0, rejected_0;
  {
    std::lock_guard<std::mutex> lock(mutex);
    dropped_0 = hope_dropped;
    rejected_0 = hope_rejected;
  }
  ASSERT_GE(dropped_0, 0) << "no diagnostics from hope during the warm-up";
  // Resident memory sampled every second: one reading moves by a whole message (a 4.9 MB
  // cloud waiting in a queue, a 6.1 MB labeled cloud being sent: ~7 % of the manager), so the
  // growth compares the median of the first tenth of the readings with that of the last.
  std::vector<long> rss;
  const std::pair<double, double> cpu_0 = cpuTotalAndStolen();
  const ros::WallTime window_end = ros::WallTime::now() + ros::WallDuration(seconds - warm_up);
  while (ros::WallTime::now() < window_end) {
    rss.push_back(residentKb(manager));
    ASSERT_GT(rss.back(), 0) << "no process with '" << manager << "' in its command line";
    ros::WallDuration(std::min(1.0, (window_end - ros::WallTime::now()).toSec())).sleep();
  }
  player.stop();
  const soak::SteadyPlayer::Progress end = player.progress();
  const std::pair<double, double> cpu_1 = cpuTotalAndStolen();
  const double stolen = cpu_1.first > cpu_0.first
                            ? 100.0 * (cpu_1.second - cpu_0.second) / (cpu_1.first - cpu_0.first)
                            : 0.0;
  ros::WallDuration(2.0).sleep();  // the frames in flight come out; one more diagnostics report
  std::lock_guard<std::mutex> lock(mutex);
  const std::size_t tenth = std::max<std::size_t>(rss.size() / 10, 1);
  auto medianOf = [](std::vector<long> v) {
    std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
    return v[v.size() / 2];
  };
  const long rss_first = medianOf(std::vector<long>(rss.begin(), rss.begin() + tenth));
  const long rss_last = medianOf(std::vector<long>(rss.end() - tenth, rss.end()));
  const double span = seconds - warm_up;
  // Each cloud of the window must be answered: a PlaneArray with its stamp.
  const double in = static_cast<double>(end.published - start.published);
  const double out = static_cast<double>(std::count_if(
      answered.begin(), answered.end(),
      [&](const ros::Time& stamp) { return stamp > start.last_stamp && stamp <= end.last_stamp; }));
  std::printf(
      "soak: %.0f s after a %.0f s warm-up: %.0f clouds in (%.1f/s, %zu different frames), %.0f "
      "PlaneArrays out (%zu labeled clouds, %zu marker arrays in all); manager RSS (median of "
      "%zu readings) %ld kB after warm-up, %ld kB at the end (%+.2f %%); CPU stolen by the "
      "hypervisor meanwhile: %.1f %%\nsoak: hope's diagnostics at the end: %s\n",
      span, warm_up, in, in / span, player.numFrames(), out, clouds_seen, markers_seen, tenth,
      rss_first, rss_last, 100.0 * (rss_last - rss_first) / rss_first, stolen, hope_status.c_str());
  // Not an excuse (the check fails all the same), but the reason to rerun on a quieter host.
  const std::string steal_note =
      stolen > 2.0 ? " (note: the hypervisor took " + std::to_string(stolen) +
                         " % of the CPU during the window; rerun on a quieter host)"
                   : "";
  EXPECT_GE(in, 0.9 * rate * span) << "the player did not keep " << rate << " Hz";
  EXPECT_EQ(out, in) << "clouds of the window went unanswered" << steal_note;
  EXPECT_EQ(hope_dropped, dropped_0)
      << "hope's cloud subscriber dropped clouds after the warm-up: it fell behind" << steal_note;
  EXPECT_EQ(hope_rejected, rejected_0) << "hope refused clouds after the warm-up";
  EXPECT_GT(clouds_seen, 0u);
  EXPECT_GT(markers_seen, 0u);
  EXPECT_LT(rss_last, 1.05 * rss_first) << "memory grew by 5 % or more";
}

}  // namespace

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "hope_plane_checker");
  return RUN_ALL_TESTS();
}
