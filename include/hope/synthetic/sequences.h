// Moving-camera sequences over a scene with known surfaces, for measuring plane identities:
// the paper's pattern object, floor, a table with a book, a cabinet and stairs, seen by a
// simulated depth camera along realistic hand-held trajectories.
#pragma once

#include <string>
#include <vector>

#include "hope/synthetic/scene.h"

namespace hope {
namespace synthetic {

// The paper's pattern object (§3.3): a 0.96 × 0.96 × 0.10 m base plate carrying a 5 × 5
// grid of blocks whose widths along x and y are 0.02, 0.04, 0.08, 0.16, 0.36 m, each gap as
// wide as the block before it; block (row i, column j) tops out at 0.12 + 0.02·min(i, j).
// Placed with its base corner at `pose` (rotation about that corner tilts it). Labels: the
// exposed base top is `first_label`, block (i, j) is first_label + 1 + 5·i + j: 26 faces.
constexpr int kPatternObjectFaces = 26;
void addPatternObject(Scene& scene, const Eigen::Isometry3d& pose, int first_label);
// Block extents along one axis (start, end) in metres from the base corner, for tests.
std::vector<std::pair<double, double>> patternObjectBlockSpans();

// The scene of the tracking sequences. Ground-truth surfaces: 0 floor, 1 table top (0.75 m),
// 2 book (0.80 m), 3 cabinet (0.45 m), 4 and 5 stair treads (0.17, 0.34 m), 10–35 the pattern
// object's faces (0.10–0.20 m). A tall pillar (no horizontal face in view) can be moved
// through the view as an occluder.
class TrackingScene {
 public:
  TrackingScene();
  // Renders with the occluder centred at `occluder_xy` (far away when not wanted). Moves the
  // occluder in place, so one TrackingScene must not render two frames concurrently.
  RenderedFrame render(const Camera& camera, const Eigen::Vector2d& occluder_xy,
                       const SensorNoise& noise) const;
  static const char* surfaceName(int label);

 private:
  Scene scene_;
  Box* occluder_;
};

struct TrackingFrame {
  double stamp = 0;
  Camera camera;
  Eigen::Vector2d occluder_xy{100.0, 100.0};  // out of the way
};

struct TrackingSequence {
  std::string name;
  std::string description;
  std::vector<TrackingFrame> frames;
};

// "pan", "rpy", "shake", "occlusion", "leave_enter".
std::vector<std::string> trackingSequenceNames();
// `frames` frames at 30 Hz, camera images `width` × 3/4·width (TUM intrinsics scaled). Each
// motion takes 3 s (90 frames); a shorter sequence is its beginning.
// Throws std::invalid_argument for an unknown name or fewer than 2 frames.
TrackingSequence makeTrackingSequence(const std::string& name, int frames, int width = 640,
                                      unsigned seed = 1);

}  // namespace synthetic
}  // namespace hope
