// Parameters of the horizontal plane extractor and their validation.
#pragma once

#include <limits>
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

}  // namespace hope
