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

const sensor_msgs::PointField* field(const sensor_msgs::PointCloud2& cloud, const char* name) {
  for (const auto& f : cloud.fields)
    if (f.name == name) return &f;
  return nullptr;
}

}  // namespace

std::string viewOf(const sensor_msgs::PointCloud2& cloud, hope::PointsView& view) {
  // Every size below comes from the message: the arithmetic is 64-bit (the header's fields are
  // 32-bit, so sums and products of two of them cannot wrap) and the one product of three is
  // checked, so a hostile header cannot make a bounds check pass by overflow.
  const std::uint64_t point_step = cloud.point_step;
  const char* names[3] = {"x", "y", "z"};
  std::size_t offsets[3];
  for (int k = 0; k < 3; ++k) {
    const sensor_msgs::PointField* f = field(cloud, names[k]);
    if (!f) return std::string("the cloud has no '") + names[k] + "' field";
    if (f->datatype != sensor_msgs::PointField::FLOAT32 || f->count != 1) {
      return std::string("field '") + names[k] + "' is not a single float32 (datatype " +
             std::to_string(f->datatype) + ", count " + std::to_string(f->count) + ")";
    }
    if (std::uint64_t(f->offset) + sizeof(float) > point_step) {
      return std::string("field '") + names[k] + "' (offset " + std::to_string(f->offset) +
             ") lies outside point_step " + std::to_string(point_step);
    }
    offsets[k] = f->offset;
  }
  if (cloud.is_bigendian) return "big-endian clouds are not supported";
  const std::uint64_t count = std::uint64_t(cloud.width) * cloud.height;
  if (count > 0 && std::uint64_t(cloud.row_step) != std::uint64_t(cloud.width) * point_step) {
    return "rows are padded or row_step is wrong (row_step " + std::to_string(cloud.row_step) +
           " != width " + std::to_string(cloud.width) + " x point_step " +
           std::to_string(point_step) + ")";
  }
  // row_step == width · point_step fits in 32 bits here, so height · row_step fits in 64.
  const std::uint64_t needed = count > 0 ? std::uint64_t(cloud.height) * cloud.row_step : 0;
  if (cloud.data.size() < needed) {
    return "the data holds " + std::to_string(cloud.data.size()) + " bytes, the header (width " +
           std::to_string(cloud.width) + ", height " + std::to_string(cloud.height) +
           ", point_step " + std::to_string(point_step) + ") says " + std::to_string(needed);
  }
  view = hope::PointsView();
  view.data = cloud.data.empty() ? nullptr : cloud.data.data();
  view.count = static_cast<std::size_t>(count);
  view.stride = static_cast<std::size_t>(point_step);
  view.x_offset = offsets[0];
  view.y_offset = offsets[1];
  view.z_offset = offsets[2];
  view.width = cloud.width;
  view.height = cloud.height;
  return "";
}

sensor_msgs::PointCloud2 cloudMessage(const pcl::PointCloud<pcl::PointXYZ>& cloud,
                                      const std_msgs::Header& header) {
  sensor_msgs::PointCloud2 msg;
  msg.header = header;
  msg.width = cloud.width;
  msg.height = cloud.height;
  const char* names[3] = {"x", "y", "z"};
  for (std::uint32_t k = 0; k < 3; ++k) {
    sensor_msgs::PointField f;
    f.name = names[k];
    f.offset = 4 * k;
    f.datatype = sensor_msgs::PointField::FLOAT32;
    f.count = 1;
    msg.fields.push_back(f);
  }
  msg.point_step = sizeof(pcl::PointXYZ);  // x y z and padding
  msg.row_step = msg.point_step * msg.width;
  msg.is_dense = false;
  msg.data.resize(static_cast<std::size_t>(msg.point_step) * cloud.size());
  if (!cloud.empty()) std::memcpy(msg.data.data(), cloud.points.data(), msg.data.size());
  return msg;
}

hope::PlaneArray toMessage(const hope::Result& result, const std_msgs::Header& header) {
  hope::PlaneArray msg;
  msg.header = header;
  msg.processing_ms = result.timings.total_ms;
  for (const hope::HorizontalPlane& p : result.planes) {
    hope::Plane m;
    m.id = p.id;
    m.age = p.age;
    m.last_seen = header.stamp;
    m.split_from = p.split_from;
    m.height = p.height;
    m.x_min = p.bbox[0];
    m.y_min = p.bbox[1];
    m.x_max = p.bbox[2];
    m.y_max = p.bbox[3];
    m.centroid = point(p.centroid);
    m.normal.x = p.normal.x();
    m.normal.y = p.normal.y();
    m.normal.z = p.normal.z();
    m.tilt = p.tilt;
    m.area = p.area;
    m.num_points = static_cast<std::uint32_t>(p.num_points);
    m.num_parts = p.num_parts;
    m.facing = p.facing == hope::Facing::kUp     ? hope::Plane::FACING_UP
               : p.facing == hope::Facing::kDown ? hope::Plane::FACING_DOWN
                                                 : hope::Plane::FACING_UNKNOWN;
    for (const auto& h : p.hull) m.hull.points.push_back(point32(h));
    for (const auto& ring : p.outline) {
      m.outline.emplace_back();
      for (const auto& q : ring) m.outline.back().points.push_back(point32(q));
    }
    msg.planes.push_back(m);
  }
  return msg;
}

sensor_msgs::PointCloud2 labeledCloud(const hope::AlignedPoints& aligned,
                                      const hope::Result& result, const hope::PointsView& input,
                                      const std_msgs::Header& header) {
  sensor_msgs::PointCloud2 out;
  fillLabeledCloud(aligned, result, input, header, out);
  return out;
}

void fillLabeledCloud(const hope::AlignedPoints& aligned, const hope::Result& result,
                      const hope::PointsView& input, const std_msgs::Header& header,
                      sensor_msgs::PointCloud2& out) {
  out.header = header;
  out.fields.clear();
  out.width = input.width;
  out.height = input.height;
  const char* names[6] = {"x", "y", "z", "rgb", "label", "object"};
  for (std::uint32_t k = 0; k < 6; ++k) {
    sensor_msgs::PointField f;
    f.name = names[k];
    f.offset = 4 * k;
    f.datatype = k >= 4 ? sensor_msgs::PointField::UINT32 : sensor_msgs::PointField::FLOAT32;
    f.count = 1;
    out.fields.push_back(f);
  }
  out.point_step = kLabeledPointStep;
  out.row_step = out.point_step * out.width;
  out.is_dense = false;
  // Every byte is written below: a buffer of the right size is reused as it is.
  out.data.resize(static_cast<std::size_t>(out.point_step) * aligned.size());
  // The colour and label of each plane index once, not per point: entry 0 is "on no plane"
  // (grey, label 0), entry k + 1 plane k (its id's colour, label id + 1).
  std::vector<std::array<std::uint32_t, 2>> rgb_and_label(result.planes.size() + 1);
  rgb_and_label[0] = {hope::packRgb({128, 128, 128}), 0u};
  for (std::size_t k = 0; k < result.planes.size(); ++k) {
    const int id = result.planes[k].id;
    rgb_and_label[k + 1] = {hope::packRgb(hope::planeColor(id)),
                            static_cast<std::uint32_t>(id + 1)};
  }
  // Aligned points are relative to the local origin (zero unless the sensor is far out).
  const Eigen::Vector3f origin = result.local_origin.cast<float>();
  const std::size_t labelled = std::min(aligned.size(), result.point_labels.size());
  // Plain pointers in locals: stores through a byte pointer may alias anything, so through the
  // containers the compiler would reload every pointer and size after each point.
  const std::uint8_t* source = aligned.data;
  const std::size_t source_stride = aligned.stride;
  const std::int32_t* labels = result.point_labels.data();
  // Objects only when they were asked for (ExtractOutputs::objects): 0 everywhere otherwise.
  const std::size_t with_objects = std::min(aligned.size(), result.point_objects.size());
  const std::int32_t* objects = result.point_objects.data();
  const std::array<std::uint32_t, 2>* table = rgb_and_label.data();
  std::uint8_t* target = out.data.data();
  const float ox = origin.x(), oy = origin.y(), oz = origin.z();
  const std::size_t num_points = aligned.size();
  // Each coordinate is copied on its own: through a float[3] the compiler passed every point
  // through the stack.
  for (std::size_t i = 0; i < num_points; ++i) {
    const std::uint8_t* point = source + i * source_stride;
    float x, y, z;
    std::memcpy(&x, point, sizeof(x));
    std::memcpy(&y, point + 4, sizeof(y));
    std::memcpy(&z, point + 8, sizeof(z));
    x += ox, y += oy, z += oz;
    std::uint8_t* record = target + kLabeledPointStep * i;
    std::memcpy(record, &x, sizeof(x));
    std::memcpy(record + 4, &y, sizeof(y));
    std::memcpy(record + 8, &z, sizeof(z));
    const int index = i < labelled ? labels[i] : -1;
    std::memcpy(record + 12, table[static_cast<std::size_t>(index + 1)].data(), 8);
    const std::uint32_t object = i < with_objects ? static_cast<std::uint32_t>(objects[i] + 1) : 0u;
    std::memcpy(record + 20, &object, sizeof(object));
  }
}

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
