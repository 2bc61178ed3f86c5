// hope_synth: renders synthetic scenes with an exact answer so that hope_extract can be tried
// without any dataset: one TUM-style depth/colour pair with its pose, or a whole moving-camera
// sequence in the TUM RGB-D folder layout.
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <iostream>
#include <sstream>
#include <stdexcept>
#include <string>

#include <pcl/io/pcd_io.h>
#include <pcl/point_types.h>

#include "hope/synthetic/lidar.h"
#include "hope/synthetic/scene.h"
#include "hope/synthetic/sequences.h"
#include "hope/tools/cli.h"
#include "hope/tools/io.h"
#include "hope/tools/output_file.h"

// A spinning LiDAR's point as drivers publish it, with the simulation's ground truth.
struct SyntheticLidarPoint {
  PCL_ADD_POINT4D;
  float intensity;
  std::uint16_t ring;
  std::int32_t label;  // ground-truth surface (see truth.txt), -1 none
  EIGEN_MAKE_ALIGNED_OPERATOR_NEW
} EIGEN_ALIGN16;
POINT_CLOUD_REGISTER_POINT_STRUCT(SyntheticLidarPoint,
                                  (float, x, x)(float, y, y)(float, z, z)(float, intensity,
                                                                          intensity)(
                                      std::uint16_t, ring, ring)(std::int32_t, label, label))

namespace {

// Every option of hope_synth, grouped as the help shows them.
hope::tools::CommandLine commandLine() {
  hope::tools::CommandLine cl(
      "hope_synth",
      {"--out DIR [--sequence NAME [--frames N] [--width W]]",
       "--out DIR --lidar MODEL [--scene street|room] [--unorganized]",
       "--out DIR --room-scan SPACING"},
      "Renders synthetic scenes with an exact answer so that hope_extract can be tried without "
      "any dataset. Without --sequence, --lidar or --room-scan: the demo room (floor, table, "
      "book, cabinet, two stair treads, a ramp, a ball, a cone, a tube) seen by a 640x480 depth "
      "camera with structured-light noise. Writes DIR/depth.png (16-bit, 5000 per metre), "
      "DIR/rgb.png, DIR/pose.txt (tx ty tz qx qy qz qw) and DIR/truth.txt (the planes to find).");
  cl.section("output").value("--out", "DIR", "the folder to write into (required)");
  cl.section("sequence",
             "a moving camera over floor, table, book, cabinet, stairs and the paper's pattern "
             "object, in the TUM RGB-D layout: depth/ rgb/ truth/ (ground-truth surface per "
             "pixel, 16-bit, label + 1), depth.txt, rgb.txt, groundtruth.txt, accelerometer.txt "
             "(optical frame, m/s^2, pointing up at rest) and intrinsics.txt (fx fy cx cy)")
      .value("--sequence", "NAME", "pan, rpy, shake, occlusion or leave_enter")
      .value("--frames", "N", "N frames at 30 Hz (default 60)")
      .value("--width", "W", "W pixels wide (default 640; intrinsics scaled)");
  cl.section("LiDAR scan",
             "one revolution of a spinning LiDAR over a street (road, 12 cm kerb and sidewalk, a "
             "1.2 m loading platform, a parked car, a bench, a 2° driveway, a 25° ramp; the "
             "sensor 1.8 m up) or a room (floor, table, two boards, ceiling; 1.2 m up), range "
             "noise 2 cm. Writes DIR/scan.pcd in the sensor's frame (z up): x y z intensity ring "
             "label, organized rings x azimuth steps with NaN where a beam returned nothing, and "
             "DIR/truth.txt (the surfaces and their heights in that frame). Try:\n"
             "  hope_extract --input DIR/scan.pcd --viewpoint \"0 0 0\" --r-xy 0.3 --r-z 0.1")
      .value("--lidar", "MODEL", "vlp16, hdl64 or os128")
      .value("--scene", "NAME", "street (default) or room")
      .flag("--unorganized", "the returns only, not rings x azimuth steps");
  cl.section("room scan",
             "the demo room scanned straight from above every SPACING over 6 x 6 m, 2 mm height "
             "noise, z up, unorganized. Writes DIR/room_scan.pcd (x y z, binary). For speed and "
             "memory on a large cloud:\n"
             "  /usr/bin/time -v hope_extract --input DIR/room_scan.pcd --repeat 5")
      .value("--room-scan", "SPACING",
             "metres (0.00245: the 6.0 M points of hope_benchmark's large cloud)");
  return cl;
}

// Every file complete or absent (output_file.h), as hope_extract's outputs.
void writeImage(const std::string& path, const cv::Mat& image) {
  hope::tools::OutputFile file(path);
  hope::tools::writeImage(file, image);
  file.commit();
}

void writeTextFile(const std::string& path, const std::string& text) {
  hope::tools::OutputFile file(path);
  hope::tools::writeText(file, [&](std::ostream& out) { out << text; });
  file.commit();
}

cv::Mat depthTo16Bit(const cv::Mat& depth) {
  cv::Mat depth16(depth.size(), CV_16UC1);
  depth.convertTo(depth16, CV_16UC1, 5000.0);  // TUM scale; saturates beyond 13 m
  return depth16;
}

std::string poseText(const Eigen::Isometry3d& pose) {
  const Eigen::Quaterniond q(pose.linear());
  const Eigen::Vector3d t = pose.translation();
  char text[200];
  std::snprintf(text, sizeof(text), "%.6f %.6f %.6f %.9f %.9f %.9f %.9f", t.x(), t.y(), t.z(),
                q.x(), q.y(), q.z(), q.w());
  return text;
}

void writeDemo(const std::string& out_dir) {
  using namespace hope::synthetic;
  const Scene scene = demoRoom();
  const Camera camera = demoCamera();
  const RenderedFrame frame = scene.render(camera);
  writeImage(out_dir + "/depth.png", depthTo16Bit(frame.depth));
  writeImage(out_dir + "/rgb.png", frame.bgr);
  writeTextFile(out_dir + "/pose.txt", poseText(camera.pose) + "\n");
  writeTextFile(out_dir + "/truth.txt",
                "# label height_m surface\n0 0.00 floor\n1 0.75 table top\n2 0.45 cabinet top\n"
                "3 0.17 first stair tread\n4 0.34 second stair tread\n5 0.80 book on the table\n"
                "# not planes: a ramp sloped 0.5 rad, a ball, a cone, a lying tube\n");
  std::cout << "hope_synth: wrote " << out_dir << "/{depth.png,rgb.png,pose.txt,truth.txt}\n";
}

void writeSequence(const std::string& out_dir, const std::string& name, int frames, int width) {
  using namespace hope::synthetic;
  const TrackingSequence sequence = makeTrackingSequence(name, frames, width);
  const TrackingScene scene;
  namespace fs = std::filesystem;
  for (const char* sub : {"depth", "rgb", "truth"}) fs::create_directories(fs::path(out_dir) / sub);
  // The lists are written when every frame is: complete or absent.
  std::ostringstream depth_list, rgb_list, groundtruth, accelerometer, intrinsics;
  depth_list << "# depth maps\n# sequence: " << name << " (" << sequence.description
             << ")\n# timestamp filename\n";
  rgb_list << "# color images\n# timestamp filename\n";
  groundtruth << "# ground truth trajectory\n# timestamp tx ty tz qx qy qz qw\n";
  accelerometer << "# accelerometer data\n# timestamp ax ay az\n";
  const auto& k = sequence.frames.front().camera.intrinsics;
  intrinsics << k.fx << " " << k.fy << " " << k.cx << " " << k.cy << "\n";
  const double t0 = 1300000000.0;  // like TUM: seconds since the epoch
  for (std::size_t f = 0; f < sequence.frames.size(); ++f) {
    const TrackingFrame& frame = sequence.frames[f];
    SensorNoise noise;
    noise.seed = static_cast<std::uint32_t>(f + 1);
    const RenderedFrame rendered = scene.render(frame.camera, frame.occluder_xy, noise);
    char stamp[32];
    std::snprintf(stamp, sizeof(stamp), "%.6f", t0 + frame.stamp);
    writeImage(out_dir + "/depth/" + stamp + ".png", depthTo16Bit(rendered.depth));
    writeImage(out_dir + "/rgb/" + stamp + ".png", rendered.bgr);
    cv::Mat truth16;
    rendered.labels.convertTo(truth16, CV_16UC1, 1.0, 1.0);  // -1 (none) → 0
    writeImage(out_dir + "/truth/" + stamp + ".png", truth16);
    depth_list << stamp << " depth/" << stamp << ".png\n";
    rgb_list << stamp << " rgb/" << stamp << ".png\n";
    // Sensors are not synchronized: pose and accelerometer 4 ms after the image.
    char later[32];
    std::snprintf(later, sizeof(later), "%.6f", t0 + frame.stamp + 0.004);
    groundtruth << later << " " << poseText(frame.camera.pose) << "\n";
    const Eigen::Vector3d up = frame.camera.pose.linear().transpose() * Eigen::Vector3d::UnitZ();
    accelerometer << later << " " << 9.81 * up.x() << " " << 9.81 * up.y() << " " << 9.81 * up.z()
                  << "\n";
    if (isatty(2)) {
      std::fprintf(stderr, "\rhope_synth: %s frame %zu/%zu", name.c_str(), f + 1,
                   sequence.frames.size());
    }
  }
  if (isatty(2)) std::fprintf(stderr, "\n");
  writeTextFile(out_dir + "/depth.txt", depth_list.str());
  writeTextFile(out_dir + "/rgb.txt", rgb_list.str());
  writeTextFile(out_dir + "/groundtruth.txt", groundtruth.str());
  writeTextFile(out_dir + "/accelerometer.txt", accelerometer.str());
  writeTextFile(out_dir + "/intrinsics.txt", intrinsics.str());
  std::cout << "hope_synth: wrote " << sequence.frames.size() << " frames of '" << name << "' to "
            << out_dir << " (TUM RGB-D layout)\n";
}

void writeLidar(const std::string& out_dir, const std::string& model_name,
                const std::string& scene_name, bool organized) {
  using namespace hope::synthetic;
  const LidarModel model = LidarModel::byName(model_name);
  std::ostringstream truth;
  Scene scene;
  Eigen::Isometry3d pose;
  if (scene_name == "street") {
    scene = lidarStreet();
    pose = lidarStreetPose();
    const double z = -pose.translation().z();
    truth << "# label height_m surface (sensor frame, z up; the sensor is 1.8 m above the road)\n"
          << street::kRoad << " " << z << " road (the ground)\n"
          << street::kGrade << " - driveway climbing at " << street::kGradeDeg
          << " deg from the road\n"
          << street::kSidewalk << " " << z + street::kSidewalkHeight << " sidewalk\n"
          << street::kPlatform << " " << z + street::kPlatformHeight << " loading platform\n"
          << street::kCarRoof << " " << z + street::kCarRoofHeight << " car roof\n"
          << street::kCarHood << " " << z + street::kCarHoodHeight << " car bonnet and boot\n"
          << street::kBench << " " << z + street::kBenchHeight << " bench seat\n"
          << street::kRamp << " - ramp at " << street::kRampDeg << " deg (not horizontal)\n";
  } else if (scene_name == "room") {
    scene = lidarRoom();
    pose = lidarRoomPose();
    const double z = -pose.translation().z();
    truth << "# label height_m surface (sensor frame, z up; the sensor is 1.2 m above the floor)\n"
          << room::kFloor << " " << z << " floor\n"
          << room::kTable << " " << z + room::kTableHeight << " table\n"
          << room::kLowBoard << " " << z + room::kLowBoardHeight << " low board\n"
          << room::kHighBoard << " " << z + room::kHighBoardHeight << " high board\n"
          << room::kCeiling << " " << z + room::kCeilingHeight << " ceiling (seen from below)\n";
  } else {
    throw std::invalid_argument("unknown --scene '" + scene_name + "' (choose street or room)");
  }
  const LidarScan scan = scanWithLidar(scene, model, pose);
  pcl::PointCloud<SyntheticLidarPoint> cloud;
  for (std::size_t i = 0; i < scan.points.size(); ++i) {
    if (!organized && !scan.valid(i)) continue;
    SyntheticLidarPoint p;
    p.x = scan.points[i].x();
    p.y = scan.points[i].y();
    p.z = scan.points[i].z();
    p.intensity = scan.intensity[i];
    p.ring = scan.ring[i];
    p.label = scan.labels[i];
    cloud.push_back(p);
  }
  if (organized) {
    cloud.width = static_cast<std::uint32_t>(scan.columns);
    cloud.height = static_cast<std::uint32_t>(scan.rings);
    cloud.is_dense = false;
  }
  hope::tools::OutputFile file(out_dir + "/scan.pcd");
  if (pcl::io::savePCDFileBinary(file.writePath(), cloud) != 0) {
    hope::tools::throwCannotWrite(file.path());
  }
  file.commit();
  writeTextFile(out_dir + "/truth.txt", truth.str());
  std::cout << "hope_synth: wrote " << out_dir << "/{scan.pcd,truth.txt}: " << model.name << " ("
            << scan.rings << " rings x " << scan.columns << " steps), " << scene_name << ", "
            << cloud.size() << " points" << (organized ? " (organized)" : "") << "\n";
}

void writeRoomScan(const std::string& out_dir, double spacing) {
  if (!(spacing >= 0.001 && spacing <= 1.0)) {
    throw std::invalid_argument("--room-scan spacing must be in [0.001, 1] metres");
  }
  const auto scan = hope::synthetic::demoRoom().scanFromAbove(-1.0, -3.0, 5.0, 3.0, spacing, 0.002);
  hope::tools::OutputFile file(out_dir + "/room_scan.pcd");
  if (pcl::io::savePCDFileBinary(file.writePath(), scan.cloud) != 0) {
    hope::tools::throwCannotWrite(file.path());
  }
  file.commit();
  std::cout << "hope_synth: wrote " << out_dir << "/room_scan.pcd: the demo room from above every "
            << spacing << " m, " << scan.cloud.size() << " points\n";
}

int run(const hope::tools::ParsedArgs& args) {
  const auto& values = args.values;
  auto valueOr = [&](const char* name, const std::string& fallback) {
    return values.count(name) ? values.at(name) : fallback;
  };
  const std::string out_dir = valueOr("--out", "");
  if (out_dir.empty()) throw std::invalid_argument("--out DIR is required");
  const std::string sequence = valueOr("--sequence", "");
  const std::string lidar = valueOr("--lidar", "");
  const std::string lidar_scene = valueOr("--scene", "street");
  const int frames =
      values.count("--frames") ? hope::tools::leadingInt("--frames", values.at("--frames")) : 60;
  const int width =
      values.count("--width") ? hope::tools::leadingInt("--width", values.at("--width")) : 640;
  const bool room_scan = values.count("--room-scan") > 0;
  const double room_scan_spacing =
      room_scan ? hope::tools::parseNumbers(values.at("--room-scan"), 1, "--room-scan")[0] : 0;

  std::filesystem::create_directories(out_dir);
  if (room_scan) {
    writeRoomScan(out_dir, room_scan_spacing);
  } else if (!lidar.empty()) {
    writeLidar(out_dir, lidar, lidar_scene, !args.flag("--unorganized"));
  } else if (sequence.empty()) {
    writeDemo(out_dir);
  } else {
    writeSequence(out_dir, sequence, frames, width);
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  return hope::tools::runTool("hope_synth", commandLine, run, argc, argv);
}
