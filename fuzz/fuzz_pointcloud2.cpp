// libFuzzer target: a PointCloud2 as the nodelet receives it (header fields and data from the
// fuzzer) → the in-place reader → the whole pipeline and the three outputs. Whatever the
// message says, the reader refuses it with a reason or the pipeline runs within its bounds.
#include <cstdint>
#include <cstring>
#include <stdexcept>

#include "fuzz_input.h"
#include "hope/extractor.h"
#include "hope_ros/cloud_conversion.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  hope::fuzz::Input in(data, size);
  sensor_msgs::PointCloud2 msg;
  msg.width = in.take<std::uint32_t>();
  msg.height = in.take<std::uint32_t>();
  msg.point_step = in.take<std::uint32_t>();
  msg.row_step = in.take<std::uint32_t>();
  msg.is_bigendian = in.take<std::uint8_t>() & 1;
  const int num_fields = in.take<std::uint8_t>() % 6;
  const char* names[6] = {"x", "y", "z", "rgb", "x", "label"};
  for (int f = 0; f < num_fields; ++f) {
    sensor_msgs::PointField field;
    field.name = names[f];
    field.offset = in.take<std::uint32_t>();
    field.datatype = in.take<std::uint8_t>();
    field.count = in.take<std::uint32_t>();
    msg.fields.push_back(field);
  }
  msg.data = in.rest();

  hope::PointsView view;
  if (!hope_ros::viewOf(msg, view).empty()) return 0;  // refused, with a reason
  try {
    hope::Extractor extractor;
    const hope::Result result = extractor.extract(view, hope::Orientation::identity());
    std_msgs::Header header;
    hope_ros::toMessage(result, header);
    hope_ros::labeledCloud(extractor.alignedPoints(), result, view, header);
    hope_ros::planeMarkers(result, header);
  } catch (const std::invalid_argument&) {
    // a cloud that cannot be a scene in metres: the nodelet warns and skips it
  }
  return 0;
}
