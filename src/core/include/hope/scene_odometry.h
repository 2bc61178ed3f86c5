// Scene odometry: where the sensor went between two frames, from the frames' own points, when
// its orientation alone is known (an IMU, an accelerometer, up from the scene, rotation-only
// poses). Not in the paper. The surface map (surface_map.h) keeps one id per surface only in a
// frame that stays put; with an orientation alone the reference frame's origin and heading
// follow the sensor. Gravity fixes roll and pitch, so the motion between two gravity-aligned
// frames is a turn about the vertical and a shift: four unknowns, found by point-to-plane ICP
// (Chen and Medioni 1992) on voxel centroids, coarse to fine. The frames' poses, chained, put
// every frame in one world for the map; they drift slowly, and the map forgets surfaces unseen
// for a while.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <vector>

#include <Eigen/Geometry>

#include "hope/params.h"
#include "hope/points_view.h"

namespace hope {

struct OdometryParams {
  // The finest voxel, metres: 1.5 r_z at the defaults. A depth camera's samples of one surface
  // lie within a few millimetres of each other up to 2–3 m (its noise grows with the square of
  // the range: ~1.5 mm at 1 m, ~25 mm at 4 m), so a 3 cm voxel's centroid is on the surface,
  // and the points of the voxel twice its size that holds it tell the surface's normal.
  double cell = 0.03;
  // Levels of voxels, each twice the next: a coarse level reaches a larger motion (a
  // correspondence is sought within 1.5 voxels), the finest is the most precise. Three reach
  // 18 cm between frames at the defaults (a hand-held camera at 3 Hz moves about 7 cm).
  int levels = 3;
  // Gauss–Newton steps at each level (fewer when the step becomes negligible).
  int iterations = 10;
  // The moving frame's voxels used at each level, at most (evenly picked): they overdetermine
  // four unknowns many times over.
  std::size_t max_samples = 1500;
  // The sensor's range noise σ(d): points where it exceeds the finest voxel are not used (a
  // depth camera's past 4.3 m at 3 cm; a LiDAR's nearly all kept). Unset: a depth camera's for
  // an image-like cloud, a LiDAR's otherwise (RangeNoise).
  std::optional<RangeNoise> noise;
  // Surfaces whose normal is within this of vertical are horizontal (Eq 3: atan(r_z / r_xy),
  // 21.8° at the defaults): they tell the height alone, and their normals' noise says nothing
  // of a shift along them. A frame with nothing else in view keeps the shift and turn it
  // started from (none, or the last frame's motion), degrees.
  double level_tilt_deg = 21.8;
  // The share of the moving frame's finest voxels that lie on the last frame's surfaces once
  // aligned (within half a voxel of the plane of a flat voxel within 1.5 voxels: along the
  // surface, sparse samples' centroids lie up to a voxel apart); below it the alignment is not
  // trusted (OdometryStep::tracked) and other starting motions are tried. A frame that turned
  // to a new view shares little.
  double min_overlap = 0.33;
};

// Throws std::invalid_argument naming the parameter that is out of range.
void validate(const OdometryParams& params);

struct OdometryStep {
  // The gravity-aligned frame's pose in the odometry's world (the first frame's gravity-aligned
  // frame): a turn about z and a shift.
  Eigen::Isometry3d world_from_frame = Eigen::Isometry3d::Identity();
  // See OdometryParams::min_overlap; 0 on the first frame.
  double overlap = 0.0;
  // False on the first frame (the world starts there) and where no starting motion reached
  // min_overlap (the best one is used: the map's own gates reject what it misplaces).
  bool tracked = false;
  // This frame began the world: the first frame, or the first after reset().
  bool started = false;
};

class SceneOdometry {
 public:
  explicit SceneOdometry(const OdometryParams& params = OdometryParams());

  // `sensor_to_frame` takes the cloud's points into the frame's gravity-aligned frame (z up).
  // Non-finite points are skipped; a frame with too few voxels is not tracked.
  OdometryStep update(const PointsView& cloud, const Eigen::Isometry3d& sensor_to_frame);

  // Forgets the last frame: the next one starts a new world.
  void reset();
  const OdometryParams& params() const { return params_; }

  // One level's voxels: centroid, unit normal of its neighbourhood where that is flat.
  struct Voxels {
    double size = 0.0;
    std::vector<std::uint64_t> table_keys;  // open addressing, kEmpty for a free slot
    std::vector<std::int32_t> table_index;
    std::vector<Eigen::Vector3d> centroid;
    std::vector<Eigen::Vector3d> normal;
    std::vector<char> flat;
    std::int32_t find(std::uint64_t key) const;
  };

 private:
  struct Motion {
    double yaw = 0.0;
    Eigen::Vector3d shift = Eigen::Vector3d::Zero();
  };
  // `moving`: the frame's sample centroids at each level.
  bool align(const std::vector<std::vector<Eigen::Vector3d>>& moving, Motion& motion,
             double& overlap) const;

  OdometryParams params_;
  std::vector<Voxels> last_;
  Eigen::Isometry3d world_from_last_ = Eigen::Isometry3d::Identity();
  Motion last_motion_;
};

}  // namespace hope
