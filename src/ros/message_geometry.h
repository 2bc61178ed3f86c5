// Small conversions shared by the message builders of src/ros (not installed).
#pragma once

#include <geometry_msgs/Point.h>
#include <geometry_msgs/Point32.h>
#include <std_msgs/ColorRGBA.h>
#include <Eigen/Core>

#include "hope/plane_colors.h"

namespace hope_ros {

// The colour of a plane's id (Pascal VOC palette), as RViz takes it.
inline std_msgs::ColorRGBA colorOf(int id, float alpha) {
  const hope::Rgb rgb = hope::planeColor(id);
  std_msgs::ColorRGBA c;
  c.r = rgb.r / 255.f;
  c.g = rgb.g / 255.f;
  c.b = rgb.b / 255.f;
  c.a = alpha;
  return c;
}

inline geometry_msgs::Point point(const Eigen::Vector3d& p) {
  geometry_msgs::Point q;
  q.x = p.x();
  q.y = p.y();
  q.z = p.z();
  return q;
}

inline geometry_msgs::Point32 point32(const Eigen::Vector3d& p) {
  geometry_msgs::Point32 q;
  q.x = static_cast<float>(p.x());
  q.y = static_cast<float>(p.y());
  q.z = static_cast<float>(p.z());
  return q;
}

}  // namespace hope_ros
