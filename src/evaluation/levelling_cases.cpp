#include "hope/evaluation/levelling_cases.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <opencv2/imgcodecs.hpp>  // the IMREAD_ flags; images are read through the tools' module

#include "hope/depth_image.h"
#include "hope/evaluation/table_scenes.h"
#include "hope/extractor.h"
#include "hope/synthetic/lidar.h"
#include "hope/synthetic/sequences.h"
#include "hope/tools/image_codecs.h"
#include "hope/tools/io.h"
#include "hope/tools/sequence.h"

namespace hope {
namespace evaluation {

namespace {

constexpr double kDegree = M_PI / 180.0;

// A rendered depth frame as the sensor gives it: organized, in the optical frame.
LevellingCase cameraCase(const std::string& group, const std::string& name,
                         const synthetic::RenderedFrame& frame, const synthetic::Camera& camera) {
  LevellingCase c;
  c.group = group;
  c.name = name;
  c.cloud = depthToCloud(frame.depth, camera.intrinsics, 1.0);
  c.truth = Orientation::fromTransform(camera.pose);
  c.labels.assign(frame.labels.begin<int>(), frame.labels.end<int>());
  return c;
}

LevellingCase lidarCase(const std::string& group, const std::string& name,
                        const synthetic::LidarScan& scan) {
  LevellingCase c;
  c.group = group;
  c.name = name;
  c.cloud = scan.toCloud();
  c.truth = Orientation::fromTransform(scan.sensor_pose);
  c.labels = scan.labels;
  c.camera = false;
  return c;
}

std::string degrees(double value) {
  std::ostringstream out;
  out << static_cast<int>(std::lround(value));
  return out.str();
}

// The datasets of realLevellingCases, one each.
void tumCases(const std::string& data_dir, const CaseVisitor& visit,
              std::vector<std::string>& missing) {
  // TUM fr1_desk: the one frame with its motion-capture pose.
  const std::string tum = data_dir + "/tum_fr1_desk";
  cv::Mat depth;
  tools::readImageFile(tum + "/1305031459.274941.png", cv::IMREAD_ANYDEPTH, depth);
  std::ifstream groundtruth(tum + "/groundtruth.txt");
  if (!depth.empty() && groundtruth) {
    std::string line, last;
    while (std::getline(groundtruth, line)) {
      if (!line.empty() && line[0] != '#') last = line;
    }
    double stamp, tx, ty, tz, qx, qy, qz, qw;
    std::istringstream(last) >> stamp >> tx >> ty >> tz >> qx >> qy >> qz >> qw;
    LevellingCase c;
    c.group = "TUM fr1_desk (motion-capture pose)";
    c.name = "1305031459.274941";
    c.cloud = depthToCloud(depth, PinholeIntrinsics::tumFreiburg1(), 5000);
    c.truth = Orientation::fromPose(tx, ty, tz, qx, qy, qz, qw);
    visit(c);
  } else {
    missing.push_back(tum);
  }
}

void mosdCases(const std::string& data_dir, const CaseVisitor& visit,
               std::vector<std::string>& missing) {
  namespace fs = std::filesystem;
  // mOSD: up is the labelled (level) table top's normal.
  const std::string mosd = data_dir + "/mosd_dev";
  if (fs::is_directory(mosd)) {
    std::vector<std::string> paths;
    for (const auto& entry : fs::directory_iterator(mosd)) {
      if (entry.path().extension() == ".pcd") paths.push_back(entry.path().string());
    }
    std::sort(paths.begin(), paths.end());
    for (const std::string& path : paths) {
      const LabelledTableScene scene = loadLabelledTableScene(path);
      LevellingCase c;
      c.group = "mOSD tabletops (labelled table's normal)";
      c.name = scene.name;
      c.cloud = scene.cloud;
      c.truth = scene.orientation;
      c.is_table = scene.is_table;
      visit(c);
    }
  } else {
    missing.push_back(mosd);
  }
}

// A recorded sequence in the TUM layout (depth.txt, groundtruth.txt with poses in a
// gravity-aligned world, intrinsics.txt or the Kinect's): every step-th frame with its pose.
void sequenceCases(const std::string& dir, const std::string& group, int step,
                   const CaseVisitor& visit, std::vector<std::string>& missing) {
  namespace fs = std::filesystem;
  if (fs::is_regular_file(dir + "/depth.txt")) {
    tools::SequenceOptions options;
    options.dir = dir;
    const tools::SequenceListing listing = tools::listSequence(options);
    const PinholeIntrinsics k = listing.intrinsics_file.empty()
                                    ? PinholeIntrinsics{585, 585, 320, 240}
                                    : tools::readIntrinsics(listing.intrinsics_file);
    for (std::size_t f = 0; f < listing.frames.size(); f += std::max(1, step)) {
      cv::Mat image;
      if (!tools::readImageFile(listing.frames[f].depth, cv::IMREAD_ANYDEPTH, image)) continue;
      LevellingCase c;
      c.group = group;
      c.name = fs::path(listing.frames[f].depth).stem().string();
      c.cloud = depthToCloud(image, k, 5000);
      c.truth = listing.frames[f].orientation;
      visit(c);
    }
  } else {
    missing.push_back(dir);
  }
}

void pclLaserCases(const std::string& data_dir, const CaseVisitor& visit,
                   std::vector<std::string>& missing) {
  namespace fs = std::filesystem;
  // PCL's laser scans: unorganized, "z roughly up" (the truth is approximate).
  const std::string laser = data_dir + "/pcl_laser";
  bool any_laser = false;
  for (const char* file : {"room_scan1", "room_scan2", "min_cut_segmentation_tutorial"}) {
    const std::string path = laser + "/" + file + ".pcd";
    if (!fs::is_regular_file(path)) continue;
    const tools::InputCloud input = tools::loadCloud(path);
    LevellingCase c;
    c.group = "PCL laser scans (z roughly up)";
    c.name = file;
    c.cloud.resize(input.points.size());
    for (std::size_t i = 0; i < input.points.size(); ++i) {
      c.cloud[i].getVector3fMap() = input.points[i];
    }
    c.cloud.width = static_cast<std::uint32_t>(input.points.size());
    c.cloud.height = 1;
    c.exact = false;
    c.camera = false;
    visit(c);
    any_laser = true;
  }
  if (!any_laser) missing.push_back(laser);
}

}  // namespace

synthetic::Camera cameraAt(const Eigen::Vector3d& eye, double yaw, double pitch, double roll) {
  const Eigen::Vector3d forward(std::cos(pitch) * std::cos(yaw), std::cos(pitch) * std::sin(yaw),
                                -std::sin(pitch));
  // Right of the heading, level; down completes the optical frame (x right, y down, z forward).
  const Eigen::Vector3d level_right(std::sin(yaw), -std::cos(yaw), 0.0);
  const Eigen::AngleAxisd rolled(roll, forward);
  const Eigen::Vector3d right = rolled * level_right;
  const Eigen::Vector3d down = forward.cross(right);
  synthetic::Camera camera;
  camera.pose.linear().col(0) = right;
  camera.pose.linear().col(1) = down;
  camera.pose.linear().col(2) = forward;
  camera.pose.translation() = eye;
  return camera;
}

void syntheticLevellingCases(bool quick, const CaseVisitor& visit) {
  const synthetic::SensorNoise noise = synthetic::SensorNoise::kinectLike();
  // The demo room from a camera held 1.5 m up, aimed at the table's near corner: level, it sees
  // the floor, the table and the cabinet ahead; straight down, the table top, the book and the
  // floor beside them.
  const synthetic::Scene room = synthetic::demoRoom();
  const Eigen::Vector3d target(1.45, -0.35, 0.45);
  const double eye_height = 1.5;
  const int step = quick ? 45 : 15;
  for (int pitch = 0; pitch <= 90; pitch += step) {
    for (int roll = -30; roll <= 30; roll += quick ? 30 : 15) {
      const double yaw = 0.1;
      const double horizontal =
          pitch == 0 ? 2.2 : std::min(2.2, (eye_height - target.z()) / std::tan(pitch * kDegree));
      const Eigen::Vector3d eye(target.x() - horizontal * std::cos(yaw),
                                target.y() - horizontal * std::sin(yaw), eye_height);
      const synthetic::Camera camera = cameraAt(eye, yaw, pitch * kDegree, roll * kDegree);
      visit(cameraCase("demo room, hand-held camera",
                       "pitch " + degrees(pitch) + "°, roll " + degrees(roll) + "°",
                       room.render(camera, noise), camera));
    }
  }
  // The tracking sequences' scene (floor, table, book, cabinet, stairs, the pattern object)
  // along each motion, which pans, rolls, pitches and shakes the camera.
  const synthetic::TrackingScene tracking_scene;
  for (const std::string& name : synthetic::trackingSequenceNames()) {
    const synthetic::TrackingSequence sequence = synthetic::makeTrackingSequence(name, 90, 640);
    for (std::size_t f = 0; f < sequence.frames.size(); f += quick ? 45 : 15) {
      const synthetic::TrackingFrame& frame = sequence.frames[f];
      visit(cameraCase("tracking sequences", name + " frame " + std::to_string(f),
                       tracking_scene.render(frame.camera, frame.occluder_xy, noise),
                       frame.camera));
    }
  }
  // Spinning LiDARs tilted on their mounts (roll, pitch in degrees).
  const std::vector<std::pair<double, double>> tilts =
      quick ? std::vector<std::pair<double, double>>{{0, 0}, {5, -3}}
            : std::vector<std::pair<double, double>>{{0, 0}, {3, 0}, {0, -5}, {5, -3}, {-10, 8}};
  const synthetic::Scene street = synthetic::lidarStreet(), lidar_room = synthetic::lidarRoom();
  for (const auto& tilt : tilts) {
    const Eigen::Matrix3d rotation =
        (Eigen::AngleAxisd(tilt.second * kDegree, Eigen::Vector3d::UnitY()) *
         Eigen::AngleAxisd(tilt.first * kDegree, Eigen::Vector3d::UnitX()))
            .toRotationMatrix();
    const std::string name =
        "roll " + degrees(tilt.first) + "°, pitch " + degrees(tilt.second) + "°";
    Eigen::Isometry3d pose = synthetic::lidarStreetPose();
    pose.linear() = pose.linear() * rotation;
    visit(lidarCase("HDL-64E street", name,
                    synthetic::scanWithLidar(street, synthetic::LidarModel::hdl64(), pose)));
    pose = synthetic::lidarRoomPose();
    pose.linear() = pose.linear() * rotation;
    visit(lidarCase("VLP-16 room", name,
                    synthetic::scanWithLidar(lidar_room, synthetic::LidarModel::vlp16(), pose)));
  }
}

void realLevellingCases(const std::string& data_dir, int kitchen_step, const CaseVisitor& visit,
                        std::vector<std::string>& missing, unsigned which) {
  if (which & kTumDesk) tumCases(data_dir, visit, missing);
  if (which & kMosd) mosdCases(data_dir, visit, missing);
  if (which & kKitchen) {
    sequenceCases(data_dir + "/kitchen_dev", "kitchen_dev (sequence poses)", kitchen_step, visit,
                  missing);
  }
  if (which & kStudyroom) {
    sequenceCases(data_dir + "/studyroom_dev", "studyroom_dev (sequence poses)", kitchen_step,
                  visit, missing);
  }
  if (which & kPclLaser) pclLaserCases(data_dir, visit, missing);
}

std::optional<Eigen::Vector3d> tiltSearchUp(const PointsView& cloud, const Params& params) {
  Extractor extractor(params);
  for (int degrees = 0; degrees <= 75; degrees += 15) {
    const double pitch = degrees * kDegree;
    const Orientation guess = Orientation::fromGravity(0, -std::cos(pitch), -std::sin(pitch));
    ExtractOutputs planes_only;
    planes_only.point_labels = false;
    const Result rough = extractor.extract(cloud, guess, planes_only);
    const auto largest = std::max_element(
        rough.planes.begin(), rough.planes.end(),
        [](const HorizontalPlane& a, const HorizontalPlane& b) { return a.area < b.area; });
    if (largest == rough.planes.end() || largest->area < 0.1) continue;
    return Eigen::Vector3d(rough.sensor_to_reference.linear().transpose() * largest->normal);
  }
  return std::nullopt;
}

double angleDeg(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  const double cosine = a.normalized().dot(b.normalized());
  return std::acos(std::clamp(cosine, -1.0, 1.0)) / kDegree;
}

}  // namespace evaluation
}  // namespace hope
