#include "hope/fragment_merging.h"

#include "hope/plane_description.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numeric>

namespace hope {

namespace {

class DisjointSets {
 public:
  explicit DisjointSets(std::size_t n) : parent_(n) {
    std::iota(parent_.begin(), parent_.end(), 0);
  }
  std::size_t find(std::size_t i) {
    while (parent_[i] != i) i = parent_[i] = parent_[parent_[i]];
    return i;
  }
  void join(std::size_t a, std::size_t b) {
    a = find(a);
    b = find(b);
    if (a != b) parent_[std::max(a, b)] = std::min(a, b);
  }

 private:
  std::vector<std::size_t> parent_;
};

// Height of the fitted plane of `plane` above (x, y). Planes reaching here are near
// horizontal; a degenerate normal counts as level rather than divide by zero.
double heightAt(const HorizontalPlane& plane, double x, double y) {
  const Eigen::Vector3d& n = plane.normal;
  const Eigen::Vector3d& c = plane.centroid;
  if (!(n.z() > 1e-3)) return c.z();
  return c.z() - (n.x() * (x - c.x()) + n.y() * (y - c.y())) / n.z();
}

// Distance between two axis-aligned xy boxes (x_min, y_min, x_max, y_max); 0 when they overlap.
double boxGap(const std::array<double, 4>& a, const std::array<double, 4>& b) {
  const double dx = std::max({0.0, b[0] - a[2], a[0] - b[2]});
  const double dy = std::max({0.0, b[1] - a[3], a[1] - b[3]});
  return std::hypot(dx, dy);
}

// Heights within r_z, normals within the accepted slope: the larger accepted plane's fit,
// evaluated at the other's centroid, within r_z of it. The accepted plane with the larger
// footprint is the better estimate of the surface (point counts favour whatever is nearest the
// sensor; a rejected fit may be anything).
bool atOneHeight(const Fragment& a, const Fragment& b, const Params& params) {
  const Fragment& larger =
      a.accepted != b.accepted ? (a.accepted ? a : b) : (a.plane.area >= b.plane.area ? a : b);
  const Fragment& smaller = &larger == &a ? b : a;
  const double step =
      heightAt(larger.plane, smaller.plane.centroid.x(), smaller.plane.centroid.y()) -
      smaller.plane.centroid.z();
  const double angle = std::acos(std::min(1.0, std::fabs(a.plane.normal.dot(b.plane.normal))));
  return std::fabs(step) <= params.r_z && angle <= params.maxSlope();
}

// At one height (atOneHeight), boxes near enough to bridge. A rejected fragment must moreover
// lie on the accepted one's plane: all its voxels within r_z of it, and 80 % within r_z / 2.
bool compatible(const VoxelGrid& grid, const Fragment& a, const Fragment& b, const Params& params) {
  if (!a.accepted && !b.accepted) return false;
  if (boxGap(a.plane.bbox, b.plane.bbox) > params.max_merge_gap) return false;  // cheap first
  if (!atOneHeight(a, b, params)) return false;
  const Fragment& rejected = a.accepted ? b : a;
  if (rejected.accepted) return true;
  // Its rim may be lifted by the object that cut it off (see completeSurface), its body not.
  const HorizontalPlane& surface = (a.accepted ? a : b).plane;
  std::size_t on_surface = 0;
  for (std::uint32_t v : *rejected.voxels) {
    const Eigen::Vector3f& p = grid.centroid(v);
    const double offset = std::fabs(heightAt(surface, p.x(), p.y()) - p.z());
    if (offset > params.r_z) return false;
    on_surface += offset <= 0.5 * params.r_z ? 1 : 0;
  }
  return on_surface >= 0.8 * static_cast<double>(rejected.voxels->size());
}

// What the sensor saw in one cell of the surface's raster. Plane cells hold the plane's index
// in the group (>= 0) instead.
enum : std::int32_t {
  kUnseen = -1,    // nothing known: not passable
  kPassable = -2,  // the surface, something on or in front of it, or its shadow
  kGap = -3,       // the sensor saw through the surface's height here
};

// A raster over the xy box of one group of compatible planes.
class SurfaceRaster {
 public:
  SurfaceRaster(double x0, double y0, double x1, double y1, double cell)
      : x0_(x0), y0_(y0), cell_(cell) {
    nx_ = std::max<std::int64_t>(1, static_cast<std::int64_t>(std::ceil((x1 - x0) / cell)));
    ny_ = std::max<std::int64_t>(1, static_cast<std::int64_t>(std::ceil((y1 - y0) / cell)));
    state_.assign(static_cast<std::size_t>(nx_ * ny_), kUnseen);
  }
  std::int64_t nx() const { return nx_; }
  std::int64_t ny() const { return ny_; }
  std::int32_t& at(std::int64_t ix, std::int64_t iy) {
    return state_[static_cast<std::size_t>(iy * nx_ + ix)];
  }
  // The cell index of (x, y), or -1 outside the raster.
  std::int64_t cellOf(double x, double y) const {
    const double fx = std::floor((x - x0_) / cell_), fy = std::floor((y - y0_) / cell_);
    if (!(fx >= 0 && fy >= 0 && fx < nx_ && fy < ny_)) return -1;
    return static_cast<std::int64_t>(fy) * nx_ + static_cast<std::int64_t>(fx);
  }
  // Raises the cell's state: a plane cell stays, a gap overrides what is merely passable.
  void mark(double x, double y, std::int32_t what) {
    const std::int64_t k = cellOf(x, y);
    if (k < 0) return;
    std::int32_t& s = state_[static_cast<std::size_t>(k)];
    if (s >= 0 || s == kGap) return;
    if (what == kGap || s == kUnseen) s = what;
  }
  // Marks every cell whose centre lies inside the convex polygon `corners` (any order) as
  // passable, clipped to the raster.
  void markConvex(const Eigen::Vector2d* corners, std::size_t n) {
    if (n == 0) return;
    double lo = HUGE_VAL, hi = -HUGE_VAL;
    for (std::size_t k = 0; k < n; ++k) {
      lo = std::min(lo, corners[k].y());
      hi = std::max(hi, corners[k].y());
    }
    const std::int64_t row0 =
        std::max<std::int64_t>(0, static_cast<std::int64_t>(std::ceil((lo - y0_) / cell_ - 0.5)));
    const std::int64_t row1 = std::min<std::int64_t>(
        ny_ - 1, static_cast<std::int64_t>(std::floor((hi - y0_) / cell_ - 0.5)));
    for (std::int64_t row = row0; row <= row1; ++row) {
      const double y = y0_ + (row + 0.5) * cell_;
      double left = HUGE_VAL, right = -HUGE_VAL;
      for (std::size_t k = 0; k < n; ++k) {
        const Eigen::Vector2d& a = corners[k];
        const Eigen::Vector2d& b = corners[(k + 1) % n];
        if (y < std::min(a.y(), b.y()) || y > std::max(a.y(), b.y())) continue;
        if (a.y() == b.y()) {  // a horizontal edge on this row: both its ends
          left = std::min({left, a.x(), b.x()});
          right = std::max({right, a.x(), b.x()});
          continue;
        }
        const double x = a.x() + (y - a.y()) / (b.y() - a.y()) * (b.x() - a.x());
        left = std::min(left, x);
        right = std::max(right, x);
      }
      if (left > right) continue;
      const std::int64_t c0 = std::max<std::int64_t>(
          0, static_cast<std::int64_t>(std::ceil((left - x0_) / cell_ - 0.5)));
      const std::int64_t c1 = std::min<std::int64_t>(
          nx_ - 1, static_cast<std::int64_t>(std::floor((right - x0_) / cell_ - 0.5)));
      for (std::int64_t col = c0; col <= c1; ++col) {
        std::int32_t& s = state_[static_cast<std::size_t>(row * nx_ + col)];
        if (s == kUnseen) s = kPassable;
      }
    }
  }

  std::vector<std::int32_t>& states() { return state_; }
  // Whether the box [lo, hi] overlaps the raster.
  bool overlaps(const Eigen::Vector2d& lo, const Eigen::Vector2d& hi) const {
    return hi.x() >= x0_ && hi.y() >= y0_ && lo.x() <= x0_ + nx_ * cell_ &&
           lo.y() <= y0_ + ny_ * cell_;
  }

 private:
  double x0_, y0_, cell_;
  std::int64_t nx_ = 1, ny_ = 1;
  std::vector<std::int32_t> state_;
};

// Marks what every voxel of the scene says about the surface through `reference` (the group's
// largest plane): see the header.
void observeScene(const VoxelGrid& grid, const HorizontalPlane& reference,
                  const std::optional<Eigen::Vector3d>& viewpoint, double r_z,
                  SurfaceRaster& raster) {
  const Eigen::Vector3d& n = reference.normal;
  const Eigen::Vector3d& c = reference.centroid;
  const double tolerance = r_z * n.z();  // r_z measured vertically, as a distance along n
  const double sensor_side = viewpoint ? n.dot(*viewpoint - c) : 0.0;
  // A sensor within r_z of the surface sees it edge-on: rays tell nothing, use the columns.
  const bool use_rays = viewpoint && std::fabs(sensor_side) > tolerance;

  // Per grid column, only the occluder farthest from the surface matters: the shadows of the
  // lower points in that column lie inside its shadow (same start, same direction, shorter).
  std::int64_t column_occluder = -1;
  double column_occluder_distance = 0;
  // The shadow of a column of the grid, from the surface up to the top of voxel v: the convex
  // hull of the column's square and of that square's top projected from the sensor onto the
  // surface. Projections of a point just below the sensor's height reach the horizon: 1000×
  // its distance is far enough for any raster.
  const double r_xy = grid.rXY();
  auto castShadow = [&](std::int64_t v) {
    const std::size_t voxel = static_cast<std::size_t>(v);
    const double x0 = grid.cellMinX(grid.cellX(voxel)), y0 = grid.cellMinY(grid.cellY(voxel));
    // The voxel's face toward the sensor's side of the surface.
    const double top = grid.centroid(voxel).z() + (sensor_side > 0 ? 0.5 : -0.5) * grid.rZ();
    std::array<Eigen::Vector2d, 8> corners;
    std::size_t count = 0;  // four corners of the column's square, four of its shadow's tip
    for (int k = 0; k < 4; ++k) {
      const Eigen::Vector3d corner(x0 + (k & 1) * r_xy, y0 + (k >> 1) * r_xy, top);
      corners[count++] = corner.head<2>();
      const double side = n.dot(corner - c);
      const double denominator = sensor_side - side;  // same sign as sensor_side unless the
                                                      // corner is past the sensor's height
      const double t =
          denominator * sensor_side > 0 ? std::min(1000.0, sensor_side / denominator) : 1000.0;
      const Eigen::Vector3d tip = *viewpoint + t * (corner - *viewpoint);
      corners[count++] = tip.head<2>();
    }
    Eigen::Vector2d lo = corners[0], hi = corners[0];
    for (const Eigen::Vector2d& q : corners) {
      lo = lo.cwiseMin(q);
      hi = hi.cwiseMax(q);
    }
    if (!raster.overlaps(lo, hi)) return;  // most shadows fall beside a small surface
    std::array<Eigen::Vector2d, 17> hull;  // room for 2 · 8 + 1, no allocation per column
    raster.markConvex(hull.data(), convexHullInPlace(corners.data(), corners.size(), hull.data()));
    raster.mark(x0 + 0.5 * r_xy, y0 + 0.5 * r_xy, kPassable);  // when cells exceed columns
  };

  const std::size_t num_voxels = grid.numVoxels();
  for (std::size_t v = 0; v < num_voxels; ++v) {
    if (v > 0 && grid.column(v) != grid.column(v - 1) && column_occluder >= 0) {
      castShadow(column_occluder);
      column_occluder = -1;
    }
    const Eigen::Vector3d p = grid.centroid(v).cast<double>();
    const double side = n.dot(p - c);
    if (std::fabs(side) <= tolerance) {
      raster.mark(p.x(), p.y(), kPassable);  // the surface itself, seen here
      continue;
    }
    if (!use_rays) {
      raster.mark(p.x(), p.y(), side > 0 ? kPassable : kGap);
      continue;
    }
    if ((side > 0) != (sensor_side > 0)) {
      // Beyond the surface: the ray from the sensor to this return crossed the surface's
      // height without meeting it, so where it crossed there is no surface.
      const double t = sensor_side / (sensor_side - side);  // in (0, 1)
      const Eigen::Vector3d crossing = *viewpoint + t * (p - *viewpoint);
      raster.mark(crossing.x(), crossing.y(), kGap);
    } else if (std::fabs(side) < std::fabs(sensor_side)) {
      // Between the sensor and the surface: it stands on the surface or in front of it, and
      // hides the surface behind it.
      if (column_occluder < 0 || std::fabs(side) > column_occluder_distance) {
        column_occluder = static_cast<std::int64_t>(v);
        column_occluder_distance = std::fabs(side);
      }
    }
    // Farther from the surface than the sensor (a ceiling above a floor): its rays never
    // reach the surface and say nothing about it.
  }
  if (column_occluder >= 0) castShadow(column_occluder);
}

}  // namespace

std::vector<std::vector<std::size_t>> groupFragments(
    const VoxelGrid& grid, const std::vector<Fragment>& fragments,
    const std::optional<Eigen::Vector3d>& viewpoint, const Params& params) {
  const std::size_t count = fragments.size();
  DisjointSets merged(count);
  if (params.merge_fragments && count > 1) {
    // Candidate groups: planes linked by compatible pairs. Only these need the scene test.
    DisjointSets candidates(count);
    std::vector<std::pair<std::size_t, std::size_t>> compatible_pairs;  // (a, b), a < b, sorted
    for (std::size_t a = 0; a < count; ++a) {
      for (std::size_t b = a + 1; b < count; ++b) {
        if (compatible(grid, fragments[a], fragments[b], params)) {
          compatible_pairs.emplace_back(a, b);
          candidates.join(a, b);
        }
      }
    }
    auto pairOk = [&](std::size_t a, std::size_t b) {
      return std::binary_search(compatible_pairs.begin(), compatible_pairs.end(),
                                std::make_pair(std::min(a, b), std::max(a, b)));
    };
    // Each merged group's representative (representative()). Two groups join only when
    // their representatives are at one height too, by the fit or by their mean heights: pairs
    // alone chain, and a small fragment whose fit is tilted (a table's sliver taking in an
    // object's foot) linked a table with a box top 9 cm above it (mOSD test57 with its up
    // turned by 0.2°).
    std::vector<std::size_t> group_representative(count);
    std::iota(group_representative.begin(), group_representative.end(), std::size_t{0});
    auto joinGroups = [&](std::size_t a, std::size_t b) {
      const std::size_t ra = group_representative[merged.find(a)];
      const std::size_t rb = group_representative[merged.find(b)];
      if (ra != rb && !atOneHeight(fragments[ra], fragments[rb], params) &&
          std::fabs(fragments[ra].plane.centroid.z() - fragments[rb].plane.centroid.z()) >
              params.r_z) {
        return;
      }
      merged.join(a, b);
      group_representative[merged.find(a)] = representative(fragments, {ra, rb});
    };
    std::vector<std::vector<std::size_t>> candidate_groups(count);
    for (std::size_t k = 0; k < count; ++k) candidate_groups[candidates.find(k)].push_back(k);

    for (const std::vector<std::size_t>& group : candidate_groups) {
      if (group.size() < 2) continue;
      const std::size_t largest = representative(fragments, group);
      double x0 = HUGE_VAL, y0 = HUGE_VAL, x1 = -HUGE_VAL, y1 = -HUGE_VAL;
      for (std::size_t k : group) {
        const HorizontalPlane& plane = fragments[k].plane;
        x0 = std::min(x0, plane.bbox[0]);
        y0 = std::min(y0, plane.bbox[1]);
        x1 = std::max(x1, plane.bbox[2]);
        y1 = std::max(y1, plane.bbox[3]);
      }
      // Cells of the grid's size, unless the bridge would take more than 200 of them or the
      // raster more than 4 M cells (a hostile r_xy): the test stays cheap either way.
      double cell = std::max(grid.rXY(), params.max_merge_gap / 200.0);
      cell = std::max(cell, std::sqrt((x1 - x0) * (y1 - y0) / 4e6));
      // Aligned with the grid's columns, so that each column falls in one cell.
      x0 = grid.cellMinX(0) + std::floor((x0 - grid.cellMinX(0)) / grid.rXY()) * grid.rXY();
      y0 = grid.cellMinY(0) + std::floor((y0 - grid.cellMinY(0)) / grid.rXY()) * grid.rXY();
      SurfaceRaster raster(x0, y0, x1 + 1e-9, y1 + 1e-9, cell);

      for (std::size_t g = 0; g < group.size(); ++g) {
        for (std::uint32_t v : *fragments[group[g]].voxels) {
          const Eigen::Vector3f& p = grid.centroid(v);
          const std::int64_t k = raster.cellOf(p.x(), p.y());
          if (k >= 0) raster.states()[static_cast<std::size_t>(k)] = static_cast<std::int32_t>(g);
        }
      }
      observeScene(grid, fragments[largest].plane, viewpoint, params.r_z, raster);

      // From each plane, a breadth-first walk through passable cells, at most max_merge_gap
      // long; every other plane of the group it reaches is the same surface. Diagonal steps
      // may not squeeze between two cells that are not passable.
      const std::int64_t max_steps =
          static_cast<std::int64_t>(std::ceil(params.max_merge_gap / cell - 1e-9));
      std::vector<std::int32_t>& state = raster.states();
      std::vector<std::int32_t> visited(state.size(), -1);
      std::vector<std::int64_t> frontier, next;
      const std::int64_t nx = raster.nx(), ny = raster.ny();
      auto open = [&](std::int64_t ix, std::int64_t iy) {
        return ix >= 0 && iy >= 0 && ix < nx && iy < ny && raster.at(ix, iy) != kGap &&
               raster.at(ix, iy) != kUnseen;
      };
      for (std::size_t g = 0; g < group.size(); ++g) {
        const std::int32_t self = static_cast<std::int32_t>(g);
        frontier.clear();
        for (std::size_t k = 0; k < state.size(); ++k) {
          if (state[k] == self) {
            visited[k] = self;
            frontier.push_back(static_cast<std::int64_t>(k));
          }
        }
        for (std::int64_t step = 0; step <= max_steps && !frontier.empty(); ++step) {
          next.clear();
          for (std::int64_t k : frontier) {
            const std::int64_t ix = k % nx, iy = k / nx;
            for (int dy = -1; dy <= 1; ++dy) {
              for (int dx = -1; dx <= 1; ++dx) {
                if ((dx == 0 && dy == 0) || !open(ix + dx, iy + dy)) continue;
                if (dx != 0 && dy != 0 && !open(ix + dx, iy) && !open(ix, iy + dy)) continue;
                const std::int64_t m = (iy + dy) * nx + ix + dx;
                const std::int32_t s = state[static_cast<std::size_t>(m)];
                if (s >= 0 && s != self) {
                  const std::size_t a = group[g], b = group[static_cast<std::size_t>(s)];
                  if (pairOk(a, b)) joinGroups(a, b);
                  continue;  // a plane is not walked through: its own walk covers it
                }
                if (visited[static_cast<std::size_t>(m)] == self) continue;
                visited[static_cast<std::size_t>(m)] = self;
                // The walk's length counts the cells between the planes only.
                if (s == kPassable && step < max_steps) next.push_back(m);
              }
            }
          }
          frontier.swap(next);
        }
      }
    }
  }
  std::vector<std::vector<std::size_t>> groups;
  std::vector<std::int64_t> group_of_root(count, -1);
  for (std::size_t k = 0; k < count; ++k) {
    const std::size_t root = merged.find(k);
    if (group_of_root[root] < 0) {
      group_of_root[root] = static_cast<std::int64_t>(groups.size());
      groups.emplace_back();
    }
    groups[static_cast<std::size_t>(group_of_root[root])].push_back(k);
  }
  return groups;
}

// cos 72.5°: see completeSurface.
constexpr float kMinCompletionNormalZ = 0.3f;

std::size_t representative(const std::vector<Fragment>& fragments,
                           const std::vector<std::size_t>& group) {
  std::size_t best = group.front();
  for (std::size_t k : group) {
    if (fragments[k].accepted &&
        (!fragments[best].accepted || fragments[k].plane.area > fragments[best].plane.area)) {
      best = k;
    }
  }
  return best;
}

std::size_t completeSurface(const VoxelGrid& grid, const std::vector<Eigen::Vector3f>& normals,
                            const HorizontalPlane& plane, double r_z, std::int32_t id,
                            std::vector<std::int32_t>& voxel_owner,
                            std::vector<std::uint32_t>& voxels) {
  if (voxels.empty()) return 0;
  auto offset = [&](std::uint32_t v) {
    const Eigen::Vector3f& p = grid.centroid(v);
    return std::fabs(static_cast<double>(p.z()) - heightAt(plane, p.x(), p.y()));
  };
  // The surface's own spread: a robust standard deviation of its voxels' offsets (1.4826 ×
  // the median absolute offset), which something lying on part of it hardly moves.
  std::vector<double> offsets(voxels.size());
  for (std::size_t k = 0; k < voxels.size(); ++k) offsets[k] = offset(voxels[k]);
  std::nth_element(offsets.begin(), offsets.begin() + offsets.size() / 2, offsets.end());
  const double tolerance = std::max(0.5 * r_z, 2.5 * 1.4826 * offsets[offsets.size() / 2]);

  std::size_t changed = 0;
  const auto kept = std::remove_if(voxels.begin(), voxels.end(), [&](std::uint32_t v) {
    if (offset(v) <= tolerance) return false;
    voxel_owner[v] = -1;
    return true;
  });
  changed += static_cast<std::size_t>(voxels.end() - kept);
  voxels.erase(kept, voxels.end());

  // Breadth-first over voxels: `voxels` is the queue; what joins is appended and expanded.
  // Whether a voxel may join depends on the voxel alone, so the first look at a column takes
  // every voxel of it that ever will: each column is read once (marked by its first voxel),
  // not once from each of its up to nine neighbours, and the voxels join in the same order.
  std::vector<std::uint8_t> column_seen(grid.numVoxels(), 0);
  for (std::size_t next = 0; next < voxels.size(); ++next) {
    const std::uint32_t v = voxels[next];
    const int cx = grid.cellX(v), cy = grid.cellY(v);
    for (int dy = -1; dy <= 1; ++dy) {
      for (int dx = -1; dx <= 1; ++dx) {
        const auto range = grid.columnVoxels(cx + dx, cy + dy);
        if (range.first == range.second || column_seen[range.first]) continue;
        column_seen[range.first] = 1;
        for (std::uint32_t u = range.first; u < range.second; ++u) {
          if (voxel_owner[u] != -1 || offset(u) > tolerance) continue;
          if (std::fabs(normals[u].z()) < kMinCompletionNormalZ) continue;  // false for NaN
          // Part of something vertical: the column goes on in the z cells above and below.
          if (u > range.first && u + 1 < range.second && grid.cellZ(u - 1) == grid.cellZ(u) - 1 &&
              grid.cellZ(u + 1) == grid.cellZ(u) + 1) {
            continue;
          }
          voxel_owner[u] = id;
          voxels.push_back(u);
          ++changed;
        }
      }
    }
  }
  return changed;
}

}  // namespace hope
