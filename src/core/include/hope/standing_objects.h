// The objects standing on each plane: what a robot takes off a table (paper §1: "retrieving
// the objects upon the surface"). For every plane seen from above, the points above it — more
// than its noise (r_z / 2, or three times the sensor's range noise at the point, seen
// vertically) and at most ObjectParams::max_height — over its occupied cells with their holes
// filled (a hole in a table top is where something stands) and one cell around them, or within
// the convex hull of its cells where nothing is seen below it (a bay of a table hidden out to
// its far edge by the things standing there), joined
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

#include "hope/params.h"
#include "hope/plane.h"
#include "hope/points_view.h"

namespace hope {

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
// touching objects stay one. Threads may call it at once: each keeps its own scratch buffers
// from call to call (cell_keys.h), and no call's result depends on an earlier one.
StandingObjects findStandingObjects(const AlignedPoints& points,
                                    const std::vector<HorizontalPlane>& planes,
                                    const std::vector<std::int32_t>& point_labels,
                                    const Eigen::Vector3d& local_origin, const Params& params,
                                    const ObjectParams& object_params = ObjectParams(),
                                    const std::optional<Eigen::Vector3d>& viewpoint = std::nullopt);

}  // namespace hope
