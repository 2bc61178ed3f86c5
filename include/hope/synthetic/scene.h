// Synthetic scenes with an exact answer, for tests, the demo and benchmarks: primitives that
// can be ray-cast by a simulated depth camera or scanned from above into an unorganized cloud,
// each hit carrying the ground-truth plane it belongs to.
#pragma once

#include <cmath>
#include <cstdint>
#include <memory>
#include <random>
#include <vector>

#include <pcl/point_cloud.h>
#include <pcl/point_types.h>
#include <Eigen/Geometry>
#include <opencv2/core.hpp>

#include "hope/depth_image.h"

namespace hope {
namespace synthetic {

// Ground-truth label of surfaces that are not a horizontal plane.
constexpr int kNoPlane = -1;
// Ground-truth thing of primitives that belong to no object (a floor, a wall).
constexpr int kNoThing = -1;

struct Hit {
  double t = 0;                                       // ray parameter (distance for unit rays)
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();  // outward unit normal
  int label = kNoPlane;
  int thing = kNoThing;  // the physical thing hit (Primitive::thing)
};

class Primitive {
 public:
  virtual ~Primitive() = default;
  // The nearest hit with t > 1e-9 along origin + t·direction, if any.
  virtual bool intersect(const Eigen::Vector3d& origin, const Eigen::Vector3d& direction,
                         Hit& hit) const = 0;
  Eigen::Vector3f color{0.7f, 0.7f, 0.7f};  // RGB in [0, 1], for the rendered image
  // The physical thing this primitive is part of (a table's top and legs share one), the truth
  // an object segmentation is scored against; kNoThing for what is no object (the floor).
  int thing = kNoThing;
};

// A box with rotation `rotation` about its centre. Its top face (local +z) carries
// `top_label`; the other faces are no plane.
struct Box : Primitive {
  Box(const Eigen::Vector3d& min_corner, const Eigen::Vector3d& max_corner, int top_label,
      const Eigen::Matrix3d& rotation = Eigen::Matrix3d::Identity());
  bool intersect(const Eigen::Vector3d& origin, const Eigen::Vector3d& direction,
                 Hit& hit) const override;
  Eigen::Vector3d center, half;
  Eigen::Matrix3d rotation;
  int top_label;
};

// A double-sided rectangle: centre, two orthogonal unit axes, half extents along them.
struct Rectangle : Primitive {
  Rectangle(const Eigen::Vector3d& center, const Eigen::Vector3d& axis_u,
            const Eigen::Vector3d& axis_v, double half_u, double half_v, int label);
  bool intersect(const Eigen::Vector3d& origin, const Eigen::Vector3d& direction,
                 Hit& hit) const override;
  Eigen::Vector3d center, u, v, normal;
  double half_u, half_v;
  int label;
};

struct Sphere : Primitive {
  Sphere(const Eigen::Vector3d& center, double radius) : center(center), radius(radius) {}
  bool intersect(const Eigen::Vector3d& origin, const Eigen::Vector3d& direction,
                 Hit& hit) const override;
  Eigen::Vector3d center;
  double radius;
};

// A tube (open cylinder) of `radius` around the segment from `a` to `b`.
struct Cylinder : Primitive {
  Cylinder(const Eigen::Vector3d& a, const Eigen::Vector3d& b, double radius)
      : a(a), b(b), radius(radius) {}
  bool intersect(const Eigen::Vector3d& origin, const Eigen::Vector3d& direction,
                 Hit& hit) const override;
  Eigen::Vector3d a, b;
  double radius;
};

// An upright cone: apex at `apex`, axis along −z, base of `base_radius` at apex.z − height.
struct Cone : Primitive {
  Cone(const Eigen::Vector3d& apex, double base_radius, double height)
      : apex(apex), base_radius(base_radius), height(height) {}
  bool intersect(const Eigen::Vector3d& origin, const Eigen::Vector3d& direction,
                 Hit& hit) const override;
  Eigen::Vector3d apex;
  double base_radius, height;
};

struct Camera {
  int width = 640, height = 480;
  PinholeIntrinsics intrinsics = PinholeIntrinsics::tumFreiburg1();
  // Pose of the optical frame (x right, y down, z forward) in the world: p_w = R p_c + t.
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  // A camera at `eye` looking at `target`, image rows pointing roughly down the world z axis.
  static Camera lookingAt(const Eigen::Vector3d& eye, const Eigen::Vector3d& target);
};

// Range-sensor imperfections. Defaults model a structured-light camera.
struct SensorNoise {
  double sigma_at_1m = 0.0015;  // depth standard deviation at 1 m; grows with z²
  // Depth quantization step at 1 m, growing with z² like a structured-light sensor's
  // disparity steps (0 = none). Kinect-class: 1 / (f · baseline · subpixels) ≈ 2.9 mm.
  double quantization_at_1m = 0.0;
  // Rays meeting a surface at more than this angle from its normal return no depth (radians;
  // π/2 = never), like a projector pattern lost at grazing incidence.
  double max_incidence = M_PI / 2;
  bool enabled = true;
  std::uint32_t seed = 1;
  // A Kinect-like sensor: noise, quantization and grazing dropouts at 80°.
  static SensorNoise kinectLike();
};

struct RenderedFrame {
  cv::Mat depth;   // CV_32FC1 metres, 0 where nothing was hit
  cv::Mat bgr;     // CV_8UC3 shaded image
  cv::Mat labels;  // CV_32SC1 ground-truth plane label per pixel (kNoPlane elsewhere)
  cv::Mat things;  // CV_32SC1 ground-truth thing per pixel (Primitive::thing; kNoThing elsewhere)
};

struct LabeledCloud {
  pcl::PointCloud<pcl::PointXYZ> cloud;
  std::vector<int> labels;  // ground truth per point
};

class Scene {
 public:
  template <class P, class... Args>
  P& add(Args&&... args) {
    auto primitive = std::make_unique<P>(std::forward<Args>(args)...);
    P& ref = *primitive;
    primitives_.push_back(std::move(primitive));
    return ref;
  }
  bool intersect(const Eigen::Vector3d& origin, const Eigen::Vector3d& direction, Hit& hit,
                 Eigen::Vector3f* color = nullptr) const;

  // Ray-casts a pinhole depth camera: an organized view like an RGB-D sensor.
  RenderedFrame render(const Camera& camera, const SensorNoise& noise = SensorNoise()) const;
  // Casts vertical rays down from above on a square grid of `spacing` over [x0,x1]×[y0,y1]:
  // an unorganized cloud of everything visible from above, in world coordinates.
  LabeledCloud scanFromAbove(double x0, double y0, double x1, double y1, double spacing,
                             double noise_sigma = 0.0, std::uint32_t seed = 1) const;

 private:
  std::vector<std::unique_ptr<Primitive>> primitives_;
};

// Samples the rectangle densely on a grid of `spacing` (both sides, as a flat sheet): for
// scenes where surfaces overlap in xy, which a scan from above cannot see.
void sampleRectangle(const Rectangle& rect, double spacing, int label, LabeledCloud& out,
                     double noise_sigma = 0.0, std::uint32_t seed = 1);

// The demo room: floor, a table with a book, a cone and a lying tube on it, a low cabinet, a
// block of two stair treads, a ramp and a ball. Ground-truth plane labels: 0 floor, 1 table
// top, 2 cabinet top, 3 and 4 the treads, 5 the book's top. Things (Primitive::thing, the
// objects a person would name): demo::Thing.
Scene demoRoom();
namespace demo {
enum Thing { kTable, kCabinet, kStairBlock, kBook, kRamp, kBall, kCone, kTube, kThings };
}  // namespace demo
// A camera that sees the demo room like a person holding an RGB-D camera at 1.5 m.
Camera demoCamera();
// demoCamera() turned by `yaw` radians about the vertical through its eye: a robot turning in
// place.
Camera demoCameraTurned(double yaw);

}  // namespace synthetic
}  // namespace hope
