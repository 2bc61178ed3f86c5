// Surface ids: the pieces of one physical surface in one frame. The extraction leaves two
// regions apart when something seen between them contradicts their being one (a table top cut
// by what stands on it, a counter by a sink's rim), and the tracker and the map keep each piece
// its own id; a robot asking "which surface is this?" wants one answer for all of them.
#pragma once

#include <vector>

#include "hope/plane.h"

namespace hope {

// Sets each plane's surface_id: planes facing the same way whose heights differ by at most
// `max_height_step` (Z clustering's own step, r_z, §2.3) and whose bounding boxes overlap are
// pieces of one surface (transitively), and carry the id of the largest of them (its area; the
// lower id on a tie), which keeps the surface's id as long as the largest piece keeps its own;
// a piece more than the step from the largest's height (at the end of a chain) keeps its own.
// A plane alone is its own surface: surface_id = id.
void assignSurfaceIds(std::vector<HorizontalPlane>& planes, double max_height_step);

}  // namespace hope
