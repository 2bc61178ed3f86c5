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

sensor_msgs::PointCloud2 selectedPoints(const sensor_msgs::PointCloud2& cloud,
                                        const std::vector<std::uint32_t>& indices) {
  const sensor_msgs::PointField* colour = nullptr;
  std::uint32_t x = 0, y = 0, z = 0;
  for (const sensor_msgs::PointField& f : cloud.fields) {
    if (f.name == "x") x = f.offset;
    if (f.name == "y") y = f.offset;
    if (f.name == "z") z = f.offset;
    const bool four_bytes = f.datatype == sensor_msgs::PointField::FLOAT32 ||
                            f.datatype == sensor_msgs::PointField::UINT32;
    if ((f.name == "rgb" || f.name == "rgba") && four_bytes && f.count == 1) colour = &f;
  }
  sensor_msgs::PointCloud2 out;
  out.header = cloud.header;
  out.height = 1;
  out.width = static_cast<std::uint32_t>(indices.size());
  out.is_bigendian = false;
  out.is_dense = true;  // non-finite points are never selected
  std::uint32_t offset = 0;
  for (const char* name : {"x", "y", "z"}) {
    sensor_msgs::PointField f;
    f.name = name;
    f.offset = offset;
    f.datatype = sensor_msgs::PointField::FLOAT32;
    f.count = 1;
    out.fields.push_back(f);
    offset += 4;
  }
  if (colour) {
    sensor_msgs::PointField f = *colour;
    f.offset = offset;
    out.fields.push_back(f);
    offset += 4;
  }
  out.point_step = offset;
  out.row_step = out.point_step * out.width;
  out.data.resize(out.row_step);
  // viewOf refuses padded rows: point i starts i · point_step bytes in.
  std::uint8_t* to = out.data.data();
  for (std::uint32_t i : indices) {
    const std::uint8_t* from = cloud.data.data() + std::size_t{i} * cloud.point_step;
    std::memcpy(to, from + x, 4);
    std::memcpy(to + 4, from + y, 4);
    std::memcpy(to + 8, from + z, 4);
    if (colour) std::memcpy(to + 12, from + colour->offset, 4);
    to += out.point_step;
  }
  return out;
}

nav_msgs::OccupancyGrid toMessage(const hope::FloorGrid& grid, const std_msgs::Header& header) {
  nav_msgs::OccupancyGrid msg;
  msg.header = header;
  msg.info.map_load_time = header.stamp;
  msg.info.resolution = static_cast<float>(grid.resolution);
  msg.info.width = static_cast<std::uint32_t>(grid.width);
  msg.info.height = static_cast<std::uint32_t>(grid.height);
  msg.info.origin.position.x = grid.origin.x();
  msg.info.origin.position.y = grid.origin.y();
  msg.info.origin.position.z = grid.floor_height;
  msg.info.origin.orientation.w = 1.0;
  msg.data.assign(grid.cells.begin(), grid.cells.end());
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
    m.surface_id = p.surface_id;
    m.height = p.height;
    m.x_min = p.bbox[0];
    m.y_min = p.bbox[1];
    m.x_max = p.bbox[2];
    m.y_max = p.bbox[3];
    m.centroid = point(p.centroid);
    m.normal.x = p.normal.x();
    m.normal.y = p.normal.y();
    m.normal.z = p.normal.z();
    // a x + b y + c z + d = 0 through the centroid: d = -n . centroid.
    m.coef.coef = {p.normal.x(), p.normal.y(), p.normal.z(), -p.normal.dot(p.centroid)};
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

}  // namespace hope_ros
