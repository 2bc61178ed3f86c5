// A straight flight of stairs between two floors, with exact ground truth, seen by a Kinect v2
// from below, head-on and from above: the scene where a camera pitched 90° over a far wall is
// the wrong answer that up from the scene must not give (up_estimation.h).
#pragma once

#include <string>
#include <vector>

#include "hope/synthetic/scene.h"

namespace hope {
namespace synthetic {

struct StaircaseLayout {
  int steps = 12;
  double rise = 0.157, run = 0.28, width = 1.2;  // metres, a common indoor stair
  // The lower floor (z = 0) reaches back to x = lower_end; the upper floor (z = steps · rise)
  // from the top step on to x = upper_end. A wall stands at each end when far_walls is set.
  double lower_end = -4.0, upper_end = 12.0;
  bool far_walls = true;
};

// The flight rises along +x from x = 0, centred on y = 0, between two side walls. Plane labels:
// 0 the lower floor, k = 1 … steps the k-th tread (the last one is the upper floor), each at
// height k · rise. Risers and walls are no plane.
Scene staircase(const StaircaseLayout& layout = StaircaseLayout());

// A Kinect v2's depth camera at qHD (960 × 540), and its noise: a time-of-flight sensor's depth
// error grows more slowly with range than a structured-light one's; σ = 0.8 mm · z² keeps it
// near a Kinect v2's (about 1 cm at 3.5 m) within 4 m and makes the 12 m wall rough (12 cm).
Camera kinectV2Camera();
SensorNoise kinectV2Noise();

struct StaircaseView {
  std::string name;
  Camera camera;  // pose in the staircase's frame (z up)
};
// The views the tests and the quality guard use: head-on from the lower floor (a camera held
// level, and pitched 20° down), from below (pitched 10° up), and from above on the upper floor
// looking down the flight (pitched 30° and 45° down); each 1.5 m above the floor it stands on.
std::vector<StaircaseView> staircaseViews(const StaircaseLayout& layout = StaircaseLayout());

}  // namespace synthetic
}  // namespace hope
