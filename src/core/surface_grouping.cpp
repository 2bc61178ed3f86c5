#include "hope/surface_grouping.h"

#include <cmath>
#include <cstddef>
#include <numeric>

namespace hope {

namespace {

bool boxesOverlap(const HorizontalPlane& a, const HorizontalPlane& b) {
  return a.bbox[0] < b.bbox[2] && b.bbox[0] < a.bbox[2] && a.bbox[1] < b.bbox[3] &&
         b.bbox[1] < a.bbox[3];
}

std::size_t root(std::vector<std::size_t>& parent, std::size_t i) {
  while (parent[i] != i) i = parent[i] = parent[parent[i]];
  return i;
}

}  // namespace

void assignSurfaceIds(std::vector<HorizontalPlane>& planes, double max_height_step) {
  const std::size_t n = planes.size();
  std::vector<std::size_t> parent(n);
  std::iota(parent.begin(), parent.end(), 0);
  // A frame holds tens of planes: every pair is cheap.
  for (std::size_t i = 0; i < n; ++i) {
    for (std::size_t j = i + 1; j < n; ++j) {
      const HorizontalPlane& a = planes[i];
      const HorizontalPlane& b = planes[j];
      if (a.facing == b.facing && std::fabs(a.height - b.height) <= max_height_step &&
          boxesOverlap(a, b)) {
        parent[root(parent, i)] = root(parent, j);
      }
    }
  }
  // Each group's largest piece names it.
  std::vector<std::size_t> largest(n, n);
  for (std::size_t i = 0; i < n; ++i) {
    std::size_t& best = largest[root(parent, i)];
    if (best == n || planes[i].area > planes[best].area ||
        (planes[i].area == planes[best].area && planes[i].id < planes[best].id)) {
      best = i;
    }
  }
  // A chain of pieces each within the step of the next may drift from the largest: one more
  // than the step from it is not at the surface's height, and stays its own.
  for (std::size_t i = 0; i < n; ++i) {
    const HorizontalPlane& named = planes[largest[root(parent, i)]];
    planes[i].surface_id =
        std::fabs(named.height - planes[i].height) <= max_height_step ? named.id : planes[i].id;
  }
}

}  // namespace hope
