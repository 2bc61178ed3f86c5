// Objects and placements as messages (no ROS master needed): boxes turned about z, the marker
// per object, and ~find_placement's request checked before anything is searched.
#include <cmath>

#include <gtest/gtest.h>

#include "hope_ros/object_conversion.h"

namespace {

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
  EXPECT_DOUBLE_EQ(o.center.position.z, 0.9);
  // A turn of π/3 about z: (0, 0, sin π/6, cos π/6).
  EXPECT_NEAR(o.center.orientation.x, 0.0, 1e-12);
  EXPECT_NEAR(o.center.orientation.y, 0.0, 1e-12);
  EXPECT_NEAR(o.center.orientation.z, 0.5, 1e-12);
  EXPECT_NEAR(o.center.orientation.w, std::sqrt(3.0) / 2, 1e-12);
  EXPECT_DOUBLE_EQ(o.size.x, 0.2);
  EXPECT_DOUBLE_EQ(o.size.y, 0.1);
  EXPECT_DOUBLE_EQ(o.size.z, 0.3);
  EXPECT_DOUBLE_EQ(o.height, 0.3);
  ASSERT_EQ(o.footprint.points.size(), 4u);
  EXPECT_FLOAT_EQ(o.footprint.points[2].x, 1.1f);
  EXPECT_FLOAT_EQ(o.footprint.points[2].z, 0.75f);
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
