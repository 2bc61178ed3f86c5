// The sensor's orientation in the gravity-aligned reference frame: as a source gives it (a pose,
// tf, an IMU's quaternion, an accelerometer, a fixed rotation) or as the scene's level surfaces
// tell it (UpEstimate), paper §2.2.
#pragma once

#include <optional>
#include <stdexcept>
#include <string>

#include <Eigen/Geometry>

namespace hope {

// The sensor's orientation (and optionally position) in the reference frame, ROS convention:
// p_r = R · p_s + t, with R the ordinary rotation matrix of the unit quaternion. Note that
// Eq 2 as printed in the paper is the transpose of R.
class Orientation {
 public:
  // The cloud is already z-up (the paper's "omit when F_r equals F_s"). Where the sensor was
  // is unknown (a merged map, a scan already in world coordinates): add it withViewpoint()
  // when it is known.
  static Orientation identity();
  // Quaternion in ROS order (x, y, z, w). Non-unit quaternions are normalized; zero-length,
  // NaN or infinite ones throw std::invalid_argument.
  static Orientation fromQuaternion(double qx, double qy, double qz, double qw);
  // Fixed-axis roll (about x), pitch (about y), yaw (about z) in radians, R = Rz·Ry·Rx, as
  // tf2::Quaternion::setRPY.
  static Orientation fromRollPitchYaw(double roll, double pitch, double yaw);
  // A full pose (a TUM ground-truth line: tx ty tz qx qy qz qw): heights become real heights.
  static Orientation fromPose(double tx, double ty, double tz, double qx, double qy, double qz,
                              double qw);
  // The specific force measured by an accelerometer at rest, in the sensor frame. At rest it
  // points UP (the reaction to gravity), e.g. (0, 0, +9.81) for a level sensor. Yaw is
  // unobservable and irrelevant; the smallest rotation taking it to +z is used.
  static Orientation fromGravity(double gx, double gy, double gz);
  // Any rigid transform (sensor → reference); the rotation is re-orthonormalized.
  static Orientation fromTransform(const Eigen::Isometry3d& sensor_to_reference);

  // A copy that records where the sensor was, in the reference frame. Every factory but
  // identity() sets it to the sensor frame's origin (the translation; zero for a rotation).
  Orientation withViewpoint(const Eigen::Vector3d& viewpoint) const;
  // A copy with the sensor's position unknown (as identity() has it).
  Orientation withoutViewpoint() const;

  const Eigen::Isometry3d& sensorToReference() const { return transform_; }
  // The sensor's position in the reference frame, when known. The fragment merge uses it to
  // tell a shadow from a real gap, and the plane's facing (up/down) comes from it.
  const std::optional<Eigen::Vector3d>& viewpoint() const { return viewpoint_; }
  std::string describe() const;

 private:
  explicit Orientation(const Eigen::Isometry3d& t) : transform_(t), viewpoint_(t.translation()) {}
  Eigen::Isometry3d transform_ = Eigen::Isometry3d::Identity();
  std::optional<Eigen::Vector3d> viewpoint_;
};

// Where up may lie before the scene is looked at.
enum class UpPrior {
  // kCamera for an image-like organized cloud or an unorganized one that lies in front of its
  // origin (every point at z > 0: a camera's optical frame); kZUp otherwise.
  kAuto,
  // A camera: the image's top is up, pitched anywhere from 15° above level to straight down,
  // rolled by at most 35°. The camera's axes come from the cloud's layout when it is an image
  // (a pinhole fit: each point lies on its pixel's ray), else the optical frame's (x right,
  // y down, z forward).
  kCamera,
  // A LiDAR or a map: up within 45° of the cloud's +z.
  kZUp,
};

const char* toString(UpPrior prior);

struct UpEstimate {
  // The unit up vector in the input cloud's frame.
  Eigen::Vector3d up_in_sensor = Eigen::Vector3d::UnitZ();
  // The orientation to extract with. estimate(): the smallest rotation taking up to +z, the
  // sensor at the origin (heights relative to the sensor, as with a gravity vector). refine():
  // the given orientation turned about the sensor by `correction_deg` (or unchanged when the
  // correction was not applied).
  Orientation orientation = Orientation::identity();
  // How sure: the level area that fixed up (footprint at cell size, m²), the RMS angle between
  // its cells' normals and up, how many connected level surfaces and distinct heights it has.
  double support_area = 0;
  double angle_spread_deg = 0;
  int level_surfaces = 0;
  int level_heights = 0;
  // The prior that was used, and for a camera its pitch (down positive) and roll, degrees.
  UpPrior prior = UpPrior::kAuto;
  double pitch_deg = 0, roll_deg = 0;
  // refine() only: the angle between the given up and the scene's, the tilt the level
  // surfaces can tell in that direction (the smallest correction they support), whether the
  // correction was applied, and why not when it was not.
  bool refinement = false;
  double correction_deg = 0;
  double resolution_deg = 0;
  bool applied = true;
  std::string note;
  double time_ms = 0;

  // One line: up, support, spread, surfaces (and the correction for a refinement).
  std::string describe() const;
};

// The scene gives no evidence of up (see the file comment). what() says why and names the
// other orientation sources.
class LevellingError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace hope
