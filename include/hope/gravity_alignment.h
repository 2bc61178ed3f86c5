// Gravity alignment (paper §2.2, Eq 1): bring the cloud from the sensor frame F_s into the
// reference frame F_r whose z axis points up.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "hope/points_view.h"

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

// The reference frame's +z (up) in the sensor's frame: Rᵀ·z of a sensor-to-reference transform.
Eigen::Vector3d upInSensor(const Eigen::Isometry3d& sensor_to_reference);

// Aligned points are stored as float, whose centimetres are gone beyond ~100 km (a pose in
// UTM map coordinates). They are stored relative to this local origin instead: the sensor's
// position rounded to a multiple of 1024 m — zero for any pose within 512 m of the reference
// frame's origin, so ordinary scenes are computed exactly as without it.
Eigen::Vector3d localOrigin(const Orientation& orientation);

// Transforms every point into F_r, minus `origin` (see localOrigin). Non-finite input points
// become NaN so that later stages (and per-point labels) keep the input order. Returns the
// number of finite points; with `finite_box`, also their bounding box (the grid filter needs
// it, and this pass has every point at hand). `threads` as Params::threads (0: every core).
std::size_t alignToGravity(const PointsView& input, const Orientation& orientation,
                           std::vector<Eigen::Vector3f>& aligned,
                           const Eigen::Vector3d& origin = Eigen::Vector3d::Zero(),
                           Eigen::AlignedBox3f* finite_box = nullptr, int threads = 1);

// Whether alignToGravity would copy `input` unchanged: the orientation has no rotation and its
// translation equals `origin`, and x, y, z are packed float32 at the start of each point. The
// stages then read the input in place (see AlignedPoints) and only finiteBox() is needed.
bool alignmentIsIdentity(const PointsView& input, const Orientation& orientation,
                         const Eigen::Vector3d& origin);

// The number of finite points of `input` and their box (a point with any non-finite
// coordinate is skipped), in one read; `threads` as Params::threads. x, y, z must be packed
// float32 at the start of each point, as alignmentIsIdentity() requires.
std::size_t finiteBox(const PointsView& input, Eigen::AlignedBox3f& box, int threads = 1);

}  // namespace hope
