// Touching objects apart at the concave creases between them: a box standing against a can, a
// box on a box. Joining points where they touch (standing_objects.h) makes such a pair one
// object; what tells them apart is the fold between them, which bends away from the sensor.
// The criterion is LCCP's (Stein et al., "Object partitioning using local convexity", CVPR
// 2014): two adjacent surface patches with centroids c1, c2 and normals n1, n2 (pointing at
// the sensor) meet convexly when (n1 − n2)·(c1 − c2) > 0, and an object is what its patches
// reach through convex or smooth (normals within `smooth_deg`) connections. Patches here are
// cubes of the object points, not supervoxels: the cells the stage already has, coarser.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "hope/points_view.h"

namespace hope {

struct CreaseParams {
  // Side of a patch, metres: large enough that its points give a normal through a depth
  // camera's noise (~3 mm at 1 m), small enough that a 5 cm box side has patches of its own.
  double patch = 0.02;
  // Per object (indexed as object_of_point's objects), a patch side for it instead of `patch`
  // (an object seen from farther away, where the points are noisier, needs larger patches);
  // empty: `patch` for all.
  std::vector<double> object_patch;
  // Per object, whether it was joined across a gap its points do not bridge (a tall thing's
  // top and its legs): its parts that touch no other part stay with its largest. Empty: none.
  std::vector<std::uint8_t> joined_across_gap;
  // Adjacent patches whose normals differ by less than this are one surface whatever the sign
  // of the bend (a can's side, a bowl's inside), degrees. Patches of side s on a surface of
  // radius R differ by about s / R: 15° keeps a bowl or a cup of radius 4 patches (4 cm at
  // 1 m) whole on its concave inside, which 10° cut into pieces; the crease between two things
  // that touch is far steeper (90° for two boxes). On mosd_dev, 10° → 12.5° → 15° → 20°
  // (coplanar_deg 10°): weighted overlap 0.962 → 0.966 → 0.968 → 0.963 (docs/quality.md).
  double smooth_deg = 15.0;
  // Flat patches on either side of a region of patches that tell no normal are one surface
  // when they lie in one plane: normals within smooth_deg, and the step between them running
  // along both within this, degrees. Not smooth_deg: the step spans several patches, and a
  // wider angle lets two parallel tops a few centimetres apart in height join (with 15° here
  // too, mosd_dev's weighted overlap 0.967 against 0.968; the normals within 10° as well, 0.966).
  double coplanar_deg = 10.0;
  // A part with fewer points than this is no face of its own: it joins the neighbour it touches
  // that has the most points (in one round, so that a small object split off a large one stays).
  std::size_t min_part_points = 800;
  // Nor is one with fewer than this an object at all: such parts join their neighbours until
  // none is left (ObjectParams::min_points).
  std::size_t min_points = 40;
};

// Splits the objects of `object_of_point` (per point: an object index or -1) at their concave
// creases, seen from `viewpoint` (the sensor, in the points' frame); a part that hangs on
// another part of its object (a handle on its body: above the object's foot, beside the other
// part and no higher) stays with it. On return it holds the parts' indices, numbered in the order
// of their first point, and parent[k] says which object part k was split from. Returns the number
// of parts. Objects are left whole when their extent exceeds 65,000 patches along an axis (a
// kilometre scan) or there are more than 65,000 of them.
std::size_t splitAtConcaveCreases(const AlignedPoints& points, const Eigen::Vector3d& viewpoint,
                                  const CreaseParams& params,
                                  std::vector<std::int32_t>& object_of_point,
                                  std::vector<int>& parent);

}  // namespace hope
