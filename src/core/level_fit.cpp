#include "level_fit.h"

#include <algorithm>
#include <cmath>
#include <unordered_set>

#include <Eigen/Eigenvalues>

namespace hope {
namespace detail {

namespace {

constexpr double kDegree = M_PI / 180.0;
constexpr int kMinPatchCells = 3;
// A patch of this many cells or more counts as a level surface.
constexpr int kSurfaceCells = 6;
// A patch of this many fit cells has a normal of its own worth comparing with up; one more than
// kOutlierPatchDeg from it is flat but not level, and left out.
constexpr int kOwnNormalCells = 12;
constexpr double kOutlierPatchDeg = 2.0;

// Union-find over cell numbers, with path halving.
int findRoot(std::vector<int>& parent, int v) {
  while (parent[v] != v) {
    parent[v] = parent[parent[v]];
    v = parent[v];
  }
  return v;
}

Eigen::Vector3d anyPerpendicular(const Eigen::Vector3d& u) {
  const Eigen::Vector3d other =
      std::fabs(u.x()) < 0.9 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY();
  return u.cross(other).normalized();
}

// The least-variance direction of a scatter matrix, on the side of `near`.
Eigen::Vector3d flattest(const Eigen::Matrix3d& scatter, const Eigen::Vector3d& near) {
  Eigen::Vector3d d = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(scatter).eigenvectors().col(0);
  return d.dot(near) < 0 ? Eigen::Vector3d(-d) : d;
}

}  // namespace

// One connected patch: its cells' centroid sums, and those of the cells that are not on a rim
// (the fit's).
struct LevelFit::Patch {
  int cells = 0;
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  Eigen::Matrix3d outer = Eigen::Matrix3d::Zero();
  int fit_cells = 0;
  Eigen::Vector3d fit_sum = Eigen::Vector3d::Zero();
  Eigen::Matrix3d fit_outer = Eigen::Matrix3d::Zero();

  void add(const Eigen::Vector3d& c, bool rim) {
    const Eigen::Matrix3d cc = c * c.transpose();
    ++cells, sum += c, outer += cc;
    if (!rim) ++fit_cells, fit_sum += c, fit_outer += cc;
  }
  Eigen::Matrix3d scatter() const { return outer - sum * sum.transpose() / cells; }
  Eigen::Matrix3d fitScatter() const {
    return fit_outer - fit_sum * fit_sum.transpose() / fit_cells;
  }
};

// A patch large and wide enough for a normal of its own (kOwnNormalCells fit cells, spread over
// half a cell or more both ways) whose normal lies more than kOutlierPatchDeg from `up`: flat,
// but not level.
bool LevelFit::notLevel(const Patch& patch, const Eigen::Vector3d& up) const {
  if (patch.fit_cells < kOwnNormalCells) return false;
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> own(patch.fitScatter());
  const bool wide = own.eigenvalues()(1) >= 0.25 * cell_ * cell_;
  const double cosine = std::fabs(own.eigenvectors().col(0).dot(up));
  return wide && std::acos(std::min(1.0, cosine)) > kOutlierPatchDeg * kDegree;
}

void LevelFit::reset(const VoxelGrid& grid, const std::vector<Eigen::Vector3f>& normals) {
  const std::size_t n = grid.numVoxels();
  cell_ = grid.rXY();
  centroid_.resize(n);
  normal_.resize(n);
  neighbour_begin_.assign(1, 0);
  neighbours_.clear();
  for (std::size_t v = 0; v < n; ++v) {
    centroid_[v] = grid.centroid(v).cast<double>();
    normal_[v] = normals[v].cast<double>();
    for (int dy = -1; dy <= 1; ++dy) {
      for (int dx = -1; dx <= 1; ++dx) {
        const auto column = grid.columnVoxels(grid.cellX(v) + dx, grid.cellY(v) + dy);
        for (std::uint32_t u = grid.firstAtOrAbove(column, grid.cellZ(v) - 1);
             u < column.second && grid.cellZ(u) <= grid.cellZ(v) + 1; ++u) {
          if (u != v) neighbours_.push_back(u);
        }
      }
    }
    neighbour_begin_.push_back(static_cast<std::uint32_t>(neighbours_.size()));
  }
}

LevelFit::Result LevelFit::fit(const Eigen::Vector3d& start, double first_tolerance_deg,
                               int rounds) const {
  Result result;
  Eigen::Vector3d up = start.normalized();
  const std::size_t n = centroid_.size();
  std::vector<std::uint8_t> selected(n), rim(n);
  std::vector<int> parent(n), patch_of(n);
  std::vector<Patch> patches;
  for (int round = 0; round < rounds; ++round) {
    const double tolerance_deg =
        std::max(kLastToleranceDeg, first_tolerance_deg * std::pow(0.6, round));
    const double cos_tolerance = std::cos(tolerance_deg * kDegree);
    const double sin_tolerance = std::sin(tolerance_deg * kDegree);
    for (std::size_t v = 0; v < n; ++v) {
      selected[v] = std::fabs(normal_[v].dot(up)) >= cos_tolerance;  // false for NaN
      rim[v] = 0;
      parent[v] = static_cast<int>(v);
    }
    // Patches: selected cells that touch (26-neighbourhood) and lie at one height, a step of at
    // most half a cell plus what the tolerance allows over their distance. A cell with any
    // neighbour half a cell or more above or below it is on a rim (a wall's foot, an object
    // standing on the surface, a table's edge): its centroid holds some of that other surface's
    // points, raised or lowered, so it joins its patch but not the fit (along a long rim such
    // cells tilted a synthetic floor by 0.5°).
    for (std::size_t v = 0; v < n; ++v) {
      if (!selected[v]) continue;
      for (std::uint32_t k = neighbour_begin_[v]; k < neighbour_begin_[v + 1]; ++k) {
        const std::uint32_t u = neighbours_[k];
        const Eigen::Vector3d d = centroid_[u] - centroid_[v];
        const double step = std::fabs(d.dot(up));
        if (step > 0.5 * cell_) rim[v] = 1;
        if (u < v || !selected[u] || step > 0.5 * cell_ + sin_tolerance * d.norm()) continue;
        const int a = findRoot(parent, static_cast<int>(v));
        const int b = findRoot(parent, static_cast<int>(u));
        if (a != b) parent[std::max(a, b)] = std::min(a, b);
      }
    }
    patches.clear();
    std::fill(patch_of.begin(), patch_of.end(), -1);
    for (std::size_t v = 0; v < n; ++v) {
      if (!selected[v]) continue;
      const int root = findRoot(parent, static_cast<int>(v));
      if (patch_of[root] < 0) {
        patch_of[root] = static_cast<int>(patches.size());
        patches.emplace_back();
      }
      patch_of[v] = patch_of[root];
      patches[patch_of[root]].add(centroid_[v], rim[v]);
    }
    // Each patch's scatter about its own mean, pooled: the direction that makes every patch
    // flattest at once, each at its own height. Rims everywhere (small or noisy surfaces):
    // every cell of the patches, then.
    Eigen::Matrix3d pooled = Eigen::Matrix3d::Zero();
    int pooled_cells = 0;
    for (const Patch& patch : patches) {
      if (patch.cells < kMinPatchCells || patch.fit_cells < kMinPatchCells) continue;
      pooled += patch.fitScatter();
      pooled_cells += patch.fit_cells;
    }
    if (pooled_cells < 2 * kMinPatchCells) {
      pooled.setZero();
      pooled_cells = 0;
      for (const Patch& patch : patches) {
        if (patch.cells < kMinPatchCells) continue;
        pooled += patch.scatter();
        pooled_cells += patch.cells;
      }
    }
    if (pooled_cells < kMinPatchCells) return result;
    const Eigen::Vector3d next = flattest(pooled, up);
    // Two flat patches that happen to line up can make the pooled scatter's smallest direction
    // jump far from where the normals agree: no support for this start then.
    if (next.dot(start) < std::cos((first_tolerance_deg + 10.0) * kDegree)) return result;
    up = next;
  }

  // Patches that are flat but not level (a keyboard, a book lying askew, a ramp of a few
  // degrees) pass the tolerance and pull the pooled fit their way: a patch large and wide
  // enough for its own normal, whose normal is more than kOutlierPatchDeg from up, is left out
  // and up fitted again.
  auto counts = [&](const Patch& patch) {
    return patch.cells >= kMinPatchCells && patch.fit_cells >= kMinPatchCells;
  };
  for (int pass = 0; pass < 2 && rounds == kRounds; ++pass) {
    Eigen::Matrix3d kept = Eigen::Matrix3d::Zero();
    int kept_cells = 0, dropped = 0;
    for (const Patch& patch : patches) {
      if (!counts(patch)) continue;
      if (notLevel(patch, up)) {
        ++dropped;
        continue;
      }
      kept += patch.fitScatter();
      kept_cells += patch.fit_cells;
    }
    if (dropped == 0 || kept_cells < 2 * kMinPatchCells) break;
    up = flattest(kept, up);
  }
  // What the final direction rests on, for the refinement's bound (up_estimation.h).
  for (const Patch& patch : patches) {
    if (!counts(patch) || (rounds == kRounds && notLevel(patch, up))) continue;
    result.evidence.push_back({patch.sum / patch.cells, patch.scatter() / patch.cells});
  }

  // The support of the final direction: footprint of the patches on the level plane, the
  // spread of their cells' normals, their number and their distinct heights.
  const Eigen::Vector3d a = anyPerpendicular(up), b = up.cross(a);
  std::unordered_set<std::uint64_t> footprint;
  double squared_angles = 0;
  int angles = 0;
  for (std::size_t v = 0; v < n; ++v) {
    if (!selected[v] || patches[patch_of[v]].cells < kMinPatchCells) continue;
    const auto ia = static_cast<std::int64_t>(std::floor(centroid_[v].dot(a) / cell_));
    const auto ib = static_cast<std::int64_t>(std::floor(centroid_[v].dot(b) / cell_));
    footprint.insert((static_cast<std::uint64_t>(ia) << 32) ^
                     (static_cast<std::uint64_t>(ib) & 0xffffffffu));
    const double cosine = std::min(1.0, std::fabs(normal_[v].dot(up)));
    squared_angles += std::pow(std::acos(cosine) / kDegree, 2);
    ++angles;
  }
  std::vector<double> heights;
  for (const Patch& patch : patches) {
    if (patch.cells < kSurfaceCells) continue;
    ++result.level_surfaces;
    heights.push_back(up.dot(patch.sum) / patch.cells);
    if (result.level_surfaces == 1 || heights.back() < result.lowest_height) {
      result.lowest_height = heights.back();
    }
  }
  std::sort(heights.begin(), heights.end());
  for (std::size_t i = 0; i < heights.size(); ++i) {
    if (i == 0 || heights[i] - heights[i - 1] > 2 * cell_) ++result.level_heights;
  }
  result.supported = true;
  result.up = up;
  result.support_area = static_cast<double>(footprint.size()) * cell_ * cell_;
  result.angle_spread_deg = angles ? std::sqrt(squared_angles / angles) : 0;
  return result;
}

}  // namespace detail
}  // namespace hope
