// Simulated spinning LiDARs (Velodyne VLP-16 and HDL-64E, a 128-beam Ouster-like sensor) over
// an outdoor street and an indoor room, each return carrying its ground-truth surface: scans
// whose rings grow sparse with range, as real ones do, with an exact answer.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "hope/synthetic/scene.h"

namespace hope {
namespace synthetic {

struct LidarModel {
  std::string name;
  std::vector<double> elevations_deg;  // one per ring, ring 0 the lowest beam
  double azimuth_step_deg = 0.2;
  double max_range = 100.0;
  double min_range = 0.5;
  double range_sigma = 0.02;  // Gaussian range noise, metres

  int rings() const { return static_cast<int>(elevations_deg.size()); }
  int columns() const;  // azimuth steps per revolution

  // Beam tables after the manufacturers' data sheets (rounded; equal steps within a block).
  static LidarModel vlp16();  // 16 beams, −15°…+15° every 2°, 0.2° azimuth
  static LidarModel hdl64();  // 64 beams, +2°…−24.8° (1/3° then 1/2° apart), 0.17° azimuth
  static LidarModel ouster128();  // 128 beams, −22.5°…+22.5° evenly, 2048 per revolution
  // "vlp16", "hdl64" or "os128"; throws std::invalid_argument naming the choices otherwise.
  static LidarModel byName(const std::string& name);
};

// One revolution, organized rings × azimuth (row = ring, column = azimuth step), in the sensor
// frame (x forward, y left, z up). Directions without a return hold NaN coordinates.
struct LidarScan {
  int rings = 0, columns = 0;
  std::vector<Eigen::Vector3f> points;  // rings × columns, row-major
  std::vector<float> intensity;         // 0–255, from the incidence angle
  std::vector<std::uint16_t> ring;      // the beam of each point
  std::vector<int> labels;              // ground-truth surface, kNoPlane (or NaN point) elsewhere
  Eigen::Isometry3d sensor_pose = Eigen::Isometry3d::Identity();  // sensor in the world

  bool valid(std::size_t i) const { return points[i].allFinite(); }
  // The points as a driver publishes them: organized rings × columns, NaN without a return.
  pcl::PointCloud<pcl::PointXYZ> toCloud() const;
};

// Casts every beam of one revolution from `sensor_pose` (world frame, z up).
LidarScan scanWithLidar(const Scene& scene, const LidarModel& model,
                        const Eigen::Isometry3d& sensor_pose, std::uint32_t seed = 1);

// The outdoor street. Ground truth (labels): kRoad the road, flat at z = 0 (the ground);
// kGrade a driveway off its left edge climbing at 2° (x 22–36 m, y 3–18 m) to a garage;
// kSidewalk 12 cm above the road;
// kPlatform a loading platform at 1.2 m; kCarRoof and kCarHood a parked car's roof (1.45 m)
// and bonnet/boot (1.0 m); kBench a bench seat (0.45 m). Not planes: a 25° ramp up to the
// platform, walls, poles, a tree, the car's sides.
namespace street {
constexpr int kRoad = 0, kGrade = 1, kSidewalk = 2, kPlatform = 3, kCarRoof = 4, kCarHood = 5,
              kBench = 6, kRamp = 7;
constexpr double kGradeMinX = 22.0, kGradeMaxX = 36.0, kGradeStartY = 3.0, kGradeEndY = 18.0;
constexpr double kGradeDeg = 2.0;
constexpr double kSidewalkHeight = 0.12, kPlatformHeight = 1.2, kCarRoofHeight = 1.45,
                 kCarHoodHeight = 1.0, kBenchHeight = 0.45;
constexpr double kRampDeg = 25.0;
}  // namespace street
Scene lidarStreet();
// The street sensor: 1.8 m above the road (a car's roof rack), level.
Eigen::Isometry3d lidarStreetPose();

// The indoor room (20 × 12 m, 3 m high): kFloor, kTable (0.75 m), two boards on brackets
// (kLowBoard 0.4 m, kHighBoard 0.9 m), kCeiling (3.0 m, seen from below). Walls, legs, a cabinet
// taller than the sensor and a pillar are no plane.
namespace room {
constexpr int kFloor = 0, kTable = 1, kLowBoard = 2, kHighBoard = 3, kCeiling = 4;
constexpr double kTableHeight = 0.75, kLowBoardHeight = 0.4, kHighBoardHeight = 0.9,
                 kCeilingHeight = 3.0;
}  // namespace room
Scene lidarRoom();
// A robot's LiDAR 1.2 m above the floor, level.
Eigen::Isometry3d lidarRoomPose();

// Whether a street label is ground (the road).
inline bool isStreetGround(int label) { return label == street::kRoad; }

}  // namespace synthetic
}  // namespace hope
