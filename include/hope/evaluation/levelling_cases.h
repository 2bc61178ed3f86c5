// Clouds in their sensor's own frame whose up is known, for measuring up from the scene
// (up_estimation.h): synthetic camera views at many pitches and rolls and tilted LiDAR scans
// (exact), and the real data of ../shared/data (TUM with its pose, mOSD by its labelled table,
// the kitchen and study-room sequences with their poses, PCL's laser scans whose z is roughly up).
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include <Eigen/Geometry>

#include "hope/gravity_alignment.h"
#include "hope/params.h"
#include "hope/points_view.h"
#include "hope/synthetic/scene.h"

namespace hope {
namespace evaluation {

struct LevellingCase {
  std::string group;  // what the table groups by, e.g. "mOSD tabletops"
  std::string name;
  pcl::PointCloud<pcl::PointXYZ> cloud;  // in the sensor's frame, as the sensor gives it
  // The true orientation (sensor → a z-up frame); its up in the sensor frame is trueUp().
  Orientation truth = Orientation::identity();
  // Whether the truth is exact (synthetic, a labelled level table, motion capture) or only
  // roughly right (a scan said to be "roughly z-up").
  bool exact = true;
  // Ground-truth plane label per point (synthetic scenes; kNoPlane elsewhere), or empty.
  std::vector<int> labels;
  // mOSD: 1 for the labelled table top's points.
  std::vector<std::uint8_t> is_table;
  // A camera's cloud (where the −y tilt search applies) rather than a LiDAR's.
  bool camera = true;

  Eigen::Vector3d trueUp() const { return upInSensor(truth.sensorToReference()); }
};

using CaseVisitor = std::function<void(const LevellingCase&)>;

// A camera at `eye` in a z-up world, heading `yaw` (radians from +x towards +y), pitched down by
// `pitch` (π/2: straight down) and rolled by `roll` about its optical axis.
synthetic::Camera cameraAt(const Eigen::Vector3d& eye, double yaw, double pitch, double roll);

// Synthetic cases, Kinect-like noise: the demo room from a hand-held camera at pitches 0–90°
// and rolls ±30° (every 15° with `quick` false), and the HDL-64E street and the indoor LiDAR
// room scanned with the sensor tilted.
void syntheticLevellingCases(bool quick, const CaseVisitor& visit);

// The real datasets, for choosing which to read.
enum RealData : unsigned {
  kTumDesk = 1,
  kMosd = 2,
  kKitchen = 4,
  kPclLaser = 8,
  kStudyroom = 16,
  kAllRealData = kTumDesk | kMosd | kKitchen | kPclLaser | kStudyroom,
};

// The real clouds of `data_dir` whose up is known, in groups, from the datasets in `which`; a
// group whose data is absent is left out (the names of the absent ones go to `missing`).
// `kitchen_step`: every n-th frame of the recorded sequences (kitchen_dev, studyroom_dev).
void realLevellingCases(const std::string& data_dir, int kitchen_step, const CaseVisitor& visit,
                        std::vector<std::string>& missing, unsigned which = kAllRealData);

// The levelling hope_eval used before up_estimation.h, measured beside it: up = −y (a level
// camera's optical frame) tilted down by 0, 15, … 75°; the first tilt that finds a plane of
// 0.1 m² or more wins, then up = that plane's normal. Nothing when no tilt finds one.
std::optional<Eigen::Vector3d> tiltSearchUp(const PointsView& cloud, const Params& params);

// The angle between two directions, degrees.
double angleDeg(const Eigen::Vector3d& a, const Eigen::Vector3d& b);

}  // namespace evaluation
}  // namespace hope
