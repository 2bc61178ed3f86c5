// The rostest side of objects and placements: while the demo room bag replays with tf (heights
// and positions in odom, the scene's own frame), checks hope's ~objects, the object boxes in
// ~markers, the labeled cloud's object field, ~obstacles, ~floor_grid, ~segment, object_points,
// publish_tf and ~find_placement against the
// scene's ground truth (hope::synthetic::demoRoom()), then switches objects and placements off
// through dynamic_reconfigure.
// Parameters (private): hope_ns (/hope), timeout (60 s).
#include <algorithm>
#include <cmath>
#include <cstring>
#include <map>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include <dynamic_reconfigure/Reconfigure.h>
#include <gtest/gtest.h>
#include <nav_msgs/OccupancyGrid.h>
#include <ros/ros.h>
#include <sensor_msgs/PointCloud2.h>
#include <visualization_msgs/MarkerArray.h>

#include <tf2_eigen/tf2_eigen.h>
#include <tf2_ros/buffer.h>
#include <tf2_ros/transform_listener.h>
#include <Eigen/Geometry>

#include "checker_wait.h"
#include "hope/FindPlacement.h"
#include "hope/ObjectArray.h"
#include "hope/PlaneArray.h"
#include "hope/Segment.h"

namespace {

// demoRoom()'s table top: z 0.75, x 1.3–2.2, y −0.9–0.1 (world = odom).
constexpr double kTableZ = 0.75, kTableX0 = 1.3, kTableX1 = 2.2, kTableY0 = -0.9, kTableY1 = 0.1;

// What stands on the table in demoRoom(), by the primitives that make it.
// An object's box height (BOX_Z of its SolidPrimitive); the message must carry a box.
double boxHeight(const hope::Object& o) {
  EXPECT_EQ(o.box.type, shape_msgs::SolidPrimitive::BOX);
  return o.box.dimensions.at(shape_msgs::SolidPrimitive::BOX_Z);
}

struct Expected {
  const char* name;
  double x, y;  // centre of its footprint
  double height;
  // Distance in xy from `p` to its footprint (0 inside).
  double (*distance)(double px, double py);
};

double bookDistance(double px, double py) {  // box 1.7–1.95 × −0.45–−0.25, 5 cm high
  const double dx = std::max({1.7 - px, 0.0, px - 1.95}),
               dy = std::max({-0.45 - py, 0.0, py + 0.25});
  return std::hypot(dx, dy);
}
double coneDistance(double px, double py) {  // apex (1.5, −0.2, 1.0), base radius 0.1, 0.25 high
  return std::max(0.0, std::hypot(px - 1.5, py + 0.2) - 0.1);
}
double tubeDistance(double px, double py) {  // tube r 0.04 from (1.95, −0.8) to (2.15, −0.55)
  const double ax = 1.95, ay = -0.8, bx = 2.15, by = -0.55;
  const double t = std::clamp(((px - ax) * (bx - ax) + (py - ay) * (by - ay)) /
                                  ((bx - ax) * (bx - ax) + (by - ay) * (by - ay)),
                              0.0, 1.0);
  return std::max(0.0, std::hypot(px - (ax + t * (bx - ax)), py - (ay + t * (by - ay))) - 0.04);
}

const Expected kOnTheTable[] = {{"book", 1.825, -0.35, 0.05, bookDistance},
                                {"cone", 1.5, -0.2, 0.25, coneDistance},
                                {"lying tube", 2.05, -0.675, 0.08, tubeDistance}};

struct Received {
  std::mutex mutex;
  std::vector<hope::ObjectArray> objects;
  std::vector<hope::PlaneArray> planes;
  // Per stamp: the number of points of each object value (index + 1) in the labeled cloud, and
  // the object boxes among the markers.
  std::map<double, std::map<std::uint32_t, std::size_t>> cloud_counts;
  std::map<double, std::size_t> marker_boxes;
  bool cloud_has_object_field = true;
};
Received received;

// Waits until `done()` (under received.mutex) or the timeout; false on timeout.
template <class Done>
bool waitFor(Done done, double timeout) {
  return hope_test::waitFor(received.mutex, done, timeout);
}

void onCloud(const sensor_msgs::PointCloud2::ConstPtr& m) {
  int offset = -1;
  for (const auto& f : m->fields) {
    if (f.name == "object" && f.datatype == sensor_msgs::PointField::UINT32) offset = f.offset;
  }
  std::lock_guard<std::mutex> lock(received.mutex);
  if (offset < 0) {
    received.cloud_has_object_field = false;
    return;
  }
  auto& counts = received.cloud_counts[m->header.stamp.toSec()];
  counts.clear();
  for (std::size_t i = 0; i < std::size_t(m->width) * m->height; ++i) {
    std::uint32_t object;
    std::memcpy(&object, &m->data[i * m->point_step + offset], sizeof(object));
    ++counts[object];
  }
}

void onMarkers(const visualization_msgs::MarkerArray::ConstPtr& m) {
  if (m->markers.size() < 2) return;
  std::size_t boxes = 0;
  for (const auto& marker : m->markers) {
    boxes += marker.ns == "objects" && marker.type == visualization_msgs::Marker::CUBE ? 1 : 0;
  }
  std::lock_guard<std::mutex> lock(received.mutex);
  received.marker_boxes[m->markers.back().header.stamp.toSec()] = boxes;
}

// The table's id in the latest PlaneArray, or -1.
int tableId() {
  std::lock_guard<std::mutex> lock(received.mutex);
  if (received.planes.empty()) return -1;
  for (const auto& p : received.planes.back().planes) {
    if (std::abs(p.height - kTableZ) < 0.02 && p.x_min < kTableX0 + 0.2 && p.x_max > kTableX1 - 0.2)
      return p.id;
  }
  return -1;
}

hope::FindPlacement::Response place(const std::string& hope_ns, double width, double depth,
                                    double clearance, int plane_id) {
  hope::FindPlacement srv;
  srv.request.width = width;
  srv.request.depth = depth;
  srv.request.clearance = clearance;
  srv.request.plane_id = plane_id;
  EXPECT_TRUE(ros::service::call(hope_ns + "/find_placement", srv)) << "the call itself failed";
  return srv.response;
}

void reconfigure(const std::string& hope_ns, bool objects, bool placements) {
  dynamic_reconfigure::Reconfigure srv;
  for (const auto& [name, value] : std::vector<std::pair<std::string, bool>>{
           {"objects", objects}, {"placements", placements}}) {
    dynamic_reconfigure::BoolParameter p;
    p.name = name;
    p.value = value;
    srv.request.config.bools.push_back(p);
  }
  ASSERT_TRUE(ros::service::call(hope_ns + "/set_parameters", srv)) << "reconfigure failed";
}

// Points of `cloud` (x y z float32 at the start of each point), their heights in odom.
std::vector<double> odomHeights(const sensor_msgs::PointCloud2& cloud,
                                const geometry_msgs::TransformStamped& to_odom) {
  const Eigen::Isometry3d t = tf2::transformToEigen(to_odom);
  std::vector<double> heights;
  for (std::size_t i = 0; i < std::size_t(cloud.width) * cloud.height; ++i) {
    float xyz[3];
    std::memcpy(xyz, &cloud.data[i * cloud.point_step], sizeof(xyz));
    const Eigen::Vector3d p(xyz[0], xyz[1], xyz[2]);
    if (p.allFinite()) heights.push_back((t * p).z());
  }
  return heights;
}

std::size_t countBetween(const std::vector<double>& heights, double low, double high) {
  return std::count_if(heights.begin(), heights.end(),
                       [&](double z) { return z > low && z <= high; });
}

// The cloud frame's transform into odom at `stamp`, or nothing when the buffer no longer holds
// it: the bag loops, and a jump back in time clears the tf buffer.
std::optional<geometry_msgs::TransformStamped> toOdom(const tf2_ros::Buffer& buffer,
                                                      const std::string& frame,
                                                      const ros::Time& stamp) {
  if (!buffer.canTransform("odom", frame, stamp, ros::Duration(1.0))) return std::nullopt;
  try {
    return buffer.lookupTransform("odom", frame, stamp);
  } catch (const tf2::TransformException&) {
    return std::nullopt;
  }
}

// The input clouds and hope's `Output` messages on `topic` with the same stamps, once at least 3
// stamps are in both (false when that takes longer than `timeout` seconds).
template <class Output>
struct Pairs {
  std::map<double, sensor_msgs::PointCloud2::ConstPtr> inputs;
  std::map<double, typename Output::ConstPtr> outputs;
  std::vector<double> stamps;
};

template <class Output>
bool collectPairs(const std::string& topic, double timeout, Pairs<Output>& pairs) {
  ros::NodeHandle nh;
  std::mutex mutex;
  ros::Subscriber output_sub =
      nh.subscribe<Output>(topic, 5,
                           boost::function<void(const typename Output::ConstPtr&)>(
                               [&](const typename Output::ConstPtr& m) {
                                 std::lock_guard<std::mutex> lock(mutex);
                                 pairs.outputs[m->header.stamp.toSec()] = m;
                               }));
  ros::Subscriber input_sub = nh.subscribe<sensor_msgs::PointCloud2>(
      "/camera/depth/points", 5,
      boost::function<void(const sensor_msgs::PointCloud2::ConstPtr&)>(
          [&](const sensor_msgs::PointCloud2::ConstPtr& m) {
            std::lock_guard<std::mutex> lock(mutex);
            pairs.inputs[m->header.stamp.toSec()] = m;
          }));
  ros::AsyncSpinner spinner(2);
  spinner.start();
  const bool enough = waitFor(
      [&] {
        std::lock_guard<std::mutex> lock(mutex);
        pairs.stamps.clear();
        for (const auto& o : pairs.outputs) {
          if (pairs.inputs.count(o.first)) pairs.stamps.push_back(o.first);
        }
        return pairs.stamps.size() >= 3;
      },
      timeout);
  spinner.stop();
  return enough;
}

// ~obstacles against the demo room (its floor at z = 0 in odom): the input's points between
// 5 cm and 2 m above the floor, all of them and nothing else (1 cm either side of each bound is
// left to the floor's estimate and the depth noise), in the cloud's own frame.
TEST(HopeObjects, ObstaclesAreTheRoomsPointsInTheBandAboveItsFloor) {
  ros::NodeHandle pnh("~");
  const std::string hope_ns = pnh.param<std::string>("hope_ns", "/hope");
  const double timeout = pnh.param("timeout", 60.0);
  tf2_ros::Buffer tf_buffer;
  tf2_ros::TransformListener tf_listener(tf_buffer);
  Pairs<sensor_msgs::PointCloud2> pairs;
  ASSERT_TRUE(collectPairs(hope_ns + "/obstacles", timeout, pairs))
      << "fewer than 3 clouds on " << hope_ns << "/obstacles matching an input";
  std::size_t checked = 0;
  for (double stamp : pairs.stamps) {
    const sensor_msgs::PointCloud2& found = *pairs.outputs[stamp];
    const sensor_msgs::PointCloud2& input = *pairs.inputs[stamp];
    EXPECT_EQ(found.header.frame_id, input.header.frame_id) << "the cloud's own frame";
    const auto to_odom = toOdom(tf_buffer, input.header.frame_id, input.header.stamp);
    if (!to_odom) continue;
    ++checked;
    const std::vector<double> all = odomHeights(input, *to_odom);
    const std::vector<double> band = odomHeights(found, *to_odom);
    const std::size_t in_band = countBetween(all, 0.06, 1.99);
    ASSERT_GT(in_band, 1000u) << "the demo room's things are in view";
    EXPECT_GE(countBetween(band, 0.06, 1.99), 0.99 * in_band) << "recall at " << stamp;
    EXPECT_GE(countBetween(band, 0.04, 2.01), 0.99 * band.size()) << "precision at " << stamp;
  }
  EXPECT_GE(checked, 1u) << "no obstacle cloud whose input's transform tf still held";
}

// ~floor_grid against the demo room (its floor at z = 0 in odom), from the input's points in
// odom: at least 99 % of the cells a standing thing's point falls in (6 cm to 1.99 m up) are
// occupied, at least 98 % of those where only the floor (within 4 cm) was seen free. Cells holding
// a point within 1 cm of a bound (5 cm, 2 m, the floor's 5 cm tolerance below it) are left to the
// floor's estimate and the depth noise; at least 99 % of the cells nothing fell in are unseen.
TEST(HopeObjects, TheFloorGridIsTheRoomsFloorSeenFreeAndItsThingsOccupied) {
  ros::NodeHandle pnh("~");
  const std::string hope_ns = pnh.param<std::string>("hope_ns", "/hope");
  const double timeout = pnh.param("timeout", 60.0);
  tf2_ros::Buffer tf_buffer;
  tf2_ros::TransformListener tf_listener(tf_buffer);
  Pairs<nav_msgs::OccupancyGrid> pairs;
  ASSERT_TRUE(collectPairs(hope_ns + "/floor_grid", timeout, pairs))
      << "fewer than 3 grids on " << hope_ns << "/floor_grid matching an input";
  std::size_t checked = 0;
  for (double stamp : pairs.stamps) {
    const nav_msgs::OccupancyGrid& grid = *pairs.outputs[stamp];
    const sensor_msgs::PointCloud2& input = *pairs.inputs[stamp];
    EXPECT_EQ(grid.header.frame_id, "odom") << "the reference frame";
    EXPECT_NEAR(grid.info.resolution, 0.05, 1e-6);
    EXPECT_NEAR(grid.info.origin.position.z, 0.0, 0.01) << "on the floor";
    const std::size_t width = grid.info.width, height = grid.info.height;
    ASSERT_EQ(grid.data.size(), width * height);
    const auto transform = toOdom(tf_buffer, input.header.frame_id, input.header.stamp);
    if (!transform) continue;
    ++checked;
    const Eigen::Isometry3d to_odom = tf2::transformToEigen(*transform);
    // Per cell: 1 floor seen, 2 a standing thing, 3 a point too near the bound to call.
    std::vector<std::uint8_t> truth(grid.data.size(), 0);
    for (std::size_t i = 0; i < std::size_t(input.width) * input.height; ++i) {
      float xyz[3];
      std::memcpy(xyz, &input.data[i * input.point_step], sizeof(xyz));
      const Eigen::Vector3d p = to_odom * Eigen::Vector3d(xyz[0], xyz[1], xyz[2]);
      if (!p.allFinite() || p.z() < -0.06 || p.z() > 2.01) continue;
      const bool floor = p.z() >= -0.04 && p.z()<0.04, thing = p.z()> 0.06 && p.z() <= 1.99;
      const std::uint8_t kind = floor ? 1 : thing ? 2 : 3;
      const double x = std::floor((p.x() - grid.info.origin.position.x) / grid.info.resolution);
      const double y = std::floor((p.y() - grid.info.origin.position.y) / grid.info.resolution);
      if (x < 0 || y < 0 || x >= width || y >= height) {
        ADD_FAILURE() << "a point at (" << p.x() << ", " << p.y() << ") is outside the grid";
        continue;
      }
      std::uint8_t& t = truth[std::size_t(y) * width + std::size_t(x)];
      t = std::max(t, kind);
    }
    std::size_t floor_cells = 0, free = 0, thing_cells = 0, occupied = 0, empty = 0, unseen = 0;
    for (std::size_t c = 0; c < truth.size(); ++c) {
      if (truth[c] == 1) ++floor_cells, free += grid.data[c] == 0;
      if (truth[c] == 2) ++thing_cells, occupied += grid.data[c] == 100;
      if (truth[c] == 0) ++empty, unseen += grid.data[c] == -1;
    }
    EXPECT_GE(unseen, 0.99 * empty) << "cells nothing was seen in are unseen at " << stamp;
    ASSERT_GT(floor_cells, 200u) << "the demo room's floor is in view";
    ASSERT_GT(thing_cells, 100u) << "the demo room's things are in view";
    EXPECT_GE(free, 0.98 * floor_cells) << "floor cells free at " << stamp;
    EXPECT_GE(occupied, 0.99 * thing_cells) << "things' cells occupied at " << stamp;
  }
  EXPECT_GE(checked, 1u) << "no grid whose input's transform tf still held";
}

// ~segment (object_points and publish_tf on in this launch): the first cloud stamped after the
// request, answered as ~planes and ~objects gave that cloud, each object with its points inside
// its box and in ~objects too, and a tf frame at each object's box.
TEST(HopeObjects, SegmentAnswersAFreshCloudAsTheStreamDid) {
  ros::NodeHandle nh, pnh("~");
  const std::string hope_ns = pnh.param<std::string>("hope_ns", "/hope");
  const double timeout = pnh.param("timeout", 60.0);
  std::mutex mutex;
  std::map<double, hope::PlaneArray::ConstPtr> planes;
  std::map<double, hope::ObjectArray::ConstPtr> objects;
  // Times the stream started over (the bag loops: a ~planes stamp older than the one before).
  std::size_t restarts = 0;
  double last_stamp = 0;
  ros::Subscriber planes_sub =
      nh.subscribe<hope::PlaneArray>(hope_ns + "/planes", 10,
                                     boost::function<void(const hope::PlaneArray::ConstPtr&)>(
                                         [&](const hope::PlaneArray::ConstPtr& m) {
                                           std::lock_guard<std::mutex> lock(mutex);
                                           const double stamp = m->header.stamp.toSec();
                                           if (stamp < last_stamp) ++restarts;
                                           last_stamp = stamp;
                                           planes[stamp] = m;
                                         }));
  ros::Subscriber objects_sub =
      nh.subscribe<hope::ObjectArray>(hope_ns + "/objects", 10,
                                      boost::function<void(const hope::ObjectArray::ConstPtr&)>(
                                          [&](const hope::ObjectArray::ConstPtr& m) {
                                            std::lock_guard<std::mutex> lock(mutex);
                                            objects[m->header.stamp.toSec()] = m;
                                          }));
  tf2_ros::Buffer tf_buffer;
  tf2_ros::TransformListener tf_listener(tf_buffer);
  ros::AsyncSpinner spinner(2);
  spinner.start();
  ASSERT_TRUE(hope_test::waitFor(
      mutex, [&] { return objects.size() >= 2; }, timeout))
      << "no ~objects stream";

  hope::Segment srv;
  srv.request.timeout = 10.0;
  srv.request.limit_height = true;
  srv.request.min_height = kTableZ - 0.05;
  srv.request.max_height = kTableZ + 0.03;  // the book's top is a plane 5 cm higher
  srv.request.limit_box = true;  // the demo room has another surface at the table's height
  srv.request.box_min.x = kTableX0 - 0.1;
  srv.request.box_min.y = kTableY0 - 0.1;
  srv.request.box_min.z = kTableZ - 0.05;
  srv.request.box_max.x = kTableX1 + 0.1;
  srv.request.box_max.y = kTableY1 + 0.1;
  srv.request.box_max.z = kTableZ + 0.5;
  std::size_t restarts_before;
  {
    std::lock_guard<std::mutex> lock(mutex);
    restarts_before = restarts;
  }
  const ros::Time asked = ros::Time::now();
  ASSERT_TRUE(ros::service::call(hope_ns + "/segment", srv));
  const hope::Segment::Response& answer = srv.response;
  ASSERT_TRUE(answer.success) << answer.message;
  // From a cloud stamped at or after the request; or, when the stream started over while the
  // request waited (the bag ends before the request's time and loops), the first cloud after.
  if (answer.header.stamp < asked) {
    EXPECT_TRUE(hope_test::waitFor(
        mutex, [&] { return restarts > restarts_before; }, 10.0))
        << "answered from a cloud older than the request (" << answer.header.stamp << " < " << asked
        << "), and the stream did not start over";
  }
  EXPECT_EQ(answer.header.frame_id, "odom");
  std::string answered;
  for (const hope::Plane& p : answer.planes) {
    answered += " id " + std::to_string(p.id) + " surface " + std::to_string(p.surface_id) +
                " at " + std::to_string(p.height) + " m x " + std::to_string(p.x_min) + "–" +
                std::to_string(p.x_max) + " y " + std::to_string(p.y_min) + "–" +
                std::to_string(p.y_max) + ",";
  }
  ASSERT_EQ(answer.planes.size(), 1u) << "the table alone is in the band and the box:" << answered;
  ASSERT_EQ(answer.plane_points.size(), 1u);
  EXPECT_NEAR(answer.planes[0].height, kTableZ, 0.02);
  EXPECT_EQ(answer.plane_points[0].width, answer.planes[0].num_points);
  // What stands on the table: the book, the cone and the tube.
  EXPECT_EQ(answer.objects.size(), 3u);

  // The stream's messages of the same cloud.
  const double stamp = answer.header.stamp.toSec();
  ASSERT_TRUE(hope_test::waitFor(
      mutex, [&] { return planes.count(stamp) > 0 && objects.count(stamp) > 0; }, 10.0))
      << "no ~planes and ~objects with the answer's stamp " << stamp;
  hope::PlaneArray::ConstPtr stream_planes;
  hope::ObjectArray::ConstPtr stream_objects;
  {
    std::lock_guard<std::mutex> lock(mutex);
    stream_planes = planes.at(stamp);
    stream_objects = objects.at(stamp);
  }
  bool found = false;
  for (const hope::Plane& p : stream_planes->planes) {
    if (p.id != answer.planes[0].id) continue;
    found = true;
    EXPECT_EQ(p.height, answer.planes[0].height);
    EXPECT_EQ(p.num_points, answer.planes[0].num_points);
  }
  EXPECT_TRUE(found) << "the stream has no plane " << answer.planes[0].id;
  std::size_t on_table = 0;
  for (const hope::Object& o : stream_objects->objects) {
    if (o.plane_id != answer.planes[0].id) continue;
    ++on_table;
    const auto same = std::find_if(answer.objects.begin(), answer.objects.end(),
                                   [&](const hope::Object& a) { return a.index == o.index; });
    ASSERT_NE(same, answer.objects.end()) << "object " << o.index << " not answered";
    EXPECT_EQ(same->num_points, o.num_points);
    EXPECT_EQ(same->pose.position.x, o.pose.position.x);
    EXPECT_EQ(same->box.dimensions, o.box.dimensions);
    EXPECT_EQ(o.points.width, o.num_points) << "object_points: ~objects carry the points";
  }
  EXPECT_EQ(on_table, answer.objects.size());
  for (const hope::Object& o : answer.objects) {
    ASSERT_EQ(o.points.width, o.num_points);
    ASSERT_EQ(o.box.dimensions.size(), 3u);
    // Its box holds its points.
    const Eigen::Vector3d centre(o.pose.position.x, o.pose.position.y, o.pose.position.z);
    const Eigen::Quaterniond turn(o.pose.orientation.w, o.pose.orientation.x, o.pose.orientation.y,
                                  o.pose.orientation.z);
    const Eigen::Vector3d half =
        0.5 * Eigen::Vector3d(o.box.dimensions[0], o.box.dimensions[1], o.box.dimensions[2]);
    std::size_t inside = 0;
    for (std::size_t i = 0; i < o.points.width; ++i) {
      float xyz[3];
      std::memcpy(xyz, &o.points.data[i * o.points.point_step], sizeof(xyz));
      const Eigen::Vector3d local =
          turn.inverse() * (Eigen::Vector3d(xyz[0], xyz[1], xyz[2]) - centre);
      inside += (local.cwiseAbs() - half).maxCoeff() <= 1e-3;
    }
    EXPECT_GE(double(inside), 0.99 * o.num_points) << "object " << o.index;
    // publish_tf: its frame at its box's centre.
    const std::string frame = "hope_object_" + std::to_string(o.index);
    std::string why;
    ASSERT_TRUE(
        tf_buffer.canTransform("odom", frame, answer.header.stamp, ros::Duration(5.0), &why))
        << frame << ": " << why;
    const Eigen::Vector3d at =
        tf2::transformToEigen(tf_buffer.lookupTransform("odom", frame, answer.header.stamp))
            .translation();
    EXPECT_LT((at - centre).norm(), 1e-4) << frame;
  }

  // Nothing in a band: a refusal naming it.
  srv.request.limit_box = false;
  srv.request.min_height = 5.0;
  srv.request.max_height = 6.0;
  ASSERT_TRUE(ros::service::call(hope_ns + "/segment", srv));
  EXPECT_FALSE(srv.response.success);
  EXPECT_NE(srv.response.message.find("between 5.00 and 6.00 m"), std::string::npos)
      << srv.response.message;
}

TEST(HopeObjects, ObjectsAndPlacementsMatchTheScene) {
  ros::NodeHandle nh, pnh("~");
  const std::string hope_ns = pnh.param<std::string>("hope_ns", "/hope");
  const double timeout = pnh.param("timeout", 60.0);
  ros::Subscriber objects_sub =
      nh.subscribe<hope::ObjectArray>(hope_ns + "/objects", 10,
                                      boost::function<void(const hope::ObjectArray::ConstPtr&)>(
                                          [](const hope::ObjectArray::ConstPtr& m) {
                                            std::lock_guard<std::mutex> lock(received.mutex);
                                            received.objects.push_back(*m);
                                          }));
  ros::Subscriber planes_sub =
      nh.subscribe<hope::PlaneArray>(hope_ns + "/planes", 10,
                                     boost::function<void(const hope::PlaneArray::ConstPtr&)>(
                                         [](const hope::PlaneArray::ConstPtr& m) {
                                           std::lock_guard<std::mutex> lock(received.mutex);
                                           received.planes.push_back(*m);
                                         }));
  ros::Subscriber cloud_sub = nh.subscribe(hope_ns + "/labeled_cloud", 2, onCloud);
  ros::Subscriber markers_sub = nh.subscribe(hope_ns + "/markers", 2, onMarkers);
  ros::AsyncSpinner spinner(2);
  spinner.start();

  // Eight frames: the first may have started before every subscription was in place.
  ASSERT_TRUE(waitFor([] { return received.objects.size() >= 8; }, timeout))
      << "fewer than 8 ObjectArrays on " << hope_ns << "/objects";
  {
    std::lock_guard<std::mutex> lock(received.mutex);
    for (std::size_t f = 2; f < received.objects.size(); ++f) {
      const hope::ObjectArray& frame = received.objects[f];
      EXPECT_EQ(frame.header.frame_id, "odom");
      for (const Expected& e : kOnTheTable) {
        int matches = 0;
        for (const hope::Object& o : frame.objects) {
          const double box_height = boxHeight(o);
          const double base = o.pose.position.z - 0.5 * box_height;
          if (std::abs(base - kTableZ) > 0.02) continue;  // not standing on the table
          if (std::hypot(o.pose.position.x - e.x, o.pose.position.y - e.y) > 0.05) continue;
          ++matches;
          EXPECT_NEAR(box_height, e.height, 0.015) << e.name << " at " << frame.header.stamp;
          EXPECT_NEAR(o.height, box_height, 1e-6) << e.name;
          EXPECT_GE(o.footprint.points.size(), 3u) << e.name;
        }
        EXPECT_EQ(matches, 1) << e.name << " found " << matches << " times at "
                              << frame.header.stamp;
      }
      // Everything standing on the table stands over it (within the 15 cm an object may
      // overhang), and is one of the three.
      for (const hope::Object& o : frame.objects) {
        const double base = o.pose.position.z - 0.5 * boxHeight(o);
        if (std::abs(base - kTableZ) > 0.02) continue;
        const double x = o.pose.position.x, y = o.pose.position.y;
        EXPECT_TRUE(x > kTableX0 - 0.15 && x < kTableX1 + 0.15 && y > kTableY0 - 0.15 &&
                    y < kTableY1 + 0.15)
            << "object " << o.index << " at (" << x << ", " << y << ") is off the table";
        bool known = false;
        for (const Expected& e : kOnTheTable) known = known || e.distance(x, y) < 0.03;
        EXPECT_TRUE(known) << "object " << o.index << " at (" << x << ", " << y
                           << ") stands where nothing stands";
      }
    }
    // The labeled cloud's object field and the marker boxes agree with ~objects, frame by frame.
    EXPECT_TRUE(received.cloud_has_object_field) << "labeled_cloud has no uint32 'object' field";
    std::size_t compared = 0;
    for (const hope::ObjectArray& frame : received.objects) {
      const double stamp = frame.header.stamp.toSec();
      const auto counts = received.cloud_counts.find(stamp);
      if (counts != received.cloud_counts.end()) {
        ++compared;
        for (const hope::Object& o : frame.objects) {
          const auto n = counts->second.find(std::uint32_t(o.index + 1));
          EXPECT_EQ(n == counts->second.end() ? 0u : n->second, o.num_points)
              << "object " << o.index << " at " << stamp;
        }
      }
      const auto boxes = received.marker_boxes.find(stamp);
      if (boxes != received.marker_boxes.end()) {
        EXPECT_EQ(boxes->second, frame.objects.size());
      }
    }
    EXPECT_GE(compared, 1u) << "no labeled cloud with the stamp of an ObjectArray";
  }

  // A 10 × 10 cm footprint with 2 cm clearance on the table: on it, and clear of its objects.
  // The bag loops, and a loop restarts the tracks and their ids: a table id read from the
  // last PlaneArray may be gone by the time the service runs. Such a refusal names the
  // frame's planes; read the id again from a newer PlaneArray (a few times at most).
  const double width = 0.10, depth = 0.10, clearance = 0.02;
  int table = -1;
  hope::FindPlacement::Response found;
  for (int attempt = 0; attempt < 5; ++attempt) {
    table = tableId();
    ASSERT_GE(table, 0) << "no table at 0.75 m in the last PlaneArray";
    found = place(hope_ns, width, depth, clearance, table);
    if (found.success ||
        found.message.find("is not a plane of the last frame") == std::string::npos)
      break;
    std::size_t seen = 0;
    {
      std::lock_guard<std::mutex> lock(received.mutex);
      seen = received.planes.size();
    }
    waitFor([seen] { return received.planes.size() > seen; }, 5.0);
  }
  ASSERT_TRUE(found.success) << found.message;
  EXPECT_EQ(found.header.frame_id, "odom");
  ASSERT_FALSE(found.placements.empty()) << "the table has room for a 10 cm square";
  for (const hope::PlacementPose& p : found.placements) {
    EXPECT_EQ(p.plane_id, table);
    EXPECT_NEAR(p.pose.position.z, kTableZ, 0.02);
    EXPECT_NEAR(2 * std::atan2(p.pose.orientation.z, p.pose.orientation.w), p.yaw, 1e-6);
    const double c = std::cos(p.yaw), s = std::sin(p.yaw);
    // Every point of the footprint (a 5 mm grid over it) on the table and at least the
    // clearance (less one r_z / 2 cell of the placement grid) from every object.
    double nearest = 1e9;
    for (double u = -width / 2; u <= width / 2 + 1e-9; u += 0.005) {
      for (double v = -depth / 2; v <= depth / 2 + 1e-9; v += 0.005) {
        const double x = p.pose.position.x + c * u - s * v, y = p.pose.position.y + s * u + c * v;
        EXPECT_TRUE(x >= kTableX0 && x <= kTableX1 && y >= kTableY0 && y <= kTableY1)
            << "placement at (" << p.pose.position.x << ", " << p.pose.position.y
            << ") leaves the table at (" << x << ", " << y << ")";
        for (const Expected& e : kOnTheTable) nearest = std::min(nearest, e.distance(x, y));
      }
    }
    EXPECT_GE(nearest, clearance - 0.01) << "placement at (" << p.pose.position.x << ", "
                                         << p.pose.position.y << ") crowds an object";
  }
  // Refusals carry the reason.
  hope::FindPlacement::Response refused = place(hope_ns, 0.0, 0.1, 0.02, -1);
  EXPECT_FALSE(refused.success);
  EXPECT_NE(refused.message.find("width"), std::string::npos) << refused.message;
  refused = place(hope_ns, 0.1, 0.1, 0.02, 123456);
  EXPECT_FALSE(refused.success);
  EXPECT_NE(refused.message.find("plane_id 123456"), std::string::npos) << refused.message;
  refused = place(hope_ns, 20.0, 20.0, 0.0, -1);  // larger than every plane of the room
  EXPECT_FALSE(refused.success);
  EXPECT_FALSE(refused.message.empty());

  // Both switched off: no objects in the cloud or the markers, and the service refuses.
  reconfigure(hope_ns, false, false);
  std::size_t planes_seen;
  {
    std::lock_guard<std::mutex> lock(received.mutex);
    planes_seen = received.planes.size();
    received.cloud_counts.clear();
    received.marker_boxes.clear();
  }
  // Three more frames: the first may have started before the change.
  ASSERT_TRUE(waitFor([&] { return received.planes.size() >= planes_seen + 3; }, timeout));
  ASSERT_TRUE(waitFor([&] { return received.cloud_counts.size() >= 2; }, timeout));
  {
    std::lock_guard<std::mutex> lock(received.mutex);
    const auto& last = received.cloud_counts.rbegin()->second;
    EXPECT_EQ(last.size(), 1u) << "object values other than 0 with objects off";
    EXPECT_EQ(last.count(0), 1u);
    ASSERT_FALSE(received.marker_boxes.empty());
    EXPECT_EQ(received.marker_boxes.rbegin()->second, 0u) << "object boxes with objects off";
  }
  refused = place(hope_ns, 0.1, 0.1, 0.02, -1);
  EXPECT_FALSE(refused.success);
  EXPECT_NE(refused.message.find("off"), std::string::npos) << refused.message;
}

}  // namespace

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "hope_object_checker");
  ros::NodeHandle nh;
  return RUN_ALL_TESTS();
}
