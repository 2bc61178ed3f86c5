#include "hope_ros/object_conversion.h"

#include <cmath>
#include <cstdio>
#include <cstring>
#include <stdexcept>

#include <sensor_msgs/point_cloud2_iterator.h>

#include "hope_ros/cloud_conversion.h"

namespace hope_ros {

namespace {

constexpr double kDefaultTimeout = 5.0, kMaxTimeout = 300.0;

std::string metres(double value) {
  char text[32];
  std::snprintf(text, sizeof(text), "%.2f", value);
  return text;
}

bool finite(const geometry_msgs::Point& p) {
  return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z);
}

bool inBand(const hope::Segment::Request& request, double height) {
  return !request.limit_height || (height >= request.min_height && height <= request.max_height);
}

// The plane's x y box at its height meets the request's box.
bool meetsBox(const hope::Segment::Request& request, const hope::HorizontalPlane& plane) {
  if (!request.limit_box) return true;
  const auto& lo = request.box_min;
  const auto& hi = request.box_max;
  return plane.bbox[0] <= hi.x && plane.bbox[2] >= lo.x && plane.bbox[1] <= hi.y &&
         plane.bbox[3] >= lo.y && plane.height >= lo.z && plane.height <= hi.z;
}

bool inBox(const hope::Segment::Request& request, const Eigen::Vector3d& p) {
  if (!request.limit_box) return true;
  const auto& lo = request.box_min;
  const auto& hi = request.box_max;
  return p.x() >= lo.x && p.x() <= hi.x && p.y() >= lo.y && p.y() <= hi.y && p.z() >= lo.z &&
         p.z() <= hi.z;
}

std::string describeLimits(const hope::Segment::Request& request) {
  std::string text;
  if (request.limit_height) {
    text += "between " + metres(request.min_height) + " and " + metres(request.max_height) + " m";
  }
  if (request.limit_box) {
    if (!text.empty()) text += " and ";
    const auto& lo = request.box_min;
    const auto& hi = request.box_max;
    text += "in the box (" + metres(lo.x) + ", " + metres(lo.y) + ", " + metres(lo.z) + ") to (" +
            metres(hi.x) + ", " + metres(hi.y) + ", " + metres(hi.z) + ")";
  }
  return text;
}

}  // namespace

sensor_msgs::PointCloud2 referencePoints(const std::vector<Eigen::Vector3f>& points,
                                         const Eigen::Vector3d& local_origin,
                                         const std::vector<std::uint32_t>& indices,
                                         const std_msgs::Header& header) {
  sensor_msgs::PointCloud2 cloud;
  cloud.header = header;
  sensor_msgs::PointCloud2Modifier modifier(cloud);
  modifier.setPointCloud2FieldsByString(1, "xyz");
  modifier.resize(indices.size());
  cloud.height = 1;
  cloud.width = static_cast<std::uint32_t>(indices.size());
  cloud.is_dense = true;
  sensor_msgs::PointCloud2Iterator<float> x(cloud, "x"), y(cloud, "y"), z(cloud, "z");
  for (const std::uint32_t i : indices) {
    if (i >= points.size()) {
      throw std::invalid_argument("point index " + std::to_string(i) + " past the " +
                                  std::to_string(points.size()) + " kept points");
    }
    const Eigen::Vector3d p = points[i].cast<double>() + local_origin;
    *x = static_cast<float>(p.x());
    *y = static_cast<float>(p.y());
    *z = static_cast<float>(p.z());
    ++x;
    ++y;
    ++z;
  }
  return cloud;
}

std::vector<std::vector<std::uint32_t>> pointsOfObjects(const hope::Result& result) {
  std::vector<std::vector<std::uint32_t>> groups(result.objects.size());
  for (std::size_t i = 0; i < result.point_objects.size(); ++i) {
    const std::int32_t o = result.point_objects[i];
    if (o >= 0 && static_cast<std::size_t>(o) < groups.size()) {
      groups[o].push_back(static_cast<std::uint32_t>(i));
    }
  }
  return groups;
}

void attachObjectPoints(const hope::Frame& frame, hope::ObjectArray& objects) {
  const hope::Result& result = frame.result;
  if (objects.objects.size() != result.objects.size()) {
    throw std::invalid_argument("the objects are not the frame's");
  }
  if (!result.objects.empty() && frame.points.empty()) {
    throw std::invalid_argument("the frame kept no points (FrameOutputs::keep_points)");
  }
  const auto groups = pointsOfObjects(result);
  for (std::size_t k = 0; k < groups.size(); ++k) {
    objects.objects[k].points =
        referencePoints(frame.points, result.local_origin, groups[k], objects.header);
  }
}

std::string checkSegmentRequest(const hope::Segment::Request& request) {
  if (!(std::isfinite(request.timeout) && request.timeout >= 0 && request.timeout <= kMaxTimeout)) {
    return "timeout must be in [0, 300] s, 0 meaning 5 (got " + std::to_string(request.timeout) +
           ")";
  }
  if (request.limit_height &&
      !(std::isfinite(request.min_height) && std::isfinite(request.max_height) &&
        request.min_height <= request.max_height)) {
    return "limit_height: min_height must be finite and at most max_height (got " +
           std::to_string(request.min_height) + " and " + std::to_string(request.max_height) + ")";
  }
  if (request.limit_box &&
      !(finite(request.box_min) && finite(request.box_max) &&
        request.box_min.x <= request.box_max.x && request.box_min.y <= request.box_max.y &&
        request.box_min.z <= request.box_max.z)) {
    const auto& lo = request.box_min;
    const auto& hi = request.box_max;
    return "limit_box: box_min must be finite and at most box_max in x, y and z (got (" +
           std::to_string(lo.x) + ", " + std::to_string(lo.y) + ", " + std::to_string(lo.z) +
           ") and (" + std::to_string(hi.x) + ", " + std::to_string(hi.y) + ", " +
           std::to_string(hi.z) + "))";
  }
  return "";
}

double segmentTimeout(const hope::Segment::Request& request) {
  return request.timeout > 0 ? request.timeout : kDefaultTimeout;
}

hope::Segment::Response segmentAnswer(const hope::Segment::Request& request,
                                      const hope::Frame& frame, const std_msgs::Header& header) {
  hope::Segment::Response response;
  response.header = header;
  const hope::Result& result = frame.result;
  const hope::PlaneArray planes = toMessage(result, header);
  std::vector<bool> answered(result.planes.size(), false);
  for (std::size_t i = 0; i < result.planes.size(); ++i) {
    const hope::HorizontalPlane& p = result.planes[i];
    answered[i] = inBand(request, p.height) && meetsBox(request, p);
  }
  // Each answered plane's points, from one pass over the labels.
  std::vector<std::vector<std::uint32_t>> plane_indices(result.planes.size());
  for (std::size_t k = 0; k < result.point_labels.size(); ++k) {
    const std::int32_t label = result.point_labels[k];
    if (label >= 0 && static_cast<std::size_t>(label) < answered.size() && answered[label]) {
      plane_indices[label].push_back(static_cast<std::uint32_t>(k));
    }
  }
  for (std::size_t i = 0; i < result.planes.size(); ++i) {
    if (!answered[i]) continue;
    response.planes.push_back(planes.planes[i]);
    response.plane_points.push_back(
        referencePoints(frame.points, result.local_origin, plane_indices[i], header));
  }
  if (response.planes.empty()) {
    std::string heights;
    for (const hope::HorizontalPlane& p : result.planes) {
      heights += (heights.empty() ? "" : ", ") + metres(p.height);
    }
    response.success = false;
    const std::string limits = describeLimits(request);
    response.message = "no plane " + (limits.empty() ? "" : limits + " ") + "in the cloud of " +
                       std::to_string(header.stamp.toSec()) + " s" +
                       (heights.empty() ? " (it had none)" : " (its planes: " + heights + " m)");
    response.plane_points.clear();
    return response;
  }
  hope::ObjectArray objects = toMessage(result.objects, header);
  if (!result.objects.empty()) attachObjectPoints(frame, objects);
  for (std::size_t k = 0; k < result.objects.size(); ++k) {
    const hope::StandingObject& o = result.objects[k];
    const bool on_answered = o.plane_index >= 0 &&
                             static_cast<std::size_t>(o.plane_index) < answered.size() &&
                             answered[o.plane_index];
    if (on_answered && inBox(request, o.centroid)) {
      response.objects.push_back(std::move(objects.objects[k]));
    }
  }
  response.success = true;
  return response;
}

}  // namespace hope_ros
