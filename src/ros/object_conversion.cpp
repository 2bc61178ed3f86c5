#include "hope_ros/object_conversion.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "message_geometry.h"

namespace hope_ros {

namespace {

// A rotation by `yaw` about z.
geometry_msgs::Quaternion aboutZ(double yaw) {
  geometry_msgs::Quaternion q;
  q.z = std::sin(0.5 * yaw);
  q.w = std::cos(0.5 * yaw);
  return q;
}

}  // namespace

hope::ObjectArray toMessage(const std::vector<hope::StandingObject>& objects,
                            const std_msgs::Header& header) {
  hope::ObjectArray msg;
  msg.header = header;
  msg.objects.reserve(objects.size());
  for (const hope::StandingObject& o : objects) {
    hope::Object m;
    m.index = o.index;
    m.plane_id = o.plane_id;
    m.pose.position = point(o.box_centre);
    m.pose.orientation = aboutZ(o.yaw);
    m.box.type = shape_msgs::SolidPrimitive::BOX;
    m.box.dimensions.resize(3);
    m.box.dimensions[shape_msgs::SolidPrimitive::BOX_X] = o.box_size.x();
    m.box.dimensions[shape_msgs::SolidPrimitive::BOX_Y] = o.box_size.y();
    m.box.dimensions[shape_msgs::SolidPrimitive::BOX_Z] = o.box_size.z();
    m.centroid = point(o.centroid);
    m.footprint.points.reserve(o.footprint.size());
    for (const Eigen::Vector3d& p : o.footprint) m.footprint.points.push_back(point32(p));
    m.height = o.height;
    m.num_points = static_cast<std::uint32_t>(o.num_points);
    msg.objects.push_back(std::move(m));
  }
  return msg;
}

void appendObjectMarkers(const std::vector<hope::StandingObject>& objects,
                         const std_msgs::Header& header, visualization_msgs::MarkerArray& markers) {
  for (const hope::StandingObject& o : objects) {
    visualization_msgs::Marker box;
    box.header = header;
    box.ns = "objects";
    box.id = o.index;
    box.action = visualization_msgs::Marker::ADD;
    box.type = visualization_msgs::Marker::CUBE;
    box.pose.position = point(o.box_centre);
    box.pose.orientation = aboutZ(o.yaw);
    // RViz draws nothing for a zero scale: a flat object still gets a visible box.
    box.scale.x = std::max(o.box_size.x(), 0.005);
    box.scale.y = std::max(o.box_size.y(), 0.005);
    box.scale.z = std::max(o.box_size.z(), 0.005);
    box.color = colorOf(o.plane_id, 0.35f);  // see-through: the object's points show inside
    markers.markers.push_back(box);
    visualization_msgs::Marker text;
    text.header = header;
    text.ns = "object_ids";
    text.id = o.index;
    text.action = visualization_msgs::Marker::ADD;
    text.type = visualization_msgs::Marker::TEXT_VIEW_FACING;
    text.pose.position = point(o.box_centre);
    text.pose.position.z += 0.5 * o.box_size.z() + 0.04;
    text.pose.orientation.w = 1.0;
    text.scale.z = 0.06;
    text.color.r = text.color.g = text.color.b = text.color.a = 1.0f;
    char label[32];
    std::snprintf(label, sizeof(label), "o%d", o.index);
    text.text = label;
    markers.markers.push_back(text);
  }
}

std::string placementQuery(const hope::FindPlacement::Request& request,
                           const std::vector<hope::HorizontalPlane>& planes,
                           hope::PlacementQuery& query) {
  query = hope::PlacementQuery();
  query.footprint.width = request.width;
  query.footprint.depth = request.depth;
  query.footprint.clearance = request.clearance;
  query.max_results = request.max_results == 0 ? 5 : request.max_results;
  if (query.max_results > 1000) {
    return "max_results " + std::to_string(request.max_results) + " is outside [0, 1000]";
  }
  if (request.plane_id == -1) return "";
  for (std::size_t k = 0; k < planes.size(); ++k) {
    if (planes[k].id == request.plane_id) {
      query.plane_index = static_cast<int>(k);
      return "";
    }
  }
  std::string ids;
  for (const auto& p : planes) ids += (ids.empty() ? "" : ", ") + std::to_string(p.id);
  return "plane_id " + std::to_string(request.plane_id) +
         " is not a plane of the last frame (its planes: " + (ids.empty() ? "none" : ids) +
         "; -1 searches them all)";
}

hope::PlacementPose toMessage(const hope::Placement& placement) {
  hope::PlacementPose m;
  m.plane_id = placement.plane_id;
  m.pose.position = point(placement.centre);
  m.pose.orientation = aboutZ(placement.yaw);
  m.yaw = placement.yaw;
  m.margin = placement.margin;
  return m;
}

}  // namespace hope_ros
