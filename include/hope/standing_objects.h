// The objects standing on each plane: what a robot takes off a table (paper §1: "retrieving
// the objects upon the surface"). For every plane seen from above, the points above it — more
// than half a vertical cell (r_z / 2) and at most ObjectParams::max_height — over its occupied
// cells with their holes filled (a hole in a table top is where something stands) and one cell
// around them, joined into objects where they touch on a grid of r_z / 4 cells (or twice the
// plane's sample spacing, where the cloud is sparser). Each point
// goes to the highest plane below it whose area it stands over, so a box on a shelf, a cup on
// a book and a can on the floor under a table each belong to their own surface. A plane that
// stands on a lower one within max_height (a box's top, a book, a chair's seat) is the top of
// an object there as well: its points carry both labels, and it still carries what stands on it.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <vector>

#include <Eigen/Core>

#include "hope/aligned_points.h"
#include "hope/params.h"
#include "hope/plane.h"

namespace hope {

struct ObjectParams {
  // Points higher than this above a plane do not stand on it (a lamp above a table), metres.
  double max_height = 0.5;
  // Fewer points than this are noise (a stray return, a mixed pixel at an edge), not an object.
  std::size_t min_points = 40;
};

// Throws std::invalid_argument naming the parameter and its range.
void validate(const ObjectParams& params);

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

struct StandingObjects {
  std::vector<StandingObject> objects;
  // One entry per input point, in input order: the index into `objects`, or -1.
  std::vector<std::int32_t> point_objects;
};

// The objects standing on `planes`, from the aligned points (relative to `local_origin`, as
// Extractor::alignedPoints() gives them) and the points' plane labels (Result::point_labels).
// Planes seen from below (facing kDown) carry nothing. With the sensor's `viewpoint` (in the
// aligned points' frame), objects that touch are split at the concave creases between them
// (crease_splitting.h); without it they stay one.
StandingObjects findStandingObjects(const AlignedPoints& points,
                                    const std::vector<HorizontalPlane>& planes,
                                    const std::vector<std::int32_t>& point_labels,
                                    const Eigen::Vector3d& local_origin, const Params& params,
                                    const ObjectParams& object_params = ObjectParams(),
                                    const std::optional<Eigen::Vector3d>& viewpoint = std::nullopt);

}  // namespace hope
