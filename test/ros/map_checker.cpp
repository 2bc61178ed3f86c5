// The rostest side of the surface map. synthetic_map: while the demo room bag replays with tf
// into odom (a fixed frame) and ~surface_map on, every surface of the room is one entry of the
// latched ~map at its height, the table keeps one id in every PlaneArray, and ~reset_map
// empties the map, which then starts afresh with ids never given before. synthetic_turning:
// while a camera turning in place replays, the latched ~map is the map the same room seen at
// once gives (the file `expected`). synthetic_odometry: the demo room bag with an accelerometer
// alone, tracking_mode odometry: the camera's slide found, the map in ~odometry_frame. Parameters
// (private): hope_ns (/hope), timeout (60 s), expected (synthetic_turning), odometry_frame
// (hope_odometry) and reference_frame (hope_gravity) (synthetic_odometry). Each .test runs its
// own test (--gtest_filter).
#include <algorithm>
#include <array>
#include <cmath>
#include <fstream>
#include <iterator>
#include <mutex>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include <gtest/gtest.h>
#include <ros/ros.h>
#include <tf2_eigen/tf2_eigen.h>
#include <tf2_msgs/TFMessage.h>
#include <Eigen/Geometry>

#include "checker_wait.h"
#include "hope/PlaneArray.h"
#include "hope/ResetMap.h"

namespace {

struct Received {
  std::mutex mutex;
  std::vector<hope::PlaneArray> arrays;
  std::vector<hope::PlaneArray> maps;
};
Received received;

// Waits until `done()` (under received.mutex) or the timeout; false on timeout.
template <class Done>
bool waitFor(Done done, double timeout) {
  return hope_test::waitFor(received.mutex, done, timeout);
}

// Collects every PlaneArray on hope_ns/planes and every map on hope_ns/map into `received`.
std::vector<ros::Subscriber> listen(ros::NodeHandle& nh, const std::string& hope_ns) {
  auto into = [&nh](const std::string& topic, std::vector<hope::PlaneArray>& list) {
    return nh.subscribe<hope::PlaneArray>(topic, 10,
                                          boost::function<void(const hope::PlaneArray::ConstPtr&)>(
                                              [&list](const hope::PlaneArray::ConstPtr& m) {
                                                std::lock_guard<std::mutex> lock(received.mutex);
                                                list.push_back(*m);
                                              }));
  };
  return {into(hope_ns + "/planes", received.arrays), into(hope_ns + "/map", received.maps)};
}

// demoRoom()'s level surfaces (world = odom heights): floor, two stair treads, the cabinet, the
// table, the book on it.
const double kSurfaces[] = {0.0, 0.17, 0.34, 0.45, 0.75, 0.80};

TEST(HopeMap, EachSurfaceIsOneEntryAndKeepsItsIdUntilTheMapIsReset) {
  ros::NodeHandle nh, pnh("~");
  const std::string hope_ns = pnh.param<std::string>("hope_ns", "/hope");
  const double timeout = pnh.param("timeout", 60.0);
  const std::vector<ros::Subscriber> subscribers = listen(nh, hope_ns);
  ros::AsyncSpinner spinner(2);
  spinner.start();
  // Ten frames: the bag loops over 5 frames of a sliding camera.
  ASSERT_TRUE(
      waitFor([] { return received.arrays.size() >= 10 && !received.maps.empty(); }, timeout))
      << "no PlaneArrays on " << hope_ns << "/planes or no map on " << hope_ns << "/map";
  int table = -1, largest_id = -1;
  {
    std::lock_guard<std::mutex> lock(received.mutex);
    for (std::size_t f = 1; f < received.arrays.size(); ++f) {
      for (const hope::Plane& p : received.arrays[f].planes) {
        largest_id = std::max(largest_id, p.id);
        if (std::abs(p.height - 0.75) > 0.015) continue;
        if (table < 0) table = p.id;
        EXPECT_EQ(p.id, table) << "the table changed its id in frame " << f;
      }
    }
    ASSERT_GE(table, 0) << "no table at 0.75 m";
    const hope::PlaneArray& latest = received.maps.back();
    EXPECT_EQ(latest.header.frame_id, "odom");
    for (double h : kSurfaces) {
      int entries = 0;
      for (const hope::Plane& p : latest.planes) entries += std::abs(p.height - h) < 0.02 ? 1 : 0;
      EXPECT_EQ(entries, 1) << "surface at " << h << " m: " << entries << " map entries";
    }
    for (const hope::Plane& p : latest.planes) {
      EXPECT_FALSE(p.outline.empty()) << "entry " << p.id;
      EXPECT_GE(p.age, 1);
      largest_id = std::max(largest_id, p.id);
    }
  }

  hope::ResetMap reset;
  ASSERT_TRUE(ros::service::call(hope_ns + "/reset_map", reset));
  EXPECT_GE(reset.response.removed, 6u);
  // The empty map is published at once, then the next clouds fill it again with new ids.
  ASSERT_TRUE(waitFor([] { return !received.maps.empty() && received.maps.back().planes.empty(); },
                      timeout))
      << "no empty map after ~reset_map";
  ASSERT_TRUE(waitFor([] { return !received.maps.back().planes.empty(); }, timeout));
  std::lock_guard<std::mutex> lock(received.mutex);
  for (const hope::Plane& p : received.maps.back().planes) {
    EXPECT_GT(p.id, largest_id) << "an id given again after the reset";
  }
}

// A robot turning in place, with tf: the map the nodelet keeps is the one the same room seen
// at once gives (hope_make_test_bags computed it with the core library, the default
// parameters): for each of its entries of 0.1 m² or more, one entry of ~map at its height
// (within 1 cm) whose box is the same to within a cell (r_xy, 5 cm) on every side, and no
// other; and each of the room's larger level surfaces (floor 0, treads 0.17 and 0.34, cabinet
// 0.45, table 0.75; ground truth) is one entry.
TEST(HopeMap, ARobotTurningInPlaceMapsWhatTheRoomSeenAtOnceGives) {
  ros::NodeHandle nh, pnh("~");
  const std::string hope_ns = pnh.param<std::string>("hope_ns", "/hope");
  const double timeout = pnh.param("timeout", 60.0);
  const std::string path = pnh.param<std::string>("expected", "");
  std::ifstream file(path);
  ASSERT_TRUE(file) << "cannot read the expected map '" << path << "' (param ~expected)";
  std::vector<std::array<double, 5>> expected;
  for (std::string line; std::getline(file, line);) {
    if (line.empty() || line[0] == '#') continue;
    std::array<double, 5> e{};
    std::istringstream in(line);
    ASSERT_TRUE(in >> e[0] >> e[1] >> e[2] >> e[3] >> e[4]) << "bad line: " << line;
    expected.push_back(e);
  }
  ASSERT_GE(expected.size(), 5u) << "the room seen at once has at least 5 large surfaces";
  const std::vector<ros::Subscriber> subscribers = listen(nh, hope_ns);
  ros::AsyncSpinner spinner(2);
  spinner.start();
  // Two turns (the bag loops over 9 views), then a map published after them: the map is
  // republished at least once a second while frames come.
  std::size_t maps_before = 0;
  ASSERT_TRUE(waitFor(
      [&] { return received.arrays.size() >= 20 && (maps_before = received.maps.size()) > 0; },
      timeout))
      << "no PlaneArrays on " << hope_ns << "/planes or no map on " << hope_ns << "/map";
  ASSERT_TRUE(waitFor([&] { return received.maps.size() > maps_before; }, timeout))
      << "no map after two turns";
  std::lock_guard<std::mutex> lock(received.mutex);
  std::vector<hope::Plane> mapped;
  for (const hope::Plane& p : received.maps.back().planes) {
    if (p.area >= 0.1) mapped.push_back(p);
  }
  for (double truth : {0.0, 0.17, 0.34, 0.45, 0.75}) {
    int entries = 0;
    for (const hope::Plane& p : mapped) entries += std::abs(p.height - truth) < 0.015 ? 1 : 0;
    EXPECT_EQ(entries, 1) << "the surface at " << truth << " m";
  }
  EXPECT_EQ(mapped.size(), expected.size()) << "entries of 0.1 m² or more";
  const double cell = 0.05 + 1e-6;
  for (const auto& e : expected) {
    const hope::Plane* match = nullptr;
    for (const hope::Plane& p : mapped) {
      if (std::abs(p.height - e[0]) < 0.01) match = &p;
    }
    ASSERT_NE(match, nullptr) << "no map entry at " << e[0] << " m";
    const double box[4] = {match->x_min, match->y_min, match->x_max, match->y_max};
    for (int side = 0; side < 4; ++side) {
      EXPECT_NEAR(box[side], e[1 + side], cell)
          << "side " << side << " of the entry at " << e[0] << " m";
    }
  }
}

// The demo room bag (the camera sliding 2 cm sideways per frame) with an accelerometer alone
// (hope knows up, not where the camera is), through the nodelet with tracking_mode odometry:
// the scene's odometry finds each 2 cm slide (the bag's truth) and broadcasts it as
// ~odometry_frame under the reference frame; the latched ~map lies in that frame and holds
// each of the room's level surfaces (heights relative to the camera, 1.5 m above the floor)
// as one entry; the table keeps one id while the bag plays (the odometry and its map start
// afresh each time the bag loops back).
TEST(HopeMap, ASlideFoundByTheSceneOdometryKeepsOneEntryPerSurface) {
  ros::NodeHandle nh, pnh("~");
  const std::string hope_ns = pnh.param<std::string>("hope_ns", "/hope");
  const double timeout = pnh.param("timeout", 60.0);
  const std::string odometry_frame = pnh.param<std::string>("odometry_frame", "hope_odometry");
  const std::string reference_frame = pnh.param<std::string>("reference_frame", "hope_gravity");
  // The odometry's poses as broadcast, in the order they came (stamp, pose): straight from /tf,
  // which a looping bag's jumps back in time do not clear.
  std::vector<std::pair<double, Eigen::Isometry3d>> world_from_frame;
  std::vector<std::string> wrong_parents;
  ros::Subscriber tf_sub = nh.subscribe<tf2_msgs::TFMessage>(
      "/tf", 100,
      boost::function<void(const tf2_msgs::TFMessage::ConstPtr&)>(
          [&](const tf2_msgs::TFMessage::ConstPtr& m) {
            std::lock_guard<std::mutex> lock(received.mutex);
            for (const geometry_msgs::TransformStamped& t : m->transforms) {
              if (t.child_frame_id != odometry_frame) continue;
              if (t.header.frame_id != reference_frame) wrong_parents.push_back(t.header.frame_id);
              world_from_frame.emplace_back(t.header.stamp.toSec(),
                                            tf2::transformToEigen(t).inverse());
            }
          }));
  const std::vector<ros::Subscriber> subscribers = listen(nh, hope_ns);
  ros::AsyncSpinner spinner(2);
  spinner.start();
  // Three passes of the 5 views, and the odometry's poses of 12 of them.
  ASSERT_TRUE(waitFor([&] { return received.arrays.size() >= 15 && world_from_frame.size() >= 12; },
                      timeout))
      << "no PlaneArrays on " << hope_ns << "/planes or no " << odometry_frame << " on /tf";
  std::lock_guard<std::mutex> lock(received.mutex);
  EXPECT_TRUE(wrong_parents.empty()) << odometry_frame << " broadcast under "
                                     << wrong_parents.front() << ", not " << reference_frame;
  // Each step between views 0.2 s apart: 2 cm sideways, level, without a turn.
  int steps = 0;
  for (auto it = world_from_frame.begin(); std::next(it) != world_from_frame.end(); ++it) {
    const auto next = std::next(it);
    // Not neighbours in one pass of the bag (a view lost on the way, or the bag looped back).
    if (std::abs(next->first - it->first - 0.2) > 0.01) continue;
    const Eigen::Isometry3d step = it->second.inverse() * next->second;
    const Eigen::Matrix3d r = step.rotation();
    const double yaw = std::atan2(r(1, 0), r(0, 0)) * 180.0 / M_PI;
    const double tilt = std::acos(std::min(1.0, r(2, 2))) * 180.0 / M_PI;
    const std::string between = " between the views at " + std::to_string(it->first) + " and " +
                                std::to_string(next->first);
    EXPECT_NEAR(yaw, 0.0, 0.5) << "the turn" << between;
    EXPECT_LT(tilt, 0.01) << "the odometry turns about the vertical alone";
    EXPECT_NEAR(step.translation().head<2>().norm(), 0.02, 0.005) << "the slide" << between;
    EXPECT_NEAR(step.translation().z(), 0.0, 0.005) << "the height" << between;
    ++steps;
  }
  EXPECT_GE(steps, 6) << "fewer than 6 steps between neighbouring views were broadcast";
  ASSERT_FALSE(received.maps.empty()) << "no map on " << hope_ns << "/map";
  // Every map: no surface twice; and one holds each of them once.
  const double eye = 1.5;
  bool all_seen = false;
  for (const hope::PlaneArray& map : received.maps) {
    EXPECT_EQ(map.header.frame_id, odometry_frame);
    std::size_t seen = 0;
    for (double truth : kSurfaces) {
      int entries = 0;
      for (const hope::Plane& p : map.planes) {
        entries += std::abs(p.height - (truth - eye)) < 0.02 ? 1 : 0;
      }
      EXPECT_LE(entries, 1) << "the surface at " << truth << " m in the map at "
                            << map.header.stamp.toSec();
      seen += entries == 1 ? 1 : 0;
    }
    all_seen = all_seen || seen == std::size(kSurfaces);
  }
  EXPECT_TRUE(all_seen) << "no map holds every surface of the room";
  // The table's id within each pass of the bag.
  int table = -1, passes = 0;
  double last_stamp = -1;
  for (const hope::PlaneArray& array : received.arrays) {
    const double stamp = array.header.stamp.toSec();
    if (stamp < last_stamp) table = -1;  // looped back: a new world, a new map
    last_stamp = stamp;
    for (const hope::Plane& p : array.planes) {
      if (std::abs(p.height - (0.75 - eye)) > 0.015) continue;
      if (table < 0) {
        table = p.id;
        ++passes;
      }
      EXPECT_EQ(p.id, table) << "the table changed its id at " << stamp << " s";
    }
  }
  EXPECT_GE(passes, 2) << "no table at 0.75 m in two passes";
}

}  // namespace

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "hope_map_checker");
  ros::NodeHandle nh;
  return RUN_ALL_TESTS();
}
