#include "hope/gravity_alignment.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "parallel.h"
#include "simd.h"

namespace hope {

namespace {

Eigen::Quaterniond checkedUnitQuaternion(double qx, double qy, double qz, double qw) {
  if (!std::isfinite(qx) || !std::isfinite(qy) || !std::isfinite(qz) || !std::isfinite(qw)) {
    std::ostringstream msg;
    msg << "orientation quaternion (x y z w) = (" << qx << " " << qy << " " << qz << " " << qw
        << ") has a NaN or infinite component";
    throw std::invalid_argument(msg.str());
  }
  // Scaled by the largest component before squaring: components of 1e200 (a corrupt line)
  // would square to infinity and normalize to zeros, taken silently as no rotation.
  const double scale = std::max({std::fabs(qx), std::fabs(qy), std::fabs(qz), std::fabs(qw)});
  const double scaled_norm =
      scale > 0 ? std::hypot(std::hypot(qx / scale, qy / scale), std::hypot(qz / scale, qw / scale))
                : 0.0;
  // Below this a quaternion carries no direction worth trusting (e.g. an IMU that reports
  // all zeros when it has no orientation estimate).
  if (scale * scaled_norm < 1e-6) {
    std::ostringstream msg;
    msg << "orientation quaternion (x y z w) = (" << qx << " " << qy << " " << qz << " " << qw
        << ") has zero length; it describes no rotation (an IMU without an orientation "
           "estimate? use gravity instead)";
    throw std::invalid_argument(msg.str());
  }
  return Eigen::Quaterniond(qw / scale / scaled_norm, qx / scale / scaled_norm,
                            qy / scale / scaled_norm, qz / scale / scaled_norm);
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

Eigen::Vector3d upInSensor(const Eigen::Isometry3d& sensor_to_reference) {
  return sensor_to_reference.linear().transpose() * Eigen::Vector3d::UnitZ();
}

Orientation Orientation::withoutViewpoint() const {
  Orientation o = *this;
  o.viewpoint_.reset();
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
  // Scaled before squaring, as the quaternion is: an overflowing length is not a zero one.
  const double scale = std::max({std::fabs(gx), std::fabs(gy), std::fabs(gz)});
  const Eigen::Vector3d up =
      scale > 0 ? Eigen::Vector3d(gx / scale, gy / scale, gz / scale) : Eigen::Vector3d::Zero();
  const double norm = up.norm();
  if (scale * norm < 1e-6) {
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

// The loop of alignToGravity for one way of reading a point, written out in scalars: the
// running box and count are locals whose address is never taken, so the compiler keeps them in
// registers instead of reloading them after every store into `out`. Only the rotated point is
// tested for finiteness: every output coordinate sums all three input coordinates (times a
// rotation entry, possibly zero), and a NaN or an infinity times anything, zero included, is
// not finite, so a non-finite input never yields a finite output. A finite but astronomically
// large input can overflow to infinity here too: treated like a missing measurement rather
// than let it poison the grid bounds.
template <class ReadPoint>
std::size_t alignRange(std::size_t begin, std::size_t end, ReadPoint read, const Eigen::Matrix3f& r,
                       const Eigen::Vector3f& t, Eigen::Vector3f* out, Eigen::Vector3f& box_min,
                       Eigen::Vector3f& box_max) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float r00 = r(0, 0), r01 = r(0, 1), r02 = r(0, 2), r10 = r(1, 0), r11 = r(1, 1),
              r12 = r(1, 2), r20 = r(2, 0), r21 = r(2, 1), r22 = r(2, 2);
  const float tx = t.x(), ty = t.y(), tz = t.z();
  float lo_x = std::numeric_limits<float>::max(), lo_y = lo_x, lo_z = lo_x;
  float hi_x = -lo_x, hi_y = -lo_x, hi_z = -lo_x;
  std::size_t finite = 0;
  for (std::size_t i = begin; i < end; ++i) {
    float x, y, z;
    read(i, x, y, z);
    const float qx = r00 * x + r01 * y + r02 * z + tx;
    const float qy = r10 * x + r11 * y + r12 * z + ty;
    const float qz = r20 * x + r21 * y + r22 * z + tz;
    // x - x is 0 for a finite x and NaN for NaN or ±inf; the sum of the three is 0 only when
    // all three are finite.
    if ((qx - qx) + (qy - qy) + (qz - qz) == 0.0f) {
      out[i] = Eigen::Vector3f(qx, qy, qz);
      lo_x = std::min(lo_x, qx), lo_y = std::min(lo_y, qy), lo_z = std::min(lo_z, qz);
      hi_x = std::max(hi_x, qx), hi_y = std::max(hi_y, qy), hi_z = std::max(hi_z, qz);
      ++finite;
    } else {
      out[i] = Eigen::Vector3f(nan, nan, nan);
    }
  }
  box_min = Eigen::Vector3f(lo_x, lo_y, lo_z);
  box_max = Eigen::Vector3f(hi_x, hi_y, hi_z);
  return finite;
}

#if HOPE_SSE2
// Points [0, lastLoadable) can be read with a 16-byte load without passing the end of the
// cloud's count · stride bytes: all of them when a point takes 16 bytes or more, all but the
// last with 12 (x, y, z packed).
std::size_t lastLoadable(const PointsView& input) {
  const std::size_t bytes = input.count * input.stride;
  return bytes < 16 ? 0 : std::min(input.count, (bytes - 16) / input.stride + 1);
}

// alignRange for points of at least 12 bytes with x, y, z packed at the start (every PCL xyz
// type, a packed float array): one 16-byte load per point and the rotation as three column
// products, in the same order of operations per coordinate as the scalar loop, so the results are
// the same bit for bit. The fourth lane (padding) is computed and ignored.
std::size_t alignRangeSse(const std::uint8_t* data, std::size_t stride, std::size_t begin,
                          std::size_t end, const Eigen::Matrix3f& r, const Eigen::Vector3f& t,
                          Eigen::Vector3f* out, Eigen::Vector3f& box_min,
                          Eigen::Vector3f& box_max) {
  const __m128 col0 = _mm_setr_ps(r(0, 0), r(1, 0), r(2, 0), 0.f);
  const __m128 col1 = _mm_setr_ps(r(0, 1), r(1, 1), r(2, 1), 0.f);
  const __m128 col2 = _mm_setr_ps(r(0, 2), r(1, 2), r(2, 2), 0.f);
  const __m128 shift = _mm_setr_ps(t.x(), t.y(), t.z(), 0.f);
  const __m128 zero = _mm_setzero_ps();
  const __m128 nan = _mm_set1_ps(std::numeric_limits<float>::quiet_NaN());
  __m128 lo = _mm_set1_ps(std::numeric_limits<float>::max());
  __m128 hi = _mm_set1_ps(-std::numeric_limits<float>::max());
  std::size_t finite = 0;
  for (std::size_t i = begin; i < end; ++i) {
    const __m128 p = _mm_loadu_ps(reinterpret_cast<const float*>(data + i * stride));
    const __m128 x = _mm_shuffle_ps(p, p, _MM_SHUFFLE(0, 0, 0, 0));
    const __m128 y = _mm_shuffle_ps(p, p, _MM_SHUFFLE(1, 1, 1, 1));
    const __m128 z = _mm_shuffle_ps(p, p, _MM_SHUFFLE(2, 2, 2, 2));
    __m128 q = _mm_add_ps(_mm_mul_ps(col0, x), _mm_mul_ps(col1, y));
    q = _mm_add_ps(_mm_add_ps(q, _mm_mul_ps(col2, z)), shift);
    // q - q is 0 in a lane exactly when that lane is finite (see alignRange).
    const bool ok = (_mm_movemask_ps(_mm_cmpeq_ps(_mm_sub_ps(q, q), zero)) & 7) == 7;
    if (ok) {
      // min(q, lo) keeps lo on ties, as std::min(lo, q) does (the sign of a zero included).
      lo = _mm_min_ps(q, lo);
      hi = _mm_max_ps(q, hi);
      ++finite;
    } else {
      q = nan;
    }
    float* o = out[i].data();
    _mm_storel_pi(reinterpret_cast<__m64*>(o), q);  // x, y
    _mm_store_ss(o + 2, _mm_shuffle_ps(q, q, _MM_SHUFFLE(2, 2, 2, 2)));
  }
  alignas(16) float l[4], h[4];
  _mm_store_ps(l, lo);
  _mm_store_ps(h, hi);
  box_min = Eigen::Vector3f(l[0], l[1], l[2]);
  box_max = Eigen::Vector3f(h[0], h[1], h[2]);
  return finite;
}
#endif

// `range(begin, end, lo, hi)` over every point in shares, one per thread; the shares' boxes and
// counts are combined afterwards (min, max and sum: the same whatever the split).
template <class AlignRange>
std::size_t alignShares(std::size_t count, int threads, Eigen::Vector3f& box_min,
                        Eigen::Vector3f& box_max, AlignRange range) {
  constexpr int kMaxShares = 64;
  threads = std::min(threads, kMaxShares);
  Eigen::Vector3f lo[kMaxShares], hi[kMaxShares];
  std::size_t finite[kMaxShares] = {};
  const int shares = parallel::forShares(count, threads, std::size_t{1} << 15,
                                         [&](int share, std::size_t begin, std::size_t end) {
                                           finite[share] = range(begin, end, lo[share], hi[share]);
                                         });
  box_min = lo[0];
  box_max = hi[0];
  std::size_t total = finite[0];
  for (int k = 1; k < shares; ++k) {
    box_min = box_min.cwiseMin(lo[k]);
    box_max = box_max.cwiseMax(hi[k]);
    total += finite[k];
  }
  return total;
}

template <class ReadPoint>
std::size_t alignAll(std::size_t count, ReadPoint read, const Eigen::Matrix3f& r,
                     const Eigen::Vector3f& t, Eigen::Vector3f* out, Eigen::Vector3f& box_min,
                     Eigen::Vector3f& box_max, int threads) {
  return alignShares(
      count, threads, box_min, box_max,
      [&](std::size_t begin, std::size_t end, Eigen::Vector3f& lo, Eigen::Vector3f& hi) {
        return alignRange(begin, end, read, r, t, out, lo, hi);
      });
}

}  // namespace

std::size_t alignToGravity(const PointsView& input, const Orientation& orientation,
                           std::vector<Eigen::Vector3f>& aligned, const Eigen::Vector3d& origin,
                           Eigen::AlignedBox3f* finite_box, int threads) {
  threads = parallel::resolve(threads);
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
    auto packed = [data, stride](std::size_t i, float& x, float& y, float& z) {
      float xyz[3];
      std::memcpy(xyz, data + i * stride, sizeof(xyz));
      x = xyz[0], y = xyz[1], z = xyz[2];
    };
    bool vectorized = false;
#if HOPE_SSE2
    // 16-byte loads: with 12-byte points the load of the cloud's last point would pass its
    // end, so that one point goes through the scalar loop.
    vectorized = true;
    Eigen::Vector3f* out = aligned.data();
    const std::size_t loadable = lastLoadable(input);
    finite = alignShares(input.count, threads, lo, hi,
                         [&](std::size_t begin, std::size_t end, Eigen::Vector3f& share_lo,
                             Eigen::Vector3f& share_hi) {
                           const std::size_t split = std::clamp(loadable, begin, end);
                           std::size_t n = alignRangeSse(data, stride, begin, split, r, t, out,
                                                         share_lo, share_hi);
                           if (split < end) {
                             Eigen::Vector3f tail_lo, tail_hi;
                             n += alignRange(split, end, packed, r, t, out, tail_lo, tail_hi);
                             share_lo = share_lo.cwiseMin(tail_lo);
                             share_hi = share_hi.cwiseMax(tail_hi);
                           }
                           return n;
                         });
#endif
    if (!vectorized) finite = alignAll(input.count, packed, r, t, aligned.data(), lo, hi, threads);
  } else {
    auto fields = [&input](std::size_t i, float& x, float& y, float& z) {
      x = input.x(i), y = input.y(i), z = input.z(i);
    };
    finite = alignAll(input.count, fields, r, t, aligned.data(), lo, hi, threads);
  }
  if (finite_box) *finite_box = Eigen::AlignedBox3f(lo, hi);
  return finite;
}

bool alignmentIsIdentity(const PointsView& input, const Orientation& orientation,
                         const Eigen::Vector3d& origin) {
  const Eigen::Isometry3d& t = orientation.sensorToReference();
  return t.linear() == Eigen::Matrix3d::Identity() && t.translation() == origin &&
         input.x_offset == 0 && input.y_offset == 4 && input.z_offset == 8 && input.stride >= 12;
}

std::size_t finiteBox(const PointsView& input, Eigen::AlignedBox3f& box, int threads) {
  const float big = std::numeric_limits<float>::max();
  // The box and count of points [begin, end), one at a time.
  auto scalarBox = [&](std::size_t begin, std::size_t end, Eigen::Vector3f& lo,
                       Eigen::Vector3f& hi) -> std::size_t {
    float lo_x = big, lo_y = big, lo_z = big, hi_x = -big, hi_y = -big, hi_z = -big;
    std::size_t count = 0;
    for (std::size_t i = begin; i < end; ++i) {
      float xyz[3];  // packed at the start of each point (alignmentIsIdentity checked it)
      std::memcpy(xyz, input.data + i * input.stride, sizeof(xyz));
      const float x = xyz[0], y = xyz[1], z = xyz[2];
      // Not finite (NaN or ±inf, see alignRange): the point changes neither bound. Selects
      // rather than a branch, as scans mix finite and missing returns unpredictably.
      const bool finite = (x - x) + (y - y) + (z - z) == 0.0f;
      lo_x = std::min(lo_x, finite ? x : big), lo_y = std::min(lo_y, finite ? y : big);
      lo_z = std::min(lo_z, finite ? z : big);
      hi_x = std::max(hi_x, finite ? x : -big), hi_y = std::max(hi_y, finite ? y : -big);
      hi_z = std::max(hi_z, finite ? z : -big);
      count += finite ? 1 : 0;
    }
    lo = Eigen::Vector3f(lo_x, lo_y, lo_z);
    hi = Eigen::Vector3f(hi_x, hi_y, hi_z);
    return count;
  };
  // One share's box and count, by alignShares' rules (the same whatever the split).
  auto boxRange = [&](std::size_t begin, std::size_t end, Eigen::Vector3f& lo,
                      Eigen::Vector3f& hi) -> std::size_t {
#if HOPE_SSE2
    // One 16-byte load per point, the lane after z ignored; a 12-byte cloud's last point is
    // left to the scalar loop (its load would pass the end). min(p, lo) keeps lo on ties, as
    // std::min(lo, p) does.
    const std::size_t split = std::clamp(lastLoadable(input), begin, end);
    const __m128 zero = _mm_setzero_ps();
    __m128 vlo = _mm_set1_ps(big), vhi = _mm_set1_ps(-big);
    std::size_t count = 0;
    for (std::size_t i = begin; i < split; ++i) {
      const __m128 p = _mm_loadu_ps(reinterpret_cast<const float*>(input.data + i * input.stride));
      if ((_mm_movemask_ps(_mm_cmpeq_ps(_mm_sub_ps(p, p), zero)) & 7) != 7) continue;
      vlo = _mm_min_ps(p, vlo);
      vhi = _mm_max_ps(p, vhi);
      ++count;
    }
    alignas(16) float l[4], h[4];
    _mm_store_ps(l, vlo);
    _mm_store_ps(h, vhi);
    lo = Eigen::Vector3f(l[0], l[1], l[2]);
    hi = Eigen::Vector3f(h[0], h[1], h[2]);
    if (split < end) {
      Eigen::Vector3f tail_lo, tail_hi;
      count += scalarBox(split, end, tail_lo, tail_hi);
      lo = lo.cwiseMin(tail_lo);
      hi = hi.cwiseMax(tail_hi);
    }
    return count;
#else
    return scalarBox(begin, end, lo, hi);
#endif
  };
  Eigen::Vector3f lo, hi;
  const std::size_t total = alignShares(input.count, parallel::resolve(threads), lo, hi, boxRange);
  box = Eigen::AlignedBox3f(lo, hi);
  return total;
}

}  // namespace hope
