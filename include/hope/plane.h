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
  // The id of the surface this plane is a piece of (FramePipeline; surface_grouping.h): pieces
  // of one physical surface in one frame (one height within r_z, or within the sensor's range
  // noise at their ranges and the up's error across the distance between them; their extents
  // overlapping) share one. A surface keeps its id from frame to frame (the one most of its
  // pieces' area carried in the last second); a surface new to the frame, or a frame answered
  // apart from a stream, carries its largest piece's id, so a plane alone carries its own.
  int surface_id = 0;

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

struct StandingObject {
  int index = 0;        // 0, 1, … within the frame
  int plane_index = 0;  // the plane it stands on: an index into Result::planes
  int plane_id = 0;     // and that plane's id when the objects were found
  std::size_t num_points = 0;
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();  // of its points, reference frame
  // The smallest upright box around its points: centre, yaw of its first side about z
  // (radians, in [0, π)), and size along that side, across it and up, z from the plane to the
  // object's top.
  Eigen::Vector3d box_centre = Eigen::Vector3d::Zero();
  double yaw = 0.0;
  Eigen::Vector3d box_size = Eigen::Vector3d::Zero();
  // Convex outline of its points in xy at the plane's height, counter-clockwise from above.
  std::vector<Eigen::Vector3d> footprint;
  // Of its top above the plane, metres.
  double height = 0.0;
};

struct Footprint {
  double width = 0.1;       // metres, along the placement's yaw
  double depth = 0.1;       // metres, across it
  double clearance = 0.02;  // metres kept free around it from every object
};

// Throws std::invalid_argument naming the value: width and depth in (0, 100] m, clearance in
// [0, 10] m, all finite.
void validate(const Footprint& footprint);

struct Placement {
  int plane_index = 0;  // into Result::planes
  int plane_id = 0;
  // The footprint's centre at the plane's height, in the reference frame, and the direction
  // of its width side about z (radians, [0, π)).
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  double yaw = 0.0;
  // Distance from the centre to the nearest unobserved cell, edge or object clearance, metres:
  // how far the placement may be off and still rest on observed free surface.
  double margin = 0.0;
};

struct PlacementQuery {
  Footprint footprint;
  int plane_index = -1;         // only this plane (an index into the planes), or -1: any
  std::size_t max_results = 5;  // placements at least a footprint apart, best first
};

}  // namespace hope
