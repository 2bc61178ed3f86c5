// A sensor's range noise: how far a reading at range d scatters along its ray. Thresholds that
// follow the data read it (the objects' margins and joining, the refinement of a given up by
// the scene) instead of constants tuned at one range.
#pragma once

#include <string>

namespace hope {

// The standard deviation of a sensor's range reading at range d, metres:
//   σ(d) = constant + per_metre · d + quadratic · (d − offset)².
struct RangeNoise {
  double constant = 0.0;
  double per_metre = 0.0;
  double quadratic = 0.0;
  double offset = 0.0;
  double at(double range) const {
    return constant + per_metre * range + quadratic * (range - offset) * (range - offset);
  }
  // A structured-light or stereo depth camera (Kinect v1, RealSense D4xx class): the axial
  // noise Nguyen, Izadi and Lovell measured on a Kinect (3DIMPVT 2012), 0.0012 + 0.0019 (d −
  // 0.4)²: 1.9 mm at 1 m, 8 mm at 2 m, 26 mm at 4 m.
  static RangeNoise depthCamera() { return {0.0012, 0.0, 0.0019, 0.4}; }
  // A spinning LiDAR (Velodyne, Ouster class): about 1 cm, growing by 1 mm a metre (2 cm at
  // 10 m, 5 cm at 40 m), from the makers' accuracy figures (±2–3 cm).
  static RangeNoise lidar() { return {0.01, 0.001, 0.0, 0.0}; }
};

// Throws std::invalid_argument, naming `owner` ("object noise"), unless every coefficient is
// finite and in [0, 100].
void validate(const RangeNoise& noise, const std::string& owner);

}  // namespace hope
