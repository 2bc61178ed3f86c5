// The objects standing on each plane: what a robot takes off a table (paper §1: "retrieving
// the objects upon the surface"). For every plane seen from above, the points above it — more
// than its noise (r_z / 2, or three times the sensor's range noise at the point, seen
// vertically) and at most ObjectParams::max_height — over its occupied cells with their holes
// filled (a hole in a table top is where something stands) and one cell around them, joined
// into objects where they touch. They touch within a distance that follows the data: cells of
// r_z / 4, or twice the plane's sample spacing where the cloud is sparser, or twice the
// sensor's range noise at the point where that is larger (a far chair's samples scatter by
// centimetres along the ray). Each point goes to the highest plane below it whose area it
// stands over, so a box on a shelf, a cup on a book and a can on the floor under a table each
// belong to their own surface. A plane that stands on a lower one (a box's top, a book, a
// chair's seat) is the top of an object there as well: its points carry both labels, and it
// still carries what stands on it. One higher than max_height (a cabinet's, a table's, up to
// max_top_height) makes what stands under it, up to it, one thing with it. What rises to
// max_height with no top of its own (a wall's foot, a partition) is structure, not an object.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <vector>

#include <Eigen/Core>

#include "hope/aligned_points.h"
#include "hope/params.h"
#include "hope/plane.h"
#include "hope/range_noise.h"

namespace hope {

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
// aligned points' frame), points touch within a distance that grows with the sensor's noise at
// their range, and objects that touch are split at the concave creases between them
// (crease_splitting.h); without it the distance follows each plane's sample spacing alone and
// touching objects stay one.
StandingObjects findStandingObjects(const AlignedPoints& points,
                                    const std::vector<HorizontalPlane>& planes,
                                    const std::vector<std::int32_t>& point_labels,
                                    const Eigen::Vector3d& local_origin, const Params& params,
                                    const ObjectParams& object_params = ObjectParams(),
                                    const std::optional<Eigen::Vector3d>& viewpoint = std::nullopt);

}  // namespace hope
