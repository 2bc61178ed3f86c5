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

#include "hope/aligned_points.h"
#include "hope/params.h"
#include "hope/plane.h"
#include "hope/standing_objects.h"

namespace hope {

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
