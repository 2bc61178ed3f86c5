// The floor as a navigation grid (what nav_msgs/OccupancyGrid holds): where the floor was seen
// free, where something stands on it, and what was not seen, from the same heights above the
// floor that decide the obstacle points (obstacle_points.h).
#pragma once

#include <cstdint>
#include <vector>

#include "hope/frame_pipeline.h"
#include "hope/plane.h"
#include "hope/points_view.h"

namespace hope {

// A grid spans at most this many cells a side (50 m at 0.05 m), centred on `centre`: a LiDAR's
// floor points 100 m out would otherwise make a 16-million-cell message of one frame.
constexpr int kFloorGridMaxCells = 1000;

// One frame's grid in the reference frame, its cells aligned to multiples of `resolution`
// (the same cell in every frame). A cell is occupied when a point more than `min_height` and at
// most `max_height` above the floor under it falls in it (an obstacle point); free when only
// floor points (within `floor_tolerance` of the floor's fitted plane) fall in it; unseen
// otherwise. Points below the floor (a hole, a stair going down) and above `max_height` (a
// ceiling) leave a cell as it is. The grid spans the cells that are not unseen, within
// kFloorGridMaxCells / 2 of `centre` (reference-frame x y). `points` as
// Extractor::alignedPoints() gives them, relative to `local_origin`. With `obstacles`, the
// obstacle points' input indices are appended to it in the same pass (what obstaclePoints()
// gives: a frame that wants both reads its points once).
FloorGrid floorGrid(const AlignedPoints& points, const Eigen::Vector3d& local_origin,
                    const HorizontalPlane& floor, const Eigen::Vector2d& centre,
                    double floor_tolerance, double min_height, double max_height, double resolution,
                    std::vector<std::uint32_t>* obstacles = nullptr);

// A cell once seen occupied is free again only after this many looks in a row saw it free: a
// thing that left is cleared within a few frames, while a thing's edge, which the depth noise
// moves across a cell boundary from frame to frame, stays occupied.
constexpr std::uint8_t kFreeLooksToClear = 3;

// The frames' grids laid over each other in a fixed frame (the surface map's).
struct FloorMap {
  FloorGrid grid;
  std::vector<std::uint8_t> free_looks;  // per cell of `grid`: free looks since it was occupied
};

// `seen` (a frame's grid, at the map's resolution, cells aligned alike) laid over `map`: a cell
// the frame saw occupied is occupied; one it saw free is free, unless it is occupied and has
// not yet been seen free kFreeLooksToClear times in a row; cells it did not see keep theirs.
// The map spans both, cropped to kFloorGridMaxCells a side around `centre` (the sensor: what
// is far behind it is let go first); the floor's height is the frame's. A map of another
// resolution starts afresh.
void accumulate(FloorMap& map, const FloorGrid& seen, const Eigen::Vector2d& centre);

}  // namespace hope
