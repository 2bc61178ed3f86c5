#include "hope/synthetic/lidar.h"

#include <cmath>
#include <limits>
#include <random>
#include <stdexcept>

namespace hope {
namespace synthetic {

namespace {

double radians(double degrees) { return degrees * M_PI / 180.0; }

}  // namespace

int LidarModel::columns() const { return static_cast<int>(std::lround(360.0 / azimuth_step_deg)); }

LidarModel LidarModel::vlp16() {
  LidarModel model;
  model.name = "vlp16";
  for (int k = 0; k < 16; ++k) model.elevations_deg.push_back(-15.0 + 2.0 * k);
  model.azimuth_step_deg = 0.2;
  model.max_range = 100.0;
  return model;
}

LidarModel LidarModel::hdl64() {
  LidarModel model;
  model.name = "hdl64";
  // Lower block: 32 beams from −24.8° to −8.83°; upper block: 32 beams from −8.33° to +2°.
  for (int k = 0; k < 32; ++k) model.elevations_deg.push_back(-24.8 + k * (24.8 - 8.83) / 31.0);
  for (int k = 0; k < 32; ++k) model.elevations_deg.push_back(-8.33 + k * (2.0 + 8.33) / 31.0);
  model.azimuth_step_deg = 0.17;
  model.max_range = 120.0;
  return model;
}

LidarModel LidarModel::ouster128() {
  LidarModel model;
  model.name = "os128";
  for (int k = 0; k < 128; ++k) model.elevations_deg.push_back(-22.5 + k * 45.0 / 127.0);
  model.azimuth_step_deg = 360.0 / 2048.0;
  model.max_range = 120.0;
  return model;
}

LidarModel LidarModel::byName(const std::string& name) {
  if (name == "vlp16") return vlp16();
  if (name == "hdl64") return hdl64();
  if (name == "os128") return ouster128();
  throw std::invalid_argument("unknown LiDAR model '" + name + "' (choose vlp16, hdl64 or os128)");
}

pcl::PointCloud<pcl::PointXYZ> LidarScan::toCloud() const {
  pcl::PointCloud<pcl::PointXYZ> cloud;
  cloud.reserve(points.size());
  for (const Eigen::Vector3f& p : points) cloud.push_back(pcl::PointXYZ(p.x(), p.y(), p.z()));
  cloud.width = static_cast<std::uint32_t>(columns);
  cloud.height = static_cast<std::uint32_t>(rings);
  cloud.is_dense = false;
  return cloud;
}

LidarScan scanWithLidar(const Scene& scene, const LidarModel& model,
                        const Eigen::Isometry3d& sensor_pose, std::uint32_t seed) {
  LidarScan scan;
  scan.rings = model.rings();
  scan.columns = model.columns();
  scan.sensor_pose = sensor_pose;
  const std::size_t n = static_cast<std::size_t>(scan.rings) * scan.columns;
  const float nan = std::numeric_limits<float>::quiet_NaN();
  scan.points.assign(n, Eigen::Vector3f(nan, nan, nan));
  scan.intensity.assign(n, 0.0f);
  scan.ring.assign(n, 0);
  scan.labels.assign(n, kNoPlane);
  std::mt19937 rng(seed);
  std::normal_distribution<double> range_noise(0.0, model.range_sigma);
  const Eigen::Vector3d origin = sensor_pose.translation();
  const Eigen::Matrix3d rotation = sensor_pose.linear();
  const double azimuth_step = 2.0 * M_PI / scan.columns;
  for (int r = 0; r < scan.rings; ++r) {
    const double elevation = radians(model.elevations_deg[r]);
    for (int c = 0; c < scan.columns; ++c) {
      const std::size_t i = static_cast<std::size_t>(r) * scan.columns + c;
      scan.ring[i] = static_cast<std::uint16_t>(r);
      const double azimuth = c * azimuth_step;
      const Eigen::Vector3d beam(std::cos(elevation) * std::cos(azimuth),
                                 std::cos(elevation) * std::sin(azimuth), std::sin(elevation));
      Hit hit;
      if (!scene.intersect(origin, rotation * beam, hit)) continue;
      if (hit.t < model.min_range || hit.t > model.max_range) continue;
      const double range = hit.t + (model.range_sigma > 0 ? range_noise(rng) : 0.0);
      scan.points[i] = (range * beam).cast<float>();
      const double cos_incidence = std::fabs(hit.normal.dot(rotation * beam));
      scan.intensity[i] = static_cast<float>(255.0 * cos_incidence);
      scan.labels[i] = hit.label;
    }
  }
  return scan;
}

Scene lidarStreet() {
  using namespace street;
  using V = Eigen::Vector3d;
  Scene scene;
  scene.add<Rectangle>(V(0, 0, 0), V::UnitX(), V::UnitY(), 130.0, 130.0, kRoad);
  // A driveway off the road's left edge climbing at 2° to a garage: y from 3 to 18 m.
  const double grade_length = (kGradeEndY - kGradeStartY) / std::cos(radians(kGradeDeg));
  const V grade_axis(0, std::cos(radians(kGradeDeg)), std::sin(radians(kGradeDeg)));
  scene.add<Rectangle>(
      V(0.5 * (kGradeMinX + kGradeMaxX), kGradeStartY, 0) + 0.5 * grade_length * grade_axis,
      V::UnitX(), grade_axis, 0.5 * (kGradeMaxX - kGradeMinX), 0.5 * grade_length, kGrade);
  const double garage_floor = (kGradeEndY - kGradeStartY) * std::tan(radians(kGradeDeg));
  scene.add<Box>(V(kGradeMinX - 2, kGradeEndY, 0),
                 V(kGradeMaxX + 2, kGradeEndY + 10, 5.0 + garage_floor), kNoPlane);
  // Sidewalk along the left of the road, 12 cm up, ending before the grade.
  scene.add<Box>(V(-70, 6, 0), V(20, 10, kSidewalkHeight), kSidewalk);
  // Buildings behind the sidewalk and across the road (their roofs are out of sight).
  scene.add<Box>(V(-40, 11, 0), V(-15, 25, 9), kNoPlane);
  scene.add<Box>(V(-35, -40, 0), V(-5, -28, 6), kNoPlane);
  // Loading platform at 1.2 m.
  scene.add<Box>(V(8, -14, 0), V(14, -8, kPlatformHeight), kPlatform);
  // A parked car: body with bonnet and boot at 1.0 m, cabin roof at 1.45 m.
  scene.add<Box>(V(-12, -4, 0.3), V(-7.5, -2.2, kCarHoodHeight), kCarHood);
  scene.add<Box>(V(-11, -4, kCarHoodHeight), V(-8.5, -2.2, kCarRoofHeight), kCarRoof);
  // A bench: seat at 0.45 m with a backrest.
  scene.add<Box>(V(4, 4, kBenchHeight - 0.05), V(6, 4.5, kBenchHeight), kBench);
  scene.add<Box>(V(4, 4.45, kBenchHeight), V(6, 4.5, 0.9), kNoPlane);
  // A free-standing 25° ramp, 1 m high, 4 m wide.
  const double ramp_height = 1.0;
  const double ramp_length = ramp_height / std::sin(radians(kRampDeg));
  const V ramp_axis(std::cos(radians(kRampDeg)), 0, std::sin(radians(kRampDeg)));
  const V ramp_foot(-20, -10, 0);
  scene.add<Rectangle>(ramp_foot + 0.5 * ramp_length * ramp_axis, ramp_axis, V::UnitY(),
                       0.5 * ramp_length, 2.0, kRamp);
  // A lamp post and a tree on the sidewalk, a bollard by the road.
  scene.add<Cylinder>(V(5, -6, 0), V(5, -6, 5), 0.1);
  scene.add<Cylinder>(V(-5, 8, 0), V(-5, 8, 3), 0.2);
  scene.add<Sphere>(V(-5, 8, 4.5), 2.0);
  scene.add<Cylinder>(V(16, 4, 0), V(16, 4, 1.0), 0.15);
  return scene;
}

Eigen::Isometry3d lidarStreetPose() {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.translation() = Eigen::Vector3d(0, 0, 1.8);
  return pose;
}

Scene lidarRoom() {
  using namespace room;
  using V = Eigen::Vector3d;
  Scene scene;
  scene.add<Rectangle>(V(0, 0, 0), V::UnitX(), V::UnitY(), 10.0, 6.0, kFloor);
  scene.add<Rectangle>(V(0, 0, kCeilingHeight), V::UnitX(), V::UnitY(), 10.0, 6.0, kCeiling);
  const double half_height = 0.5 * kCeilingHeight;
  scene.add<Rectangle>(V(10, 0, half_height), V::UnitY(), V::UnitZ(), 6.0, half_height, kNoPlane);
  scene.add<Rectangle>(V(-10, 0, half_height), V::UnitY(), V::UnitZ(), 6.0, half_height, kNoPlane);
  scene.add<Rectangle>(V(0, 6, half_height), V::UnitX(), V::UnitZ(), 10.0, half_height, kNoPlane);
  scene.add<Rectangle>(V(0, -6, half_height), V::UnitX(), V::UnitZ(), 10.0, half_height, kNoPlane);
  // A table, 1.6 × 1 m, on four legs.
  // Table top and boards as thin sheets: the ground truth has no rim faces to argue about.
  scene.add<Rectangle>(V(5.8, -1.5, kTableHeight), V::UnitX(), V::UnitY(), 0.8, 0.5, kTable);
  for (const double x : {5.05, 6.5}) {
    for (const double y : {-1.95, -1.1}) {
      scene.add<Box>(V(x, y, 0), V(x + 0.05, y + 0.05, kTableHeight - 0.01), kNoPlane);
    }
  }
  // Two boards 2 × 0.6 m on brackets: one in front of the far wall, one nearer.
  scene.add<Rectangle>(V(-3, 5.3, kLowBoardHeight), V::UnitX(), V::UnitY(), 1.0, 0.3, kLowBoard);
  scene.add<Rectangle>(V(-0.5, 2.8, kHighBoardHeight), V::UnitX(), V::UnitY(), 1.0, 0.3,
                       kHighBoard);
  // A cabinet and a pillar.
  scene.add<Box>(V(-3, -5.5, 0), V(-1.5, -5, 1.8), kNoPlane);
  scene.add<Cylinder>(V(2, 3, 0), V(2, 3, kCeilingHeight), 0.25);
  return scene;
}

Eigen::Isometry3d lidarRoomPose() {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.translation() = Eigen::Vector3d(0, 0, 1.2);
  return pose;
}

}  // namespace synthetic
}  // namespace hope
