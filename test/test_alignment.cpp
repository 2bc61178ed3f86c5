// Gravity alignment (§2.2, Eq 1): every way of giving the orientation, and its bad inputs.
#include <cmath>
#include <limits>
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

}  // namespace test
}  // namespace hope
