#include "hope/scan_gap_bridging.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <Eigen/Geometry>

#include "hope/horizontal_candidates.h"
#include "hope/normal_estimation.h"

namespace hope {

namespace {

// The farthest a link reaches, as a share of the voxel's horizontal range: ring spacing grows
// with range, and half the range covers an HDL-64E to 100 m and a VLP-16 to 30 m.
constexpr double kMaxGapShare = 0.5;
// And never more than this many cells, so that a hostile cloud (pairs of points scattered over
// kilometres at a fine r_xy) cannot make the walks cost seconds.
constexpr double kMaxWalkCells = 4096;
// The walk's map of occupied blocks: blocks of at least kBlockColumns² columns, and no more
// than kMaxBlocks of them however fine the grid.
constexpr std::int64_t kBlockColumns = 8;
constexpr double kMaxBlocks = 1 << 22;
// Power iterations for a scan line's direction: the ratio of a line's two largest variances is
// large, so a few suffice.
constexpr int kPowerIterations = 4;
// A line and a link closer than this angle to it (sin) span no plane.
constexpr float kMinSpanSine = 0.3f;

}  // namespace

std::size_t bridgeScanGaps(const VoxelGrid& grid, const Eigen::Vector3d& viewpoint,
                           const Params& params, std::vector<Eigen::Vector3f>& normals,
                           std::vector<VoxelLink>& links) {
  // A scan line zig-zags across the grid's columns: its direction is taken from the 8-connected
  // neighbourhood even where the normals use the 4-connected one.
  const NormalNeighbourhood neighbourhood(grid, std::max(params.normal_radius_factor, 1.5));
  const double r_xy = grid.rXY();
  const float r_z = static_cast<float>(grid.rZ());
  const float candidate_bound = static_cast<float>(candidateNormalZBound(params.gamma()));
  const double x0 = grid.cellMinX(0), y0 = grid.cellMinY(0);
  std::size_t bridged = 0;

  // Most of a walk crosses empty ground between rings: a coarse map of which blocks of
  // columns hold any voxel lets it jump over empty blocks instead of testing every column.
  std::int64_t max_x = 0, max_y = 0;
  for (std::size_t v = 0; v < grid.numVoxels(); ++v) {
    max_x = std::max<std::int64_t>(max_x, grid.cellX(v));
    max_y = std::max<std::int64_t>(max_y, grid.cellY(v));
  }
  const double columns = static_cast<double>(max_x + 1) * static_cast<double>(max_y + 1);
  // A block's side is a power of two, so that the walk finds a column's block by shifts.
  int block_shift = 0;
  while ((std::int64_t{1} << block_shift) < kBlockColumns ||
         static_cast<double>(std::int64_t{1} << block_shift) <
             std::ceil(std::sqrt(columns / kMaxBlocks))) {
    ++block_shift;
  }
  const std::int64_t block = std::int64_t{1} << block_shift;
  const std::int64_t blocks_x = (max_x >> block_shift) + 1, blocks_y = (max_y >> block_shift) + 1;
  std::vector<std::uint8_t> block_occupied(static_cast<std::size_t>(blocks_x * blocks_y), 0);
  for (std::size_t v = 0; v < grid.numVoxels(); ++v) {
    block_occupied[static_cast<std::size_t>((grid.cellY(v) >> block_shift) * blocks_x +
                                            (grid.cellX(v) >> block_shift))] = 1;
  }
  const double block_size = static_cast<double>(block) * r_xy;

  // The first voxel within r_z of `v`'s height along the horizontal ray direction `dir`,
  // visiting every column the ray crosses once (a grid traversal after Amanatides and Woo),
  // jumping over empty blocks.
  auto walk = [&](std::uint32_t v, const Eigen::Vector2d& dir, double reach, std::uint32_t& found) {
    const Eigen::Vector3f c = grid.centroid(v);
    const int cx = grid.cellX(v), cy = grid.cellY(v);
    const double px = c.x() - x0, py = c.y() - y0;  // the start, relative to the grid's corner
    const std::int64_t step_x = dir.x() > 0 ? 1 : -1, step_y = dir.y() > 0 ? 1 : -1;
    const double delta_x = dir.x() != 0 ? r_xy / std::fabs(dir.x()) : HUGE_VAL;
    const double delta_y = dir.y() != 0 ? r_xy / std::fabs(dir.y()) : HUGE_VAL;
    // Ray parameter (metres along dir) at which the ray crosses into `bound` along one axis.
    auto crossing = [](double bound, double start, double d) {
      return d != 0 ? (bound - start) / d : HUGE_VAL;
    };
    std::int64_t x = 0, y = 0;
    double next_x = 0, next_y = 0, t = 0;
    auto enter = [&](double at) {  // (re)starts the traversal at ray parameter `at`
      t = at;
      x = static_cast<std::int64_t>(std::floor((px + at * dir.x()) / r_xy));
      y = static_cast<std::int64_t>(std::floor((py + at * dir.y()) / r_xy));
      next_x = crossing(static_cast<double>(dir.x() > 0 ? x + 1 : x) * r_xy, px, dir.x());
      next_y = crossing(static_cast<double>(dir.y() > 0 ? y + 1 : y) * r_xy, py, dir.y());
    };
    enter(0.0);
    bool advance = true;
    for (;;) {
      if (advance) {
        if (next_x < next_y) {
          t = next_x;
          x += step_x;
          next_x += delta_x;
        } else {
          t = next_y;
          y += step_y;
          next_y += delta_y;
        }
      }
      advance = true;
      if (t > reach) return false;
      if (x < 0 || y < 0 || x > max_x || y > max_y) return false;  // left the grid
      const std::int64_t bx = x >> block_shift, by = y >> block_shift;
      if (!block_occupied[static_cast<std::size_t>(by * blocks_x + bx)]) {
        // On to the first column beyond this empty block.
        const double exit = std::min(
            crossing(static_cast<double>(dir.x() > 0 ? bx + 1 : bx) * block_size, px, dir.x()),
            crossing(static_cast<double>(dir.y() > 0 ? by + 1 : by) * block_size, py, dir.y()));
        enter(std::max(exit, t) + 1e-4 * r_xy);
        advance = false;
        continue;
      }
      if (std::abs(x - cx) <= 1 && std::abs(y - cy) <= 1) continue;  // the voxel's own neighbours
      const auto range = grid.columnVoxels(x, y);
      float best_dz = r_z;
      bool lower = false;
      for (std::uint32_t u = range.first; u < range.second; ++u) {
        const float dz = grid.centroid(u).z() - c.z();
        lower = lower || dz <= -r_z;
        if (std::fabs(dz) < best_dz) {
          best_dz = std::fabs(dz);
          found = u;
        }
      }
      if (best_dz < r_z) return true;
      // Something lower seen here: the surface ended before it (an edge, a kerb's foot). What
      // stands higher may hide the surface's continuation and is walked past.
      if (lower) return false;
    }
  };

  const std::size_t num_voxels = grid.numVoxels();
  for (std::size_t v = 0; v < num_voxels; ++v) {
    if (normals[v].allFinite()) continue;
    const Eigen::Vector3f c = grid.centroid(v);
    // Something vertical: the column goes on above and below (within 4 r_z).
    bool above = false, below = false;
    const auto column = grid.columnVoxels(grid.cellX(v), grid.cellY(v));
    for (std::uint32_t u = column.first; u < column.second; ++u) {
      const float dz = grid.centroid(u).z() - c.z();
      above = above || (dz >= r_z && dz <= 4 * r_z);
      below = below || (dz <= -r_z && dz >= -4 * r_z);
    }
    if (above && below) continue;
    const Eigen::Vector2d radial = c.head<2>().cast<double>() - viewpoint.head<2>();
    const double range = radial.norm();
    if (range < 2 * r_xy) continue;
    const Eigen::Vector2d outward = radial / range;
    // The voxel's own scan line: the main direction of its neighbourhood, by a few power
    // iterations from the ring's expected direction (across the ray), which a full eigen
    // decomposition per voxel would cost several times more for the same answer.
    const NormalNeighbourhood::Moments m = neighbourhood.moments(v);
    if (m.count < 2) continue;
    const Eigen::Matrix3f covariance = m.covariance();
    Eigen::Vector3f line(static_cast<float>(-outward.y()), static_cast<float>(outward.x()), 0.0f);
    if ((covariance * line).squaredNorm() < 1e-12f) {
      line = Eigen::Vector3f(static_cast<float>(outward.x()), static_cast<float>(outward.y()), 0);
    }
    for (int iteration = 0; iteration < kPowerIterations; ++iteration) {
      line = covariance * line;
      const float norm = line.norm();
      if (!(norm > 1e-12f)) break;
      line /= norm;
    }
    if (!(std::fabs(line.squaredNorm() - 1.0f) < 1e-3f)) continue;

    // Inward first: the nearer ring is the shorter walk, and a level link there settles it.
    Eigen::Vector3f best = Eigen::Vector3f::Zero();  // the most level normal found
    bool any = false;
    for (const Eigen::Vector2d& dir : {Eigen::Vector2d(-outward), outward}) {
      if (any && best.z() > candidate_bound) break;
      const double reach = std::min({kMaxGapShare * range, kMaxWalkCells * r_xy,
                                     dir.dot(outward) > 0 ? HUGE_VAL : range - r_xy});
      std::uint32_t u = 0;
      if (!walk(static_cast<std::uint32_t>(v), dir, reach, u)) continue;
      const Eigen::Vector3f link = grid.centroid(u) - c;
      Eigen::Vector3f n = line.cross(link);
      if (!(n.norm() > kMinSpanSine * link.norm())) continue;
      n.normalize();
      if (n.z() < 0) n = -n;
      if (n.z() > candidate_bound) links.emplace_back(static_cast<std::uint32_t>(v), u);
      if (!any || n.z() > best.z()) {
        best = n;
        any = true;
      }
    }
    if (!any) continue;
    normals[v] = best;
    ++bridged;
  }
  return bridged;
}

}  // namespace hope
