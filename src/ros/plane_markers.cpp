// RViz markers of the planes: fills, outlines and "id: height" labels where they can be seen.
#include "hope_ros/cloud_conversion.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstring>

#include "hope/plane_colors.h"
#include "message_geometry.h"

namespace hope_ros {

namespace {

std::string labelOf(const hope::HorizontalPlane& p) {
  // "id: height": RViz's font has no middle dot.
  char label[64];
  std::snprintf(label, sizeof(label), "%d: %.2f m", p.id, p.height);
  return label;
}

}  // namespace

namespace {

// Whether a higher plane's box covers `xy`: its fill would hide a label there from above.
bool underAHigherPlane(const std::vector<hope::HorizontalPlane>& planes, std::size_t k,
                       const Eigen::Vector2d& xy) {
  for (std::size_t q = 0; q < planes.size(); ++q) {
    const hope::HorizontalPlane& other = planes[q];
    if (q == k || other.height <= planes[k].height + 0.05) continue;
    if (xy.x() >= other.bbox[0] && xy.x() <= other.bbox[2] && xy.y() >= other.bbox[1] &&
        xy.y() <= other.bbox[3]) {
      return true;
    }
  }
  return false;
}

// Where a plane's label goes in x and y: its centroid, unless a higher plane covers it (the
// floor under a table), then the first of its hull's corners, drawn a third of the way in,
// that no higher plane covers (a part of the floor in the open).
Eigen::Vector2d labelAnchor(const std::vector<hope::HorizontalPlane>& planes, std::size_t k) {
  const hope::HorizontalPlane& p = planes[k];
  const Eigen::Vector2d centre = p.centroid.head<2>();
  if (!underAHigherPlane(planes, k, centre)) return centre;
  for (const Eigen::Vector3d& corner : p.hull) {
    const Eigen::Vector2d inside = corner.head<2>() + (centre - corner.head<2>()) / 3.0;
    if (!underAHigherPlane(planes, k, inside)) return inside;
  }
  return centre;
}

}  // namespace

std::vector<Eigen::Vector3d> labelPositions(const std::vector<hope::HorizontalPlane>& planes) {
  // The text faces the camera: seen from the side its lower half reaches half a text height
  // below its centre, so the centre goes that and a margin above the plane.
  constexpr double kLift = 0.5 * kLabelHeight + 0.04;
  // Two labels may overlap on screen when their texts come closer horizontally than half
  // their widths added, from the side; from above at a slant, labels one behind the other
  // meet on screen further apart, so 1.5 times that counts as near. Then one goes two text
  // heights above the other, which parts them on screen from a view 60 degrees down (RViz's
  // default is 43).
  constexpr double kNearFactor = 1.5;
  constexpr double kRowHeight = 2 * kLabelHeight;
  std::vector<std::size_t> order(planes.size());
  for (std::size_t k = 0; k < order.size(); ++k) order[k] = k;
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t a, std::size_t b) { return planes[a].area > planes[b].area; });
  std::vector<Eigen::Vector3d> positions(planes.size());
  std::vector<double> half_widths(planes.size());
  std::vector<std::size_t> placed;
  for (std::size_t k : order) {
    const hope::HorizontalPlane& p = planes[k];
    half_widths[k] = 0.5 * kLabelCharWidth * static_cast<double>(labelOf(p).size());
    Eigen::Vector3d at;
    at << labelAnchor(planes, k), p.height + kLift;
    // Raise past every placed label it could cover; each raise may meet another one, so look
    // again until none is in the way (the height only grows: at most one raise per label).
    for (bool moved = true; moved;) {
      moved = false;
      for (std::size_t q : placed) {
        const bool near = (at.head<2>() - positions[q].head<2>()).norm() <
                          kNearFactor * (half_widths[k] + half_widths[q]);
        const double above = positions[q].z() + kRowHeight;
        // (above > at.z(): rounding must not make a raise to the same height look like one.)
        if (near && std::fabs(at.z() - positions[q].z()) < kRowHeight && above > at.z()) {
          at.z() = above;
          moved = true;
        }
      }
    }
    positions[k] = at;
    placed.push_back(k);
  }
  return positions;
}

std::optional<Eigen::Vector3d> sceneCentre(const std::vector<hope::HorizontalPlane>& planes) {
  if (planes.empty()) return std::nullopt;
  double x0 = planes[0].bbox[0], y0 = planes[0].bbox[1], x1 = planes[0].bbox[2],
         y1 = planes[0].bbox[3], z0 = planes[0].height, z1 = planes[0].height;
  for (const hope::HorizontalPlane& p : planes) {
    x0 = std::min(x0, p.bbox[0]);
    y0 = std::min(y0, p.bbox[1]);
    x1 = std::max(x1, p.bbox[2]);
    y1 = std::max(y1, p.bbox[3]);
    z0 = std::min(z0, p.height);
    z1 = std::max(z1, p.height);
  }
  return Eigen::Vector3d(0.5 * (x0 + x1), 0.5 * (y0 + y1), 0.5 * (z0 + z1));
}

visualization_msgs::MarkerArray planeMarkers(const hope::Result& result,
                                             const std_msgs::Header& header) {
  const std::vector<Eigen::Vector3d> label_at = labelPositions(result.planes);
  visualization_msgs::MarkerArray markers;
  visualization_msgs::Marker clear;
  clear.header = header;
  clear.ns = "hope";
  clear.action = visualization_msgs::Marker::DELETEALL;
  markers.markers.push_back(clear);
  for (std::size_t k = 0; k < result.planes.size(); ++k) {
    const hope::HorizontalPlane& p = result.planes[k];
    visualization_msgs::Marker base;
    base.header = header;
    base.ns = "hope";
    base.action = visualization_msgs::Marker::ADD;
    base.pose.orientation.w = 1.0;
    if (!p.outline.empty()) {
      // The occupied area, filled: horizontal strips between the outline's crossings (even-odd
      // over all rings, so holes stay open), two triangles each.
      visualization_msgs::Marker fill = base;
      fill.id = 3 * p.id;
      fill.type = visualization_msgs::Marker::TRIANGLE_LIST;
      fill.scale.x = fill.scale.y = fill.scale.z = 1.0;
      fill.color = colorOf(p.id, 0.5f);
      const double step = std::max((p.bbox[3] - p.bbox[1]) / 200.0, 0.005);
      std::vector<double> crossings;
      for (double y = p.bbox[1]; y < p.bbox[3]; y += step) {
        const double mid = y + 0.5 * step;
        crossings.clear();
        for (const auto& ring : p.outline) {
          for (std::size_t k = 0, prev = ring.size() - 1; k < ring.size(); prev = k++) {
            const Eigen::Vector3d& a = ring[k];
            const Eigen::Vector3d& b = ring[prev];
            if ((a.y() > mid) != (b.y() > mid)) {
              crossings.push_back(a.x() + (mid - a.y()) / (b.y() - a.y()) * (b.x() - a.x()));
            }
          }
        }
        std::sort(crossings.begin(), crossings.end());
        for (std::size_t k = 0; k + 1 < crossings.size(); k += 2) {
          const Eigen::Vector3d a(crossings[k], y, p.height), b(crossings[k + 1], y, p.height);
          const Eigen::Vector3d up(0, step, 0);
          for (const Eigen::Vector3d& q : {a, b, Eigen::Vector3d(b + up), a,
                                           Eigen::Vector3d(b + up), Eigen::Vector3d(a + up)}) {
            fill.points.push_back(point(q));
          }
        }
      }
      markers.markers.push_back(fill);
      visualization_msgs::Marker outline = base;
      outline.id = 3 * p.id + 1;
      outline.type = visualization_msgs::Marker::LINE_LIST;
      outline.scale.x = 0.01;
      outline.color = colorOf(p.id, 1.0f);
      for (const auto& ring : p.outline) {
        for (std::size_t k = 0; k < ring.size(); ++k) {
          outline.points.push_back(point(ring[k]));
          outline.points.push_back(point(ring[(k + 1) % ring.size()]));
        }
      }
      markers.markers.push_back(outline);
    }
    visualization_msgs::Marker text = base;
    text.id = 3 * p.id + 2;
    text.type = visualization_msgs::Marker::TEXT_VIEW_FACING;
    text.pose.position = point(label_at[k]);
    text.scale.z = kLabelHeight;
    text.color.r = text.color.g = text.color.b = text.color.a = 1.0f;  // readable on any plane
    text.text = labelOf(p);
    markers.markers.push_back(text);
  }
  return markers;
}

}  // namespace hope_ros
