// Uses hope from its install space: the planes of a generated scene with a known answer (a
// floor and a table top), read through a PointCloud2 as a nodelet receives it, by the one-cloud
// extractor and by the frame pipeline over two frames (the ids kept), and hope's nodelet plugin
// loaded by pluginlib. Exit code 0 only if everything holds.
#include <cmath>
#include <cstdio>
#include <string>

#include <hope/extractor.h>
#include <hope/frame_pipeline.h>
#include <hope_ros/cloud_conversion.h>
#include <nodelet/nodelet.h>
#include <pluginlib/class_loader.hpp>

int main(int argc, char** argv) {
  const std::string prefix = argc > 1 ? argv[1] : "";
  // A 4 x 4 m floor at z = 0 and a 1 x 1 m table top at z = 0.75 over it, sampled every
  // 2 cm as seen from above (the floor under the table is hidden).
  pcl::PointCloud<pcl::PointXYZ> cloud;
  for (int i = 0; i < 200; ++i) {
    for (int j = 0; j < 200; ++j) {
      const float x = i * 0.02f, y = j * 0.02f;
      const bool on_table = x >= 1.5f && x < 2.5f && y >= 1.5f && y < 2.5f;
      cloud.push_back(pcl::PointXYZ(x, y, on_table ? 0.75f : 0.0f));
    }
  }
  std_msgs::Header header;
  header.frame_id = "map";
  const sensor_msgs::PointCloud2 message = hope_ros::cloudMessage(cloud, header);
  hope::PointsView view;
  const std::string error = hope_ros::viewOf(message, view);
  if (!error.empty()) {
    std::fprintf(stderr, "FAIL: viewOf: %s\n", error.c_str());
    return 1;
  }
  hope::Extractor extractor;
  const hope::Result result = extractor.extract(view, hope::Orientation::identity());
  bool floor = false, table = false;
  for (const hope::HorizontalPlane& plane : result.planes) {
    std::printf("plane %d at %.4f m, %zu points\n", plane.id, plane.height, plane.num_points);
    floor |= std::abs(plane.height) < 1e-3 && plane.num_points == 40000 - 2500;
    table |= std::abs(plane.height - 0.75) < 1e-3 && plane.num_points == 2500;
  }
  if (result.planes.size() != 2 || !floor || !table) {
    std::fprintf(stderr,
                 "FAIL: expected the floor (37500 points at 0 m) and the table top "
                 "(2500 points at 0.75 m)\n");
    return 1;
  }

  // The same scene twice through the frame pipeline: the same two planes, each keeping its id.
  hope::FramePipeline pipeline;
  const hope::Frame first = pipeline.process(view, 0.0, hope::Orientation::identity());
  const hope::Frame second = pipeline.process(view, 0.1, hope::Orientation::identity());
  bool ids_kept = first.result.planes.size() == 2 && second.result.planes.size() == 2;
  for (const hope::HorizontalPlane& before : first.result.planes) {
    for (const hope::HorizontalPlane& now : second.result.planes) {
      if (std::abs(before.height - now.height) < 1e-3) ids_kept &= before.id == now.id;
    }
  }
  if (!ids_kept) {
    std::fprintf(stderr, "FAIL: the frame pipeline should keep both planes' ids\n");
    return 1;
  }
  std::printf("frame pipeline: 2 planes, ids kept over 2 frames\n");

  pluginlib::ClassLoader<nodelet::Nodelet> loader("nodelet", "nodelet::Nodelet");
  const std::string name = "hope/PlaneExtractorNodelet";
  const std::string library = loader.getClassLibraryPath(name);
  auto instance = loader.createUniqueInstance(name);
  std::printf("pluginlib loaded %s from %s\n", name.c_str(), library.c_str());
  if (!instance || library.rfind(prefix, 0) != 0) {
    std::fprintf(stderr, "FAIL: the nodelet should come from %s\n", prefix.c_str());
    return 1;
  }
  std::printf("OK\n");
  return 0;
}
