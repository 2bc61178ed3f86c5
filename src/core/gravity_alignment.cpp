#include "hope/gravity_alignment.h"

#include <cmath>
#include <cstring>
#include <limits>
#include <sstream>
#include <stdexcept>

namespace hope {

namespace {

Eigen::Quaterniond checkedUnitQuaternion(double qx, double qy, double qz, double qw) {
  if (!std::isfinite(qx) || !std::isfinite(qy) || !std::isfinite(qz) || !std::isfinite(qw)) {
    std::ostringstream msg;
    msg << "orientation quaternion (x y z w) = (" << qx << " " << qy << " " << qz << " " << qw
        << ") has a NaN or infinite component";
    throw std::invalid_argument(msg.str());
  }
  const double norm = std::sqrt(qx * qx + qy * qy + qz * qz + qw * qw);
  // Below this a quaternion carries no direction worth trusting (e.g. an IMU that reports
  // all zeros when it has no orientation estimate).
  if (norm < 1e-6) {
    std::ostringstream msg;
    msg << "orientation quaternion (x y z w) = (" << qx << " " << qy << " " << qz << " " << qw
        << ") has zero length; it describes no rotation (an IMU without an orientation "
           "estimate? use gravity instead)";
    throw std::invalid_argument(msg.str());
  }
  return Eigen::Quaterniond(qw / norm, qx / norm, qy / norm, qz / norm);
}

void requireFinite(const char* what, double a, double b, double c) {
  if (!std::isfinite(a) || !std::isfinite(b) || !std::isfinite(c)) {
    std::ostringstream msg;
    msg << what << " (" << a << " " << b << " " << c << ") has a NaN or infinite component";
    throw std::invalid_argument(msg.str());
  }
}

}  // namespace

Orientation Orientation::identity() {
  Orientation o(Eigen::Isometry3d::Identity());
  o.viewpoint_.reset();
  return o;
}

Orientation Orientation::withViewpoint(const Eigen::Vector3d& viewpoint) const {
  requireFinite("viewpoint", viewpoint.x(), viewpoint.y(), viewpoint.z());
  Orientation o = *this;
  o.viewpoint_ = viewpoint;
  return o;
}

Orientation Orientation::fromQuaternion(double qx, double qy, double qz, double qw) {
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.linear() = checkedUnitQuaternion(qx, qy, qz, qw).toRotationMatrix();
  return Orientation(t);
}

Orientation Orientation::fromRollPitchYaw(double roll, double pitch, double yaw) {
  requireFinite("roll/pitch/yaw", roll, pitch, yaw);
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.linear() = (Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) *
                Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()) *
                Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitX()))
                   .toRotationMatrix();
  return Orientation(t);
}

Orientation Orientation::fromPose(double tx, double ty, double tz, double qx, double qy, double qz,
                                  double qw) {
  requireFinite("pose translation", tx, ty, tz);
  Orientation o = fromQuaternion(qx, qy, qz, qw);
  o.transform_.translation() = Eigen::Vector3d(tx, ty, tz);
  o.viewpoint_ = o.transform_.translation();
  return o;
}

Orientation Orientation::fromGravity(double gx, double gy, double gz) {
  requireFinite("gravity vector", gx, gy, gz);
  const Eigen::Vector3d up(gx, gy, gz);
  const double norm = up.norm();
  if (norm < 1e-6) {
    throw std::invalid_argument(
        "gravity vector has zero length; an accelerometer at rest measures about 9.81 m/s^2");
  }
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.linear() = Eigen::Quaterniond::FromTwoVectors(up / norm, Eigen::Vector3d::UnitZ())
                   .normalized()
                   .toRotationMatrix();
  return Orientation(t);
}

Orientation Orientation::fromTransform(const Eigen::Isometry3d& sensor_to_reference) {
  const Eigen::Matrix4d& m = sensor_to_reference.matrix();
  if (!m.allFinite()) {
    throw std::invalid_argument("sensor-to-reference transform has a NaN or infinite entry");
  }
  Eigen::Quaterniond q(sensor_to_reference.linear());
  const Eigen::Vector3d& p = sensor_to_reference.translation();
  return fromPose(p.x(), p.y(), p.z(), q.x(), q.y(), q.z(), q.w());
}

std::string Orientation::describe() const {
  const Eigen::Quaterniond q(transform_.linear());
  const Eigen::Vector3d& p = transform_.translation();
  std::ostringstream s;
  s << "t = (" << p.x() << ", " << p.y() << ", " << p.z() << "), q (x y z w) = (" << q.x() << ", "
    << q.y() << ", " << q.z() << ", " << q.w() << ")";
  return s.str();
}

Eigen::Vector3d localOrigin(const Orientation& orientation) {
  const Eigen::Vector3d t = orientation.sensorToReference().translation();
  return (t / 1024.0).array().round().matrix() * 1024.0;
}

namespace {

// The loop of alignToGravity for one way of reading a point. The running box and count are
// locals whose address is never taken, so the compiler keeps them in registers instead of
// reloading them after every store into `out`.
template <class ReadPoint>
std::size_t alignAll(std::size_t count, ReadPoint read, const Eigen::Matrix3f& r,
                     const Eigen::Vector3f& t, Eigen::Vector3f* out, Eigen::Vector3f& box_min,
                     Eigen::Vector3f& box_max) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  Eigen::Vector3f lo = Eigen::Vector3f::Constant(std::numeric_limits<float>::max());
  Eigen::Vector3f hi = -lo;
  std::size_t finite = 0;
  for (std::size_t i = 0; i < count; ++i) {
    const Eigen::Vector3f p = read(i);
    const Eigen::Vector3f q = r * p + t;
    // A finite but astronomically large input can overflow to infinity here: treat it like
    // a missing measurement rather than let it poison the grid bounds.
    if (p.allFinite() && q.allFinite()) {
      out[i] = q;
      lo = lo.cwiseMin(q);
      hi = hi.cwiseMax(q);
      ++finite;
    } else {
      out[i] = Eigen::Vector3f(nan, nan, nan);
    }
  }
  box_min = lo;
  box_max = hi;
  return finite;
}

}  // namespace

std::size_t alignToGravity(const PointsView& input, const Orientation& orientation,
                           std::vector<Eigen::Vector3f>& aligned, const Eigen::Vector3d& origin,
                           Eigen::AlignedBox3f* finite_box) {
  const Eigen::Matrix3f r = orientation.sensorToReference().linear().cast<float>();
  // The translation minus the origin is taken in double, before it becomes a float.
  const Eigen::Vector3f t = (orientation.sensorToReference().translation() - origin).cast<float>();
  aligned.resize(input.count);
  Eigen::Vector3f lo, hi;
  std::size_t finite = 0;
  if (input.x_offset == 0 && input.y_offset == 4 && input.z_offset == 8) {
    // The common layout (every PCL xyz type, most PointCloud2 messages): x, y, z packed at the
    // start of each point, read as one vector instead of three separate loads.
    const std::uint8_t* data = input.data;
    const std::size_t stride = input.stride;
    auto packed = [data, stride](std::size_t i) {
      float xyz[3];
      std::memcpy(xyz, data + i * stride, sizeof(xyz));
      return Eigen::Vector3f(xyz[0], xyz[1], xyz[2]);
    };
    finite = alignAll(input.count, packed, r, t, aligned.data(), lo, hi);
  } else {
    auto fields = [&input](std::size_t i) {
      return Eigen::Vector3f(input.x(i), input.y(i), input.z(i));
    };
    finite = alignAll(input.count, fields, r, t, aligned.data(), lo, hi);
  }
  if (finite_box) *finite_box = Eigen::AlignedBox3f(lo, hi);
  return finite;
}

}  // namespace hope
