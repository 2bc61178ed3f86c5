// Gravity alignment (§2.2, Eq 1): every way of giving the orientation, and its bad inputs.
#include <cmath>
#include <limits>
#include <random>
#include <stdexcept>

#include "helpers.h"
#include "hope/gravity_alignment.h"

namespace hope {
namespace test {

namespace {

V3 apply(const Orientation& o, const V3& p) { return o.sensorToReference() * p; }

void expectNear(const V3& a, const V3& b, double tol = 1e-9) {
  EXPECT_NEAR(a.x(), b.x(), tol);
  EXPECT_NEAR(a.y(), b.y(), tol);
  EXPECT_NEAR(a.z(), b.z(), tol);
}

}  // namespace

TEST(Alignment, QuaternionFollowsTheRosConventionNotThePrintedEq2) {
  // 90° about z: the sensor's x axis points along the reference y axis.
  const double s = std::sqrt(0.5);
  expectNear(apply(Orientation::fromQuaternion(0, 0, s, s), V3::UnitX()), V3::UnitY());
}

TEST(Alignment, NonUnitQuaternionIsNormalized) {
  const Orientation unit = Orientation::fromQuaternion(0.1, 0.2, 0.3, 0.9);
  const Orientation scaled = Orientation::fromQuaternion(0.3, 0.6, 0.9, 2.7);
  expectNear(apply(unit, V3(1, 2, 3)), apply(scaled, V3(1, 2, 3)));
}

// Components whose squares overflow (a corrupt line of 1e200s) or underflow still name their
// rotation: normalized without squaring them first, never taken as zero or as no rotation.
TEST(Alignment, QuaternionsAndGravityOfExtremeLengthNameTheirRotation) {
  const Orientation unit = Orientation::fromQuaternion(0.1, 0.2, 0.3, 0.9);
  expectNear(apply(Orientation::fromQuaternion(1e199, 2e199, 3e199, 9e199), V3(1, 2, 3)),
             apply(unit, V3(1, 2, 3)));
  expectNear(apply(Orientation::fromQuaternion(1e307, 2e307, 3e307, 9e307), V3(1, 2, 3)),
             apply(unit, V3(1, 2, 3)));
  const Orientation level = Orientation::fromGravity(0, -9.81, 0);
  expectNear(apply(Orientation::fromGravity(0, -1e300, 0), V3(1, 2, 3)), apply(level, V3(1, 2, 3)));
  expectNear(apply(Orientation::fromGravity(1e-300, -1e300, 0), V3(1, 2, 3)),
             apply(level, V3(1, 2, 3)));
}

TEST(Alignment, ZeroNanAndInfiniteQuaternionsAreRejectedWithAClearError) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  try {
    Orientation::fromQuaternion(0, 0, 0, 0);
    FAIL() << "zero quaternion accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("zero length"), std::string::npos) << e.what();
  }
  EXPECT_THROW(Orientation::fromQuaternion(nan, 0, 0, 1), std::invalid_argument);
  EXPECT_THROW(Orientation::fromQuaternion(0, inf, 0, 1), std::invalid_argument);
  EXPECT_THROW(Orientation::fromPose(nan, 0, 0, 0, 0, 0, 1), std::invalid_argument);
  EXPECT_THROW(Orientation::fromRollPitchYaw(0, inf, 0), std::invalid_argument);
  EXPECT_THROW(Orientation::fromGravity(0, 0, 0), std::invalid_argument);
  EXPECT_THROW(Orientation::fromGravity(nan, 0, 9.8), std::invalid_argument);
}

TEST(Alignment, RollPitchYawUsesFixedAxesLikeTf2) {
  // Roll 90° takes y to z; yaw 90° takes x to y; combined R = Rz·Ry·Rx.
  expectNear(apply(Orientation::fromRollPitchYaw(M_PI / 2, 0, 0), V3::UnitY()), V3::UnitZ());
  expectNear(apply(Orientation::fromRollPitchYaw(0, 0, M_PI / 2), V3::UnitX()), V3::UnitY());
  const Eigen::Quaterniond q = Eigen::AngleAxisd(0.3, V3::UnitZ()) *
                               Eigen::AngleAxisd(-0.2, V3::UnitY()) *
                               Eigen::AngleAxisd(0.1, V3::UnitX());
  expectNear(apply(Orientation::fromRollPitchYaw(0.1, -0.2, 0.3), V3(1, 2, 3)),
             apply(Orientation::fromQuaternion(q.x(), q.y(), q.z(), q.w()), V3(1, 2, 3)));
}

TEST(Alignment, PoseAddsTheTranslation) {
  expectNear(apply(Orientation::fromPose(1, 2, 3, 0, 0, 0, 1), V3(0.5, 0, 0)), V3(1.5, 2, 3));
}

TEST(Alignment, GravityPointingUpInTheSensorFrameBecomesZ) {
  // A camera optical frame held level: y points down, so the accelerometer reads −y.
  const Orientation o = Orientation::fromGravity(0, -9.81, 0);
  expectNear(apply(o, V3(0, -1, 0)), V3::UnitZ());
  // A sensor pitched so that gravity is split between x and z.
  const Orientation p = Orientation::fromGravity(3, 0, 4);
  expectNear(apply(p, V3(0.6, 0, 0.8)), V3::UnitZ());
  // Upside down.
  expectNear(apply(Orientation::fromGravity(0, 0, -9.81), V3(0, 0, -1)), V3::UnitZ());
}

TEST(Alignment, NonFinitePointsStayInPlaceAsNaN) {
  pcl::PointCloud<pcl::PointXYZ> cloud;
  cloud.push_back(pcl::PointXYZ(1, 0, 0));
  cloud.push_back(pcl::PointXYZ(NAN, 0, 0));
  cloud.push_back(pcl::PointXYZ(0, INFINITY, 0));
  cloud.push_back(pcl::PointXYZ(0, 0, 2));
  std::vector<Eigen::Vector3f> aligned;
  const std::size_t finite =
      alignToGravity(PointsView::of(cloud), Orientation::fromPose(0, 0, 1, 0, 0, 0, 1), aligned);
  EXPECT_EQ(finite, 2u);
  ASSERT_EQ(aligned.size(), 4u);
  EXPECT_FLOAT_EQ(aligned[0].z(), 1.0f);
  EXPECT_TRUE(std::isnan(aligned[1].x()));
  EXPECT_TRUE(std::isnan(aligned[2].x()));
  EXPECT_FLOAT_EQ(aligned[3].z(), 3.0f);
}

// The packed 16-byte layout takes a vectorized loop (SSE2 on x86-64), other layouts the plain
// one; both, and the box-only pass of a cloud needing no rotation, must agree bit for bit:
// the same aligned points, NaN for every point with a non-finite or overflowing coordinate,
// the same finite count and box, on random points with NaN, ±inf and huge values mixed in.
TEST(Alignment, VectorizedAndPlainLoopsAgreeBitForBit) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> uniform(-20.f, 20.f);
  pcl::PointCloud<pcl::PointXYZ> cloud;
  for (int i = 0; i < 5000; ++i) {
    pcl::PointXYZ p(uniform(rng), uniform(rng), uniform(rng));
    if (i % 97 == 1) p.x = NAN;
    if (i % 89 == 2) p.y = INFINITY;
    if (i % 83 == 3) p.z = -INFINITY;
    if (i % 79 == 4) p.x = 3e38f;  // finite, overflows once rotated and shifted
    if (i % 71 == 5) p.y = -0.0f;
    cloud.push_back(p);
  }
  // The last point sets the box's maximum: with 12-byte points it is the one the vectorized
  // loop must leave to the scalar one (a 16-byte load would pass the end; ASan would see it).
  cloud.push_back(pcl::PointXYZ(25.f, 26.f, 27.f));
  const ShiftedCopy shifted(cloud);
  const PointsView plain = shifted.view();
  // Two layouts the vectorized loop reads: PCL's 16-byte points and packed 12-byte ones in a
  // buffer that ends with the last point.
  std::vector<Eigen::Vector3f> packed;
  for (const pcl::PointXYZ& p : cloud) packed.emplace_back(p.x, p.y, p.z);
  PointsView packed_view;
  packed_view.data = reinterpret_cast<const std::uint8_t*>(packed.data());
  packed_view.count = packed.size();
  packed_view.stride = sizeof(Eigen::Vector3f);
  packed_view.width = static_cast<std::uint32_t>(packed.size());
  for (const PointsView& view : {PointsView::of(cloud), packed_view}) {
    SCOPED_TRACE("stride " + std::to_string(view.stride));
    for (const Orientation& o : {Orientation::fromPose(0.3, -1, 2, 0.2, -0.4, 0.1, 0.9),
                                 Orientation::fromRollPitchYaw(1.2, -0.3, 2.0)}) {
      for (int threads : {1, 2}) {
        std::vector<Eigen::Vector3f> fast, slow;
        Eigen::AlignedBox3f fast_box, slow_box;
        const std::size_t fast_finite =
            alignToGravity(view, o, fast, Eigen::Vector3d::Zero(), &fast_box, threads);
        const std::size_t slow_finite =
            alignToGravity(plain, o, slow, Eigen::Vector3d::Zero(), &slow_box, threads);
        EXPECT_EQ(fast_finite, slow_finite);
        EXPECT_LT(fast_finite, cloud.size());  // the bad points were caught
        EXPECT_GT(fast_finite, cloud.size() * 9 / 10);
        EXPECT_EQ(fast_box.min(), slow_box.min());
        EXPECT_EQ(fast_box.max(), slow_box.max());
        ASSERT_EQ(fast.size(), slow.size());
        for (std::size_t i = 0; i < fast.size(); ++i) {
          if (slow[i].allFinite()) {
            EXPECT_EQ(fast[i], slow[i]) << "point " << i;
          } else {
            EXPECT_TRUE(fast[i].array().isNaN().all()) << "point " << i;
            EXPECT_TRUE(slow[i].array().isNaN().all()) << "point " << i;
          }
        }
      }
    }
    // No rotation: the box-only pass against the box of the copy; the last point holds the
    // maximum y and z (x: a 3e38 point, finite without a rotation).
    Eigen::AlignedBox3f in_place_box, copy_box;
    std::vector<Eigen::Vector3f> copy;
    const std::size_t in_place = finiteBox(view, in_place_box, 2);
    const std::size_t copied =
        alignToGravity(plain, Orientation::identity(), copy, Eigen::Vector3d::Zero(), &copy_box, 1);
    EXPECT_EQ(in_place, copied);
    EXPECT_EQ(in_place_box.min(), copy_box.min());
    EXPECT_EQ(in_place_box.max(), copy_box.max());
    EXPECT_EQ(in_place_box.max().y(), 26.f);
    EXPECT_EQ(in_place_box.max().z(), 27.f);
  }
}

}  // namespace test
}  // namespace hope
