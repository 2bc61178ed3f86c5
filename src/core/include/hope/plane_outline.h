// Plane outline: the true shape of a plane, not its convex hull. The hull of an L-shaped desk
// covers the floor in the L's corner, and the hull of a merged table covers the gaps between
// its parts; a robot placing an object needs to know where the surface really is. The outline
// is the boundary of the plane's occupied grid cells (the same cells as its `area`): one
// counter-clockwise ring (seen from above) around each connected part, one clockwise ring
// around each hole where something stands on it, simplified to few vertices.
#pragma once

#include <cstdint>
#include <utility>
#include <vector>

#include <Eigen/Core>

namespace hope {

struct HorizontalPlane;

// The rings bounding the cells (cx, cy) of a grid whose cell (0, 0) has its lower-left corner
// at `origin` and whose cells are `cell` wide. Counter-clockwise rings bound the cells,
// clockwise rings are holes; cells touching only at a corner are bounded separately. Holes of
// fewer than `min_hole_cells` cells are filled (a missing measurement, not an object). Rings
// are simplified (Douglas–Peucker) within `tolerance` metres. Cells may repeat. Large grids
// are traced at a coarser cell (at most 4 M cells), so the cost stays bounded.
std::vector<std::vector<Eigen::Vector2d>> traceOutline(
    std::vector<std::pair<std::int64_t, std::int64_t>> cells, const Eigen::Vector2d& origin,
    double cell, double tolerance, double min_hole_cells = 4);

// Signed area of a ring: positive for counter-clockwise.
double ringArea(const std::vector<Eigen::Vector3d>& ring);
// The area enclosed by the plane's outline (rings minus holes), m².
double outlineArea(const HorizontalPlane& plane);
// Whether (x, y) lies on the plane as its outline draws it (even-odd over all rings).
bool outlineContains(const HorizontalPlane& plane, double x, double y);

}  // namespace hope
