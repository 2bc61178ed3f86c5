// Where a new object fits: poses for a rectangular footprint on the planes, resting only on
// what was seen. The paper's point (§2.5): a "convincing location for putting objects on" must
// lie on observed surface, not on a hull that covers unseen gaps. So a footprint is placed
// only over cells of r_z / 2 that hold points of the plane (never over a hole, an unseen strip
// behind a tall object or past the edge) and no closer than the clearance to anything that
// stands above the surface (the objects, a wall or board rising over it: every point from
// r_z / 2 to 2 m above it); the best placements are those farthest from every edge and object.
#pragma once

#include <cstddef>
#include <vector>

#include <Eigen/Core>

#include "hope/params.h"
#include "hope/plane.h"
#include "hope/points_view.h"
#include "hope/standing_objects.h"

namespace hope {

// Placements for `query` on the planes seen from above, best (largest margin) first; empty when
// the footprint fits nowhere observed. Throws std::invalid_argument for a bad footprint, a plane
// index out of range, or a footprint larger than every plane it may go on (it cannot fit
// anywhere, whatever stands there).
std::vector<Placement> findPlacements(const AlignedPoints& points,
                                      const std::vector<HorizontalPlane>& planes,
                                      const std::vector<std::int32_t>& point_labels,
                                      const Eigen::Vector3d& local_origin, const Params& params,
                                      const PlacementQuery& query);

// Each plane's free area: its observed cells of r_z / 2 that no object standing on it
// (`standing`, from findStandingObjects on the same points) covers or touches, m²; 0 for a
// plane seen from below. One pass over the points for all planes.
std::vector<double> freeAreas(const AlignedPoints& points,
                              const std::vector<HorizontalPlane>& planes,
                              const std::vector<std::int32_t>& point_labels,
                              const StandingObjects& standing, const Eigen::Vector3d& local_origin,
                              const Params& params);

}  // namespace hope
