#include "hope/synthetic/sequences.h"

#include <cmath>
#include <random>
#include <stdexcept>

namespace hope {
namespace synthetic {

using V = Eigen::Vector3d;

std::vector<std::pair<double, double>> patternObjectBlockSpans() {
  const double widths[5] = {0.02, 0.04, 0.08, 0.16, 0.36};
  std::vector<std::pair<double, double>> spans;
  double start = 0.0;
  for (double w : widths) {
    spans.emplace_back(start, start + w);
    start += 2.0 * w;  // the gap after a block is as wide as the block
  }
  return spans;
}

void addPatternObject(Scene& scene, const Eigen::Isometry3d& pose, int first_label) {
  // Boxes rotate about their own centre, so place each centre by the pose and rotate it.
  auto addBox = [&](const V& lo, const V& hi, int label, const Eigen::Vector3f& color) {
    const V center = pose * (0.5 * (lo + hi));
    const V half = 0.5 * (hi - lo);
    scene.add<Box>(center - half, center + half, label, pose.linear()).color = color;
  };
  addBox(V(0, 0, 0), V(0.96, 0.96, 0.10), first_label, {0.75f, 0.75f, 0.7f});
  const auto spans = patternObjectBlockSpans();
  for (int i = 0; i < 5; ++i) {    // rows along y
    for (int j = 0; j < 5; ++j) {  // columns along x
      const double top = 0.12 + 0.02 * std::min(i, j);
      const float shade = 0.45f + 0.1f * static_cast<float>(std::min(i, j));
      addBox(V(spans[j].first, spans[i].first, 0.10), V(spans[j].second, spans[i].second, top),
             first_label + 1 + 5 * i + j, {shade, 0.5f, 0.8f});
    }
  }
}

TrackingScene::TrackingScene() {
  scene_.add<Box>(V(-4, -4, -0.05), V(4, 4, 0.0), 0).color = {0.55f, 0.5f, 0.45f};
  scene_.add<Box>(V(0.2, 0.4, 0.72), V(1.4, 1.2, 0.75), 1).color = {0.75f, 0.6f, 0.4f};
  for (double x : {0.22, 1.34}) {
    for (double y : {0.42, 1.14}) {
      scene_.add<Box>(V(x, y, 0), V(x + 0.04, y + 0.04, 0.72), kNoPlane).color = {0.3f, 0.3f, 0.3f};
    }
  }
  scene_.add<Box>(V(0.9, 0.6, 0.75), V(1.2, 0.85, 0.80), 2).color = {0.8f, 0.2f, 0.2f};
  scene_.add<Box>(V(-1.6, 0.6, 0.0), V(-0.9, 1.2, 0.45), 3).color = {0.4f, 0.55f, 0.7f};
  scene_.add<Box>(V(1.8, -0.6, 0.0), V(2.6, 1.6, 0.17), 4).color = {0.65f, 0.65f, 0.65f};
  scene_.add<Box>(V(2.1, -0.6, 0.17), V(2.6, 1.6, 0.34), 5).color = {0.6f, 0.6f, 0.65f};
  addPatternObject(scene_, Eigen::Isometry3d(Eigen::Translation3d(-0.7, -0.7, 0.0)), 10);
  occluder_ = &scene_.add<Box>(V(-0.1, -0.1, 0.0), V(0.1, 0.1, 3.0), kNoPlane);
  occluder_->color = {0.2f, 0.2f, 0.25f};
}

RenderedFrame TrackingScene::render(const Camera& camera, const Eigen::Vector2d& occluder_xy,
                                    const SensorNoise& noise) const {
  occluder_->center.head<2>() = occluder_xy;
  return scene_.render(camera, noise);
}

const char* TrackingScene::surfaceName(int label) {
  switch (label) {
    case 0:
      return "floor";
    case 1:
      return "table";
    case 2:
      return "book";
    case 3:
      return "cabinet";
    case 4:
      return "stair 1";
    case 5:
      return "stair 2";
    default:
      return label >= 10 && label < 10 + kPatternObjectFaces ? "pattern face" : "none";
  }
}

std::vector<std::string> trackingSequenceNames() {
  return {"pan", "rpy", "shake", "occlusion", "leave_enter"};
}

namespace {

// The camera of every sequence starts like a person holding an RGB-D camera at 1.5 m, 2.4 m
// from the scene centre, looking down at it.
const V kEye(0.2, -2.4, 1.5);
const V kTarget(0.2, 0.3, 0.35);

Camera withSize(Camera camera, int width) {
  const double s = width / 640.0;
  const PinholeIntrinsics k = PinholeIntrinsics::tumFreiburg1();
  camera.width = width;
  camera.height = width * 3 / 4;
  camera.intrinsics = {k.fx * s, k.fy * s, k.cx * s, k.cy * s};
  return camera;
}

// Rotates the camera about its own optical-frame axes (x right, y down, z forward).
Camera rotatedInPlace(Camera camera, double about_x, double about_y, double about_z) {
  const Eigen::Matrix3d r =
      (Eigen::AngleAxisd(about_z, V::UnitZ()) * Eigen::AngleAxisd(about_y, V::UnitY()) *
       Eigen::AngleAxisd(about_x, V::UnitX()))
          .toRotationMatrix();
  camera.pose.linear() = camera.pose.linear() * r;
  return camera;
}

// Rotates the camera about the world's vertical axis through its own position.
Camera yawedInWorld(Camera camera, double yaw) {
  camera.pose.linear() =
      Eigen::AngleAxisd(yaw, V::UnitZ()).toRotationMatrix() * camera.pose.linear();
  return camera;
}

}  // namespace

TrackingSequence makeTrackingSequence(const std::string& name, int frames, int width,
                                      unsigned seed) {
  if (frames < 2) throw std::invalid_argument("a tracking sequence needs at least 2 frames");
  if (width < 64 || width > 4096) throw std::invalid_argument("image width must be 64–4096");
  TrackingSequence seq;
  seq.name = name;
  std::mt19937 rng(seed);
  std::normal_distribution<double> gauss(0.0, 1.0);
  const double deg = M_PI / 180.0;
  for (int f = 0; f < frames; ++f) {
    // Motions are defined over 3 s (90 frames); fewer frames show the start of it, more
    // continue it, so the motion per frame never depends on the length.
    const double s = f / 90.0;
    const double phase = 2.0 * M_PI * s;
    TrackingFrame frame;
    frame.stamp = f / 30.0;
    Camera cam;
    if (name == "pan") {
      seq.description = "slow sideways walk (±0.6 m) while panning ±20°";
      const V eye = kEye + V(0.6 * std::sin(phase), 0.0, 0.0);
      cam = yawedInWorld(Camera::lookingAt(eye, kTarget), -20.0 * deg * std::sin(phase));
    } else if (name == "rpy") {
      seq.description =
          "rotation in place about the camera's roll, pitch and yaw axes (±15°), "
          "like TUM fr1_rpy";
      cam = rotatedInPlace(Camera::lookingAt(kEye, kTarget), 15.0 * deg * std::sin(2 * phase),
                           15.0 * deg * std::sin(phase + 1.0), 15.0 * deg * std::sin(3 * phase));
    } else if (name == "shake") {
      seq.description =
          "hand-held shake: slow approach plus independent jitter per frame "
          "(1 cm, 1.5° standard deviation)";
      const V eye = kEye + V(0.0, 0.8 * s, -0.2 * s) + 0.01 * V(gauss(rng), gauss(rng), gauss(rng));
      cam = rotatedInPlace(Camera::lookingAt(eye, kTarget), 1.5 * deg * gauss(rng),
                           1.5 * deg * gauss(rng), 1.5 * deg * gauss(rng));
    } else if (name == "occlusion") {
      seq.description =
          "a pillar passes between camera and table, hiding parts of the scene "
          "for several frames, while the camera drifts";
      cam = Camera::lookingAt(kEye + V(0.2 * s, 0.0, 0.0), kTarget);
      frame.occluder_xy = Eigen::Vector2d(-1.5 + 3.5 * s, -1.0);
    } else if (name == "leave_enter") {
      seq.description = "the camera turns 70° away and back: planes leave the view and return";
      cam = yawedInWorld(Camera::lookingAt(kEye, kTarget), 70.0 * deg * std::sin(0.5 * phase));
    } else {
      throw std::invalid_argument("unknown tracking sequence '" + name +
                                  "' (pan, rpy, shake, occlusion, leave_enter)");
    }
    frame.camera = withSize(cam, width);
    seq.frames.push_back(frame);
  }
  return seq;
}

}  // namespace synthetic
}  // namespace hope
