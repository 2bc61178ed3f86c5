// What the extractor reports for each horizontal plane.
#pragma once

#include <array>
#include <cstddef>
#include <vector>

#include <Eigen/Core>

namespace hope {

// Which side of the plane the sensor saw: kUp for a surface seen from above (floor, table
// top, stair tread), kDown for one seen from below (a ceiling, a shelf's underside), kUnknown
// when the sensor's position was not given (Orientation::identity() without a viewpoint).
enum class Facing { kUnknown, kUp, kDown };
const char* toString(Facing facing);

struct HorizontalPlane {
  // Extraction order within the frame (0, 1, …); the tracker replaces it with a persistent id.
  int id = 0;
  // Mean z of the plane's input points in the reference frame, metres.
  double height = 0.0;
  // The paper's feature vector extents: x_min, y_min, x_max, y_max in the reference frame.
  std::array<double, 4> bbox{{0, 0, 0, 0}};
  // Mean of the plane's input points in the reference frame.
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  // Unit normal of a least-squares plane through the input points, pointing up (n_z > 0).
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();
  // Angle between `normal` and the reference z axis, radians.
  double tilt = 0.0;
  // Footprint at grid resolution: occupied xy cells · r_xy², m².
  double area = 0.0;
  // Observed surface with nothing standing on it, on cells of r_z / 2, m² (placement.h); set
  // only when objects were asked for (ExtractOutputs::objects), 0 otherwise.
  double free_area = 0.0;
  std::size_t num_voxels = 0;
  std::size_t num_points = 0;
  // How many connected regions (the paper's planes) the fragment merge joined into this one
  // physical surface; 1 when nothing was merged (see fragment_merging.h).
  int num_parts = 1;
  Facing facing = Facing::kUnknown;
  // Convex hull of the plane's points in xy, counter-clockwise seen from above, at z = height.
  std::vector<Eigen::Vector3d> hull;
  // The plane's true shape at z = height (plane_outline.h): the boundary of its occupied grid
  // cells, one counter-clockwise ring around each part and one clockwise ring around each
  // hole (where something stands on it), simplified. Encloses about `area`.
  std::vector<std::vector<Eigen::Vector3d>> outline;
  // The two angles of the refinement test (Eq 10), for diagnostics.
  double mean_normal_tilt = 0.0;
  double group_angle = 0.0;

  // Set by the PlaneTracker (plane_tracker.h); a single extraction leaves the defaults.
  // Frames in which this id has been seen, this one included.
  int age = 1;
  // Stamp (seconds) of the last frame this id was seen in: the current frame for a plane in
  // the output, earlier for a remembered lost plane.
  double last_seen = 0.0;
  // The id this plane split off in this frame, or -1.
  int split_from = -1;

  // Moves the plane's position fields (height, bbox, centroid, hull, outline) by `offset`.
  void translate(const Eigen::Vector3d& offset) {
    height += offset.z();
    bbox[0] += offset.x();
    bbox[2] += offset.x();
    bbox[1] += offset.y();
    bbox[3] += offset.y();
    centroid += offset;
    for (Eigen::Vector3d& h : hull) h += offset;
    for (auto& ring : outline) {
      for (Eigen::Vector3d& q : ring) q += offset;
    }
  }
};

}  // namespace hope
