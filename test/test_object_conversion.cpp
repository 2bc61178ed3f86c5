// Objects and placements as messages (no ROS master needed): boxes turned about z, the marker
// per object, and ~find_placement's request checked before anything is searched.
#include <cmath>
#include <vector>

#include <gtest/gtest.h>
#include <pcl/point_types.h>
#include <Eigen/Geometry>

#include "hope/extractor.h"
#include "hope_ros/object_conversion.h"

namespace {

// Points every `step` m on the top and the four sides of a box of `size` standing on z = 0 at
// `centre` (x, y), turned by `yaw` about z.
void addTurnedBox(pcl::PointCloud<pcl::PointXYZ>& cloud, const Eigen::Vector2d& centre, double yaw,
                  const Eigen::Vector3d& size, double step) {
  const Eigen::Rotation2Dd turn(yaw);
  auto add = [&](double u, double v, double z) {
    const Eigen::Vector2d xy = centre + turn * Eigen::Vector2d(u, v);
    cloud.push_back(pcl::PointXYZ(static_cast<float>(xy.x()), static_cast<float>(xy.y()),
                                  static_cast<float>(z)));
  };
  const double hx = 0.5 * size.x(), hy = 0.5 * size.y();
  for (double u = -hx; u <= hx + 1e-9; u += step) {
    for (double v = -hy; v <= hy + 1e-9; v += step) add(u, v, size.z());
  }
  for (double z = step; z < size.z(); z += step) {
    for (double u = -hx; u <= hx + 1e-9; u += step) {
      add(u, -hy, z);
      add(u, hy, z);
    }
    for (double v = -hy; v <= hy + 1e-9; v += step) {
      add(-hx, v, z);
      add(hx, v, z);
    }
  }
}

hope::StandingObject tallBox() {
  hope::StandingObject o;
  o.index = 2;
  o.plane_index = 1;
  o.plane_id = 7;
  o.num_points = 1234;
  o.centroid = Eigen::Vector3d(1.0, 2.0, 0.85);
  o.box_centre = Eigen::Vector3d(1.0, 2.0, 0.9);
  o.yaw = M_PI / 3;
  o.box_size = Eigen::Vector3d(0.2, 0.1, 0.3);
  o.height = 0.3;
  o.footprint = {{0.9, 1.9, 0.75}, {1.1, 1.9, 0.75}, {1.1, 2.1, 0.75}, {0.9, 2.1, 0.75}};
  return o;
}

TEST(ObjectConversion, AnObjectKeepsItsBoxTurnedAboutZAndItsPlaneId) {
  std_msgs::Header header;
  header.frame_id = "odom";
  const hope::ObjectArray msg = hope_ros::toMessage({tallBox()}, header);
  EXPECT_EQ(msg.header.frame_id, "odom");
  ASSERT_EQ(msg.objects.size(), 1u);
  const hope::Object& o = msg.objects[0];
  EXPECT_EQ(o.index, 2);
  EXPECT_EQ(o.plane_id, 7);
  EXPECT_EQ(o.num_points, 1234u);
  EXPECT_DOUBLE_EQ(o.pose.position.z, 0.9);
  // A turn of π/3 about z: (0, 0, sin π/6, cos π/6).
  EXPECT_NEAR(o.pose.orientation.x, 0.0, 1e-12);
  EXPECT_NEAR(o.pose.orientation.y, 0.0, 1e-12);
  EXPECT_NEAR(o.pose.orientation.z, 0.5, 1e-12);
  EXPECT_NEAR(o.pose.orientation.w, std::sqrt(3.0) / 2, 1e-12);
  EXPECT_EQ(o.box.type, shape_msgs::SolidPrimitive::BOX);
  ASSERT_EQ(o.box.dimensions.size(), 3u);
  EXPECT_DOUBLE_EQ(o.box.dimensions[shape_msgs::SolidPrimitive::BOX_X], 0.2);
  EXPECT_DOUBLE_EQ(o.box.dimensions[shape_msgs::SolidPrimitive::BOX_Y], 0.1);
  EXPECT_DOUBLE_EQ(o.box.dimensions[shape_msgs::SolidPrimitive::BOX_Z], 0.3);
  EXPECT_DOUBLE_EQ(o.height, 0.3);
  ASSERT_EQ(o.footprint.points.size(), 4u);
  EXPECT_FLOAT_EQ(o.footprint.points[2].x, 1.1f);
  EXPECT_FLOAT_EQ(o.footprint.points[2].z, 0.75f);
}

// The message's pose and box, as MoveIt reads a CollisionObject's, hold every point of their
// object: two boxes turned by 30° and 100° on a floor, each found as one object of its true size.
TEST(ObjectConversion, EachBoxMessageHoldsItsObjectsPoints) {
  pcl::PointCloud<pcl::PointXYZ> cloud;
  for (double x = -1.0; x <= 1.0; x += 0.01) {
    for (double y = -1.0; y <= 1.0; y += 0.01) {
      cloud.push_back(pcl::PointXYZ(static_cast<float>(x), static_cast<float>(y), 0.0f));
    }
  }
  const std::vector<Eigen::Vector3d> sizes = {{0.3, 0.15, 0.2}, {0.2, 0.12, 0.3}};
  addTurnedBox(cloud, {-0.4, 0.3}, M_PI / 6, sizes[0], 0.01);
  addTurnedBox(cloud, {0.5, -0.3}, M_PI * 100 / 180, sizes[1], 0.01);
  hope::ExtractOutputs outputs;
  outputs.objects = true;
  hope::Extractor extractor;
  const hope::Result result = extractor.extract(
      cloud, hope::Orientation::identity().withViewpoint(Eigen::Vector3d(0, 0, 1.5)), outputs);
  const hope::ObjectArray msg = hope_ros::toMessage(result.objects, std_msgs::Header());
  ASSERT_EQ(msg.objects.size(), 2u);
  for (const hope::Object& o : msg.objects) {
    ASSERT_EQ(o.box.dimensions.size(), 3u);
    const Eigen::Vector3d dims(o.box.dimensions[shape_msgs::SolidPrimitive::BOX_X],
                               o.box.dimensions[shape_msgs::SolidPrimitive::BOX_Y],
                               o.box.dimensions[shape_msgs::SolidPrimitive::BOX_Z]);
    // The true box it stands for (the nearer centre), its sides in either order.
    const Eigen::Vector3d centre(o.pose.position.x, o.pose.position.y, o.pose.position.z);
    const Eigen::Vector3d truth = centre.x() < 0 ? sizes[0] : sizes[1];
    EXPECT_NEAR(dims.z(), truth.z(), 0.02);
    EXPECT_NEAR(dims.head<2>().maxCoeff(), truth.head<2>().maxCoeff(), 0.02);
    EXPECT_NEAR(dims.head<2>().minCoeff(), truth.head<2>().minCoeff(), 0.02);
    const Eigen::Quaterniond q(o.pose.orientation.w, o.pose.orientation.x, o.pose.orientation.y,
                               o.pose.orientation.z);
    const Eigen::Isometry3d box_to_frame = Eigen::Translation3d(centre) * q;
    std::size_t points = 0, inside = 0;
    for (std::size_t i = 0; i < result.point_objects.size(); ++i) {
      if (result.point_objects[i] != o.index) continue;
      ++points;
      const Eigen::Vector3d local =
          box_to_frame.inverse() * cloud[i].getVector3fMap().cast<double>();
      inside += (local.cwiseAbs() - 0.5 * dims).maxCoeff() <= 1e-4;
    }
    EXPECT_EQ(points, o.num_points);
    EXPECT_GE(inside, 0.99 * static_cast<double>(points)) << "object " << o.index;
  }
}

TEST(ObjectConversion, EachObjectGetsABoxAndItsIndexInRViz) {
  hope::StandingObject flat = tallBox();
  flat.index = 3;
  flat.box_size.z() = 0.0;  // RViz draws nothing for a zero scale
  visualization_msgs::MarkerArray markers;
  hope_ros::appendObjectMarkers({tallBox(), flat}, std_msgs::Header(), markers);
  ASSERT_EQ(markers.markers.size(), 4u);
  const auto& box = markers.markers[0];
  EXPECT_EQ(box.type, visualization_msgs::Marker::CUBE);
  EXPECT_EQ(box.ns, "objects");
  EXPECT_EQ(box.id, 2);
  EXPECT_DOUBLE_EQ(box.scale.x, 0.2);
  EXPECT_DOUBLE_EQ(box.scale.z, 0.3);
  EXPECT_EQ(markers.markers[1].type, visualization_msgs::Marker::TEXT_VIEW_FACING);
  EXPECT_EQ(markers.markers[1].text, "o2");
  EXPECT_GT(markers.markers[1].pose.position.z, 0.9 + 0.15);  // above the box's top
  EXPECT_GT(markers.markers[2].scale.z, 0.0);
  EXPECT_EQ(markers.markers[3].text, "o3");
}

TEST(ObjectConversion, APlacementRequestNamesWhatIsWrong) {
  std::vector<hope::HorizontalPlane> planes(2);
  planes[0].id = 4;
  planes[1].id = 9;
  hope::FindPlacement::Request request;
  request.width = 0.1;
  request.depth = 0.2;
  request.clearance = 0.03;
  request.plane_id = -1;
  hope::PlacementQuery query;
  EXPECT_EQ(hope_ros::placementQuery(request, planes, query), "");
  EXPECT_EQ(query.plane_index, -1);
  EXPECT_EQ(query.max_results, 5u);  // 0 asks for the default
  EXPECT_DOUBLE_EQ(query.footprint.depth, 0.2);
  EXPECT_DOUBLE_EQ(query.footprint.clearance, 0.03);

  request.plane_id = 9;  // an id, not an index
  request.max_results = 2;
  EXPECT_EQ(hope_ros::placementQuery(request, planes, query), "");
  EXPECT_EQ(query.plane_index, 1);
  EXPECT_EQ(query.max_results, 2u);

  request.plane_id = 1;
  const std::string problem = hope_ros::placementQuery(request, planes, query);
  EXPECT_NE(problem.find("plane_id 1 is not a plane"), std::string::npos) << problem;
  EXPECT_NE(problem.find("4, 9"), std::string::npos) << problem;

  request.plane_id = -1;
  request.max_results = 100000;
  EXPECT_NE(hope_ros::placementQuery(request, planes, query).find("max_results"),
            std::string::npos);
}

TEST(ObjectConversion, APlacementPoseIsItsCentreTurnedByItsYaw) {
  hope::Placement p;
  p.plane_id = 5;
  p.centre = Eigen::Vector3d(1.5, -0.3, 0.75);
  p.yaw = M_PI / 2;
  p.margin = 0.07;
  const hope::PlacementPose m = hope_ros::toMessage(p);
  EXPECT_EQ(m.plane_id, 5);
  EXPECT_DOUBLE_EQ(m.pose.position.y, -0.3);
  EXPECT_NEAR(m.pose.orientation.z, std::sqrt(0.5), 1e-12);
  EXPECT_NEAR(m.pose.orientation.w, std::sqrt(0.5), 1e-12);
  EXPECT_DOUBLE_EQ(m.yaw, M_PI / 2);
  EXPECT_DOUBLE_EQ(m.margin, 0.07);
}

}  // namespace
