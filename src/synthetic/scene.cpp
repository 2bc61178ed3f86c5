#include "hope/synthetic/scene.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace hope {
namespace synthetic {

namespace {

constexpr double kEpsilon = 1e-9;

// The smaller root of a·t² + b·t + c = 0 above kEpsilon that `accept` agrees with.
template <class Accept>
bool smallestRoot(double a, double b, double c, Accept accept, double& t) {
  double roots[2];
  int n = 0;
  if (std::fabs(a) < 1e-14) {
    if (std::fabs(b) < 1e-14) return false;
    roots[n++] = -c / b;
  } else {
    const double disc = b * b - 4 * a * c;
    if (disc < 0) return false;
    const double s = std::sqrt(disc);
    roots[n++] = (-b - s) / (2 * a);
    roots[n++] = (-b + s) / (2 * a);
    if (roots[0] > roots[1]) std::swap(roots[0], roots[1]);
  }
  for (int i = 0; i < n; ++i) {
    if (roots[i] > kEpsilon && accept(roots[i])) {
      t = roots[i];
      return true;
    }
  }
  return false;
}

}  // namespace

Box::Box(const Eigen::Vector3d& min_corner, const Eigen::Vector3d& max_corner, int top_label,
         const Eigen::Matrix3d& rotation)
    : center(0.5 * (min_corner + max_corner)),
      half(0.5 * (max_corner - min_corner)),
      rotation(rotation),
      top_label(top_label) {}

bool Box::intersect(const Eigen::Vector3d& origin, const Eigen::Vector3d& direction,
                    Hit& hit) const {
  const Eigen::Vector3d o = rotation.transpose() * (origin - center);
  const Eigen::Vector3d d = rotation.transpose() * direction;
  double t_near = -std::numeric_limits<double>::infinity();
  double t_far = std::numeric_limits<double>::infinity();
  int near_axis = 0, far_axis = 0;
  for (int axis = 0; axis < 3; ++axis) {
    if (std::fabs(d[axis]) < 1e-14) {
      if (std::fabs(o[axis]) > half[axis]) return false;
      continue;
    }
    double t1 = (-half[axis] - o[axis]) / d[axis];
    double t2 = (half[axis] - o[axis]) / d[axis];
    if (t1 > t2) std::swap(t1, t2);
    if (t1 > t_near) {
      t_near = t1;
      near_axis = axis;
    }
    if (t2 < t_far) {
      t_far = t2;
      far_axis = axis;
    }
  }
  if (t_far < t_near || t_far <= kEpsilon) return false;
  const bool from_outside = t_near > kEpsilon;
  const int axis = from_outside ? near_axis : far_axis;
  hit.t = from_outside ? t_near : t_far;
  Eigen::Vector3d local_normal = Eigen::Vector3d::Zero();
  // Entering through a face means moving against its outward normal.
  local_normal[axis] = (d[axis] < 0) == from_outside ? 1.0 : -1.0;
  hit.normal = rotation * local_normal;
  hit.label = (axis == 2 && local_normal.z() > 0) ? top_label : kNoPlane;
  return true;
}

Rectangle::Rectangle(const Eigen::Vector3d& center, const Eigen::Vector3d& axis_u,
                     const Eigen::Vector3d& axis_v, double half_u, double half_v, int label)
    : center(center),
      u(axis_u.normalized()),
      v(axis_v.normalized()),
      normal(axis_u.cross(axis_v).normalized()),
      half_u(half_u),
      half_v(half_v),
      label(label) {}

bool Rectangle::intersect(const Eigen::Vector3d& origin, const Eigen::Vector3d& direction,
                          Hit& hit) const {
  const double denom = normal.dot(direction);
  if (std::fabs(denom) < 1e-14) return false;
  const double t = normal.dot(center - origin) / denom;
  if (t <= kEpsilon) return false;
  const Eigen::Vector3d local = origin + t * direction - center;
  if (std::fabs(local.dot(u)) > half_u || std::fabs(local.dot(v)) > half_v) return false;
  hit.t = t;
  hit.normal = denom < 0 ? normal : Eigen::Vector3d(-normal);
  hit.label = label;
  return true;
}

bool Sphere::intersect(const Eigen::Vector3d& origin, const Eigen::Vector3d& direction,
                       Hit& hit) const {
  const Eigen::Vector3d w = origin - center;
  double t;
  if (!smallestRoot(
          direction.squaredNorm(), 2 * w.dot(direction), w.squaredNorm() - radius * radius,
          [](double) { return true; }, t)) {
    return false;
  }
  hit.t = t;
  hit.normal = (origin + t * direction - center).normalized();
  hit.label = kNoPlane;
  return true;
}

bool Cylinder::intersect(const Eigen::Vector3d& origin, const Eigen::Vector3d& direction,
                         Hit& hit) const {
  const Eigen::Vector3d axis = b - a;
  const double length = axis.norm();
  const Eigen::Vector3d unit = axis / length;
  const Eigen::Vector3d w = origin - a;
  const Eigen::Vector3d d_perp = direction - direction.dot(unit) * unit;
  const Eigen::Vector3d w_perp = w - w.dot(unit) * unit;
  double t;
  auto within_length = [&](double s) {
    const double along = (w + s * direction).dot(unit);
    return along >= 0 && along <= length;
  };
  if (!smallestRoot(d_perp.squaredNorm(), 2 * w_perp.dot(d_perp),
                    w_perp.squaredNorm() - radius * radius, within_length, t)) {
    return false;
  }
  hit.t = t;
  const Eigen::Vector3d radial = w_perp + t * d_perp;
  hit.normal = radial.normalized();
  if (hit.normal.dot(direction) > 0) hit.normal = -hit.normal;  // seen from inside
  hit.label = kNoPlane;
  return true;
}

bool Cone::intersect(const Eigen::Vector3d& origin, const Eigen::Vector3d& direction,
                     Hit& hit) const {
  // Surface: x² + y² = k²·h², h = apex.z − z ∈ [0, height], k = base_radius / height.
  const double k2 = (base_radius / height) * (base_radius / height);
  const double ox = origin.x() - apex.x(), oy = origin.y() - apex.y(), oh = apex.z() - origin.z();
  const double dx = direction.x(), dy = direction.y(), dh = -direction.z();
  double t;
  auto on_surface = [&](double s) {
    const double h = oh + s * dh;
    return h >= 0 && h <= height;
  };
  if (!smallestRoot(dx * dx + dy * dy - k2 * dh * dh, 2 * (ox * dx + oy * dy - k2 * oh * dh),
                    ox * ox + oy * oy - k2 * oh * oh, on_surface, t)) {
    return false;
  }
  hit.t = t;
  const double x = ox + t * dx, y = oy + t * dy, h = oh + t * dh;
  hit.normal = Eigen::Vector3d(x, y, k2 * h).normalized();
  hit.label = kNoPlane;
  return true;
}

SensorNoise SensorNoise::kinectLike() {
  SensorNoise noise;
  noise.quantization_at_1m = 0.0029;
  noise.max_incidence = 80.0 * M_PI / 180.0;
  return noise;
}

Camera Camera::lookingAt(const Eigen::Vector3d& eye, const Eigen::Vector3d& target) {
  Camera camera;
  const Eigen::Vector3d forward = (target - eye).normalized();
  Eigen::Vector3d right = forward.cross(Eigen::Vector3d::UnitZ());
  if (right.norm() < 1e-9) right = Eigen::Vector3d::UnitX();  // looking straight up or down
  right.normalize();
  const Eigen::Vector3d down = forward.cross(right);
  camera.pose.linear().col(0) = right;
  camera.pose.linear().col(1) = down;
  camera.pose.linear().col(2) = forward;
  camera.pose.translation() = eye;
  return camera;
}

bool Scene::intersect(const Eigen::Vector3d& origin, const Eigen::Vector3d& direction, Hit& hit,
                      Eigen::Vector3f* color) const {
  bool any = false;
  Hit candidate;
  for (const auto& primitive : primitives_) {
    if (primitive->intersect(origin, direction, candidate) && (!any || candidate.t < hit.t)) {
      hit = candidate;
      hit.thing = primitive->thing;
      any = true;
      if (color) *color = primitive->color;
    }
  }
  return any;
}

RenderedFrame Scene::render(const Camera& camera, const SensorNoise& noise) const {
  RenderedFrame frame;
  frame.depth = cv::Mat(camera.height, camera.width, CV_32FC1, cv::Scalar(0));
  frame.bgr = cv::Mat(camera.height, camera.width, CV_8UC3, cv::Scalar(0, 0, 0));
  frame.labels = cv::Mat(camera.height, camera.width, CV_32SC1, cv::Scalar(kNoPlane));
  frame.things = cv::Mat(camera.height, camera.width, CV_32SC1, cv::Scalar(kNoThing));
  std::mt19937 rng(noise.seed);
  std::normal_distribution<double> gauss(0.0, 1.0);
  const Eigen::Matrix3d r = camera.pose.linear();
  const Eigen::Vector3d eye = camera.pose.translation();
  const PinholeIntrinsics& k = camera.intrinsics;
  for (int row = 0; row < camera.height; ++row) {
    for (int col = 0; col < camera.width; ++col) {
      // With z = 1 in the camera frame, the ray parameter is the depth itself.
      const Eigen::Vector3d ray_camera((col - k.cx) / k.fx, (row - k.cy) / k.fy, 1.0);
      const Eigen::Vector3d ray = r * ray_camera;
      Hit hit;
      Eigen::Vector3f color;
      if (!intersect(eye, ray, hit, &color)) continue;
      double depth = hit.t;
      if (noise.enabled) {
        const double cos_incidence = std::fabs(hit.normal.dot(ray.normalized()));
        if (cos_incidence < std::cos(noise.max_incidence)) continue;  // grazing: no return
        depth += gauss(rng) * noise.sigma_at_1m * depth * depth;
        if (noise.quantization_at_1m > 0) {
          const double step = noise.quantization_at_1m * depth * depth;
          depth = step * std::round(depth / step);
        }
      }
      frame.depth.at<float>(row, col) = static_cast<float>(depth);
      frame.labels.at<std::int32_t>(row, col) = hit.label;
      frame.things.at<std::int32_t>(row, col) = hit.thing;
      const double lambert = std::fabs(hit.normal.dot(ray.normalized()));
      const Eigen::Vector3f shaded = color * static_cast<float>(0.35 + 0.65 * lambert) * 255.f;
      frame.bgr.at<cv::Vec3b>(row, col) =
          cv::Vec3b(static_cast<uchar>(shaded.z()), static_cast<uchar>(shaded.y()),
                    static_cast<uchar>(shaded.x()));
    }
  }
  return frame;
}

LabeledCloud Scene::scanFromAbove(double x0, double y0, double x1, double y1, double spacing,
                                  double noise_sigma, std::uint32_t seed) const {
  LabeledCloud out;
  std::mt19937 rng(seed);
  std::normal_distribution<double> gauss(0.0, noise_sigma > 0 ? noise_sigma : 1.0);
  const Eigen::Vector3d down(0, 0, -1);
  for (double y = y0; y <= y1 + 1e-12; y += spacing) {
    for (double x = x0; x <= x1 + 1e-12; x += spacing) {
      const Eigen::Vector3d origin(x, y, 1000.0);
      Hit hit;
      if (!intersect(origin, down, hit)) continue;
      const Eigen::Vector3d p = origin + hit.t * down;
      const double z = p.z() + (noise_sigma > 0 ? gauss(rng) : 0.0);
      out.cloud.push_back(pcl::PointXYZ(static_cast<float>(p.x()), static_cast<float>(p.y()),
                                        static_cast<float>(z)));
      out.labels.push_back(hit.label);
    }
  }
  return out;
}

void sampleRectangle(const Rectangle& rect, double spacing, int label, LabeledCloud& out,
                     double noise_sigma, std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> gauss(0.0, noise_sigma > 0 ? noise_sigma : 1.0);
  for (double a = -rect.half_u; a <= rect.half_u + 1e-12; a += spacing) {
    for (double b = -rect.half_v; b <= rect.half_v + 1e-12; b += spacing) {
      Eigen::Vector3d p = rect.center + a * rect.u + b * rect.v;
      if (noise_sigma > 0) p += gauss(rng) * rect.normal;
      out.cloud.push_back(pcl::PointXYZ(static_cast<float>(p.x()), static_cast<float>(p.y()),
                                        static_cast<float>(p.z())));
      out.labels.push_back(label);
    }
  }
}

Scene demoRoom() {
  Scene scene;
  using V = Eigen::Vector3d;
  auto thing = [](Primitive& primitive, int which, const Eigen::Vector3f& color) {
    primitive.thing = which;
    primitive.color = color;
  };
  thing(scene.add<Box>(V(-1, -3, -0.05), V(5, 3, 0.0), 0), kNoThing, {0.55f, 0.5f, 0.45f});
  // Table: top 0.72–0.75 m on four legs.
  thing(scene.add<Box>(V(1.3, -0.9, 0.72), V(2.2, 0.1, 0.75), 1), demo::kTable,
        {0.75f, 0.6f, 0.4f});
  for (double x : {1.33, 2.13}) {
    for (double y : {-0.87, 0.03}) {
      thing(scene.add<Box>(V(x, y, 0), V(x + 0.04, y + 0.04, 0.72), kNoPlane), demo::kTable,
            {0.3f, 0.3f, 0.3f});
    }
  }
  // A low cabinet.
  thing(scene.add<Box>(V(1.3, 0.45, 0.0), V(1.9, 1.1, 0.45), 2), demo::kCabinet,
        {0.4f, 0.55f, 0.7f});
  // Two stair treads: 0.17 m and 0.34 m, one block.
  thing(scene.add<Box>(V(2.6, -1.2, 0.0), V(3.6, 1.4, 0.17), 3), demo::kStairBlock,
        {0.65f, 0.65f, 0.65f});
  thing(scene.add<Box>(V(2.9, -1.2, 0.17), V(3.6, 1.4, 0.34), 4), demo::kStairBlock,
        {0.6f, 0.6f, 0.65f});
  // A book on the table, 5 cm high: a separate plane at 0.80 m.
  thing(scene.add<Box>(V(1.7, -0.45, 0.75), V(1.95, -0.25, 0.80), 5), demo::kBook,
        {0.8f, 0.2f, 0.2f});
  // Things that look horizontal locally but are not planes.
  const double slope = 0.5;  // rad, well above atan(0.02 / 0.05) ≈ 0.38
  Eigen::Matrix3d tilt = Eigen::AngleAxisd(slope, V::UnitY()).toRotationMatrix();
  thing(scene.add<Box>(V(0.9, -1.3, 0.2), V(1.3, -0.9, 0.25), kNoPlane, tilt), demo::kRamp,
        {0.3f, 0.6f, 0.3f});
  thing(scene.add<Sphere>(V(1.1, 0.2, 0.15), 0.15), demo::kBall, {0.9f, 0.8f, 0.2f});
  thing(scene.add<Cone>(V(1.5, -0.2, 1.0), 0.1, 0.25), demo::kCone, {0.9f, 0.5f, 0.1f});
  thing(scene.add<Cylinder>(V(1.95, -0.8, 0.79), V(2.15, -0.55, 0.79), 0.04), demo::kTube,
        {0.5f, 0.3f, 0.7f});
  return scene;
}

Camera demoCamera() { return demoCameraTurned(0.0); }

Camera demoCameraTurned(double yaw) {
  const Eigen::Vector3d eye(0.0, -0.1, 1.5), target(2.0, 0.0, 0.35);
  return Camera::lookingAt(eye,
                           eye + Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) * (target - eye));
}

}  // namespace synthetic
}  // namespace hope
