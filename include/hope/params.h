// Parameters of the horizontal plane extractor and their validation.
#pragma once

#include <cstddef>
#include <limits>
#include <optional>
#include <string>

namespace hope {

// The user-facing tuning is r_xy and r_z (paper §2.2); everything else is derived from them
// or has a default that rarely needs touching.
struct Params {
  // Grid resolution in the horizontal plane of the reference frame, metres. Also the
  // normal-estimation radius scale and the xy gap that separates two planes.
  double r_xy = 0.05;
  // Grid resolution along the reference z axis, metres. Also the largest height step that
  // Z clustering joins. Together with r_xy it sets the steepest slope accepted as
  // horizontal: atan(r_z / r_xy).
  double r_z = 0.02;
  // δ of §2.2: normals use neighbours within δ·r_xy. Must exceed 1 to reach the 4 grid
  // neighbours; larger values cost time and blur edges.
  double normal_radius_factor = 1.01;
  // Clusters with fewer voxels are dropped (§2.4: fewer than 3 normals cannot form a plane).
  int min_cluster_voxels = 3;
  // Optional height band in the reference frame (metres); planes whose height lies outside
  // are dropped. Off by default (infinite band).
  double min_height = -std::numeric_limits<double>::infinity();
  double max_height = std::numeric_limits<double>::infinity();
  // Optional minimum plane area in m² (footprint at grid resolution). Off by default.
  double min_area = 0.0;
  // Fragment merge (a departure from the paper, see fragment_merging.h): planes at one height
  // that clutter or occlusion cut apart are joined into one surface when nothing seen between
  // them contradicts it. false reproduces the paper exactly (one plane per connected region).
  bool merge_fragments = true;
  // The widest gap (metres) between two fragments that the merge may bridge.
  double max_merge_gap = 1.0;
  // Scan-gap bridging (a departure from the paper, see scan_gap_bridging.h): voxels that the
  // gaps between a spinning LiDAR's rings leave without a normal take it from the next ring
  // along the sensor's ray. Needs the sensor position; applies to LiDAR layouts (rings ×
  // azimuth) and unorganized clouds, not to a camera's image. false reproduces the paper.
  bool bridge_scan_gaps = true;
  // Threads for the passes over points and voxels (alignment, normals, description, labels);
  // 0 takes every core. The output does not depend on it: each thread works on its own share
  // and the shares are combined in a fixed order. 1 by default, as a nodelet shares its
  // manager's cores with the other nodelets; hope_extract uses every core.
  int threads = 1;

  // γ of Eq 3 and Eq 10.
  double gamma() const { return r_z / r_xy; }
  // The steepest accepted slope, atan(γ), in radians.
  double maxSlope() const;
};

// Throws std::invalid_argument naming the offending parameter and the accepted range.
void validate(const Params& params);

// A sensor's range noise: how far a reading at range d scatters along its ray. Thresholds that
// follow the data read it (the objects' margins and joining, the refinement of a given up by
// the scene) instead of constants tuned at one range.
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

struct ObjectParams {
  // Points higher than this above a plane do not stand on it (a lamp above a table), metres.
  // What reaches this high and carries no top of its own is structure (a wall's foot, a
  // partition, a pillar), not an object: it is left out.
  double max_height = 0.5;
  // A plane up to this far above a lower one (or max_height, when that is larger) is the top
  // of a thing standing there (a cabinet, a table, a desk, a shelf): what stands under its area
  // up to it is that thing, however far it rises past max_height, metres.
  double max_top_height = 2.0;
  // Fewer points than this are noise (a stray return, a mixed pixel at an edge), not an object.
  std::size_t min_points = 40;
  // The sensor's range noise (used with a known viewpoint); unset: Extractor takes a LiDAR's
  // for a rings × azimuth layout or an unorganized cloud more than 10 m across, a depth
  // camera's for any other (findStandingObjects alone: a depth camera's).
  std::optional<RangeNoise> noise;
};

// Throws std::invalid_argument naming the parameter and its range.
void validate(const ObjectParams& params);

}  // namespace hope
