#include "hope/synthetic/staircase.h"

#include <cmath>

namespace hope {
namespace synthetic {

namespace {

constexpr double kDegree = M_PI / 180.0;

// A camera at `eye` heading `yaw` (radians from +x towards +y), pitched down by `pitch`.
Camera cameraLooking(const Eigen::Vector3d& eye, double yaw, double pitch) {
  const Eigen::Vector3d forward(std::cos(pitch) * std::cos(yaw), std::cos(pitch) * std::sin(yaw),
                                -std::sin(pitch));
  const Eigen::Vector3d right(std::sin(yaw), -std::cos(yaw), 0.0);
  Camera camera = kinectV2Camera();
  camera.pose.linear().col(0) = right;
  camera.pose.linear().col(1) = forward.cross(right);  // down
  camera.pose.linear().col(2) = forward;
  camera.pose.translation() = eye;
  return camera;
}

}  // namespace

Scene staircase(const StaircaseLayout& layout) {
  using V = Eigen::Vector3d;
  Scene scene;
  const double top = layout.steps * layout.rise, flight = layout.steps * layout.run;
  const double half = 0.5 * layout.width, wall_height = top + 3.0;
  scene.add<Box>(V(layout.lower_end, -half, -0.05), V(0.0, half, 0.0), 0).color = {0.55f, 0.5f,
                                                                                   0.45f};
  // Each step a block from the floor up to its tread, the last one the upper floor.
  for (int k = 1; k <= layout.steps; ++k) {
    const double x0 = (k - 1) * layout.run;
    const double x1 = k == layout.steps ? layout.upper_end : flight;
    scene.add<Box>(V(x0, -half, 0.0), V(x1, half, k * layout.rise), k).color = {0.65f, 0.65f, 0.6f};
  }
  // Side walls, then the far walls at either end.
  const double length = layout.upper_end - layout.lower_end;
  const double middle = 0.5 * (layout.upper_end + layout.lower_end);
  for (double y : {-half, half}) {
    scene
        .add<Rectangle>(V(middle, y, 0.5 * wall_height - 0.05), V(1, 0, 0), V(0, 0, 1),
                        0.5 * length, 0.5 * wall_height + 0.05, kNoPlane)
        .color = {0.8f, 0.8f, 0.75f};
  }
  if (layout.far_walls) {
    for (double x : {layout.lower_end, layout.upper_end}) {
      scene
          .add<Rectangle>(V(x, 0, 0.5 * wall_height - 0.05), V(0, 1, 0), V(0, 0, 1), half,
                          0.5 * wall_height + 0.05, kNoPlane)
          .color = {0.75f, 0.75f, 0.8f};
    }
  }
  return scene;
}

Camera kinectV2Camera() {
  Camera camera;
  camera.width = 960;
  camera.height = 540;
  camera.intrinsics = {540.7, 540.7, 479.8, 269.6};
  return camera;
}

SensorNoise kinectV2Noise() {
  SensorNoise noise;
  noise.sigma_at_1m = 0.0008;
  noise.max_incidence = 80 * kDegree;
  return noise;
}

std::vector<StaircaseView> staircaseViews(const StaircaseLayout& layout) {
  using V = Eigen::Vector3d;
  const double top = layout.steps * layout.rise, flight = layout.steps * layout.run;
  const V below(-2.0, 0.0, 1.5), above(flight + 1.0, 0.0, top + 1.5);
  return {{"head-on, level", cameraLooking(below, 0.0, 0.0)},
          {"head-on, 20° down", cameraLooking(below, 0.0, 20 * kDegree)},
          {"from below, 10° up", cameraLooking(below, 0.0, -10 * kDegree)},
          {"from above, 30° down", cameraLooking(above, M_PI, 30 * kDegree)},
          {"from above, 45° down", cameraLooking(above, M_PI, 45 * kDegree)}};
}

}  // namespace synthetic
}  // namespace hope
