#include "hope/normal_estimation.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

#include <Eigen/Eigenvalues>

#include "parallel.h"

namespace hope {

namespace {

// Neighbours spread along a line fix only one direction: their "normal" is any vector across
// the line. Require the middle eigenvalue to carry at least this share of the largest one.
constexpr float kMinPlanarity = 0.05f;

}  // namespace

NormalNeighbourhood::NormalNeighbourhood(const VoxelGrid& grid, double radius_factor)
    : grid_(grid), max_dz_(static_cast<float>(2.0 * grid.rZ())) {
  // Column offsets (in cells) whose centres lie within radius_factor·r_xy.
  const int reach = static_cast<int>(std::floor(radius_factor));
  for (int dy = -reach; dy <= reach; ++dy) {
    for (int dx = -reach; dx <= reach; ++dx) {
      if (dx * dx + dy * dy <= radius_factor * radius_factor) offsets_.emplace_back(dx, dy);
    }
  }
  reach_z_ = static_cast<int>(std::ceil(max_dz_ / grid.rZ())) + 1;
}

NormalNeighbourhood::Moments NormalNeighbourhood::moments(std::size_t v) const {
  const Eigen::Vector3f p = grid_.centroid(v);
  const int cx = grid_.cellX(v), cy = grid_.cellY(v), cz = grid_.cellZ(v);
  // Offsets from p keep the sums small, so single precision stays accurate far from 0. The
  // sums live in scalars (through the Moments struct the compiler stored all twelve after each
  // neighbour); each entry takes the same products in the same order as d·dᵀ would.
  float sx = 0, sy = 0, sz = 0, sxx = 0, sxy = 0, sxz = 0, syy = 0, syz = 0, szz = 0;
  int count = 0;
  const float max_dz = max_dz_;
  for (const auto& [dx, dy] : offsets_) {
    const auto range = grid_.columnVoxels(cx + dx, cy + dy);
    for (std::uint32_t u = grid_.firstAtOrAbove(range, cz - reach_z_); u < range.second; ++u) {
      if (grid_.cellZ(u) > cz + reach_z_) break;  // a column's voxels are sorted by z cell
      const Eigen::Vector3f& q = grid_.centroid(u);
      const float ex = q.x() - p.x(), ey = q.y() - p.y(), ez = q.z() - p.z();
      if (std::fabs(ez) > max_dz) continue;
      sx += ex, sy += ey, sz += ez;
      sxx += ex * ex, sxy += ex * ey, sxz += ex * ez;
      syy += ey * ey, syz += ey * ez, szz += ez * ez;
      ++count;
    }
  }
  Moments m;
  m.sum = Eigen::Vector3f(sx, sy, sz);
  m.outer << sxx, sxy, sxz, sxy, syy, syz, sxz, syz, szz;
  m.count = count;
  return m;
}

Eigen::Matrix3f NormalNeighbourhood::Moments::covariance() const {
  const Eigen::Vector3f mean = sum / static_cast<float>(count);
  return outer / static_cast<float>(count) - mean * mean.transpose();
}

bool planeNormal(const Eigen::Matrix3f& covariance, Eigen::Vector3f& normal) {
  // Entries scaled to at most 1 in magnitude, in double: the characteristic polynomial's
  // coefficients then carry the smallest eigenvalue of a flat neighbourhood (many orders of
  // magnitude below the others) to far more digits than float would.
  double scale = 0;
  for (int i = 0; i < 9; ++i) scale = std::max(scale, std::fabs(double{covariance(i)}));
  if (!(scale > 0) || !std::isfinite(scale)) return false;
  const double inverse = 1.0 / scale;
  const double a00 = covariance(0, 0) * inverse, a01 = covariance(0, 1) * inverse;
  const double a02 = covariance(0, 2) * inverse, a11 = covariance(1, 1) * inverse;
  const double a12 = covariance(1, 2) * inverse, a22 = covariance(2, 2) * inverse;
  // det(λI − A) = λ³ − c2·λ² + c1·λ − c0.
  const double c2 = a00 + a11 + a22;
  const double c1 = a00 * a11 + a00 * a22 + a11 * a22 - a01 * a01 - a02 * a02 - a12 * a12;
  const double c0 =
      a00 * (a11 * a22 - a12 * a12) - a01 * (a01 * a22 - a12 * a02) + a02 * (a01 * a12 - a11 * a02);
  auto eigenSolverFallback = [&]() {
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3f> solver;
    solver.computeDirect(covariance);
    const Eigen::Vector3f& eigenvalues = solver.eigenvalues();  // ascending
    if (!(eigenvalues(1) > kMinPlanarity * eigenvalues(2))) return false;
    normal = solver.eigenvectors().col(0);
    return normal.allFinite() && normal.squaredNorm() >= 0.5f;
  };
  // Most voxels of a sparse scan see their neighbours on one scan line. With
  // λ0 <= λ1 <= λ2: λ2 >= c2 / 3 and λ1·λ2 <= c1, so λ1 / λ2 <= 9·c1 / c2²; below the
  // planarity share that settles it without solving (where Newton's method would crawl
  // towards the double root λ0 ≈ λ1 ≈ 0).
  if (!(9 * c1 > kMinPlanarity * c2 * c2)) return false;
  // The smallest eigenvalue λ0: Newton's method from 0, which lies at or below it (a
  // covariance is positive semi-definite). Left of its smallest root a cubic with three real
  // roots rises and is concave, so every step lands between the last point and the root: it
  // climbs to λ0 and never passes it. c0 = λ0·λ1·λ2 below 0 is rounding in a singular matrix
  // (neighbours on a line, or exactly flat): λ0 is 0 to within that rounding.
  double lambda0 = 0;
  for (int iteration = 0; iteration < 64 && c0 > 0; ++iteration) {
    const double f = ((lambda0 - c2) * lambda0 + c1) * lambda0 - c0;
    const double slope = (3 * lambda0 - 2 * c2) * lambda0 + c1;
    if (!(slope > 0)) break;
    const double step = -f / slope;
    // Convergence is quadratic: a step of 1e-12 leaves λ0 exact to double precision, far
    // below what turns a float normal.
    if (!(step > 1e-12 * c2)) break;
    lambda0 += step;
  }
  // λ1 and λ2 from their sum and product (the roots of the cubic divided by λ − λ0); the
  // smaller one as product / larger, free of cancellation.
  const double sum = c2 - lambda0;
  const double product = std::max(0.0, c1 - lambda0 * sum);
  const double lambda2 = 0.5 * sum + std::sqrt(std::max(0.0, 0.25 * sum * sum - product));
  const double lambda1 = lambda2 > 0 ? product / lambda2 : 0.0;
  if (!(lambda1 > kMinPlanarity * lambda2)) return false;  // a line, a point or a blob's rim
  // The eigenvector of λ0 is orthogonal to every row of A − λ0·I: the largest cross product of
  // two rows. It is ill-defined only where λ0 nearly equals λ1 (a round blob), which the
  // general solver settles as before.
  const Eigen::Vector3d r0(a00 - lambda0, a01, a02), r1(a01, a11 - lambda0, a12),
      r2(a02, a12, a22 - lambda0);
  Eigen::Vector3d best = r0.cross(r1);
  for (const Eigen::Vector3d& candidate : {r0.cross(r2), r1.cross(r2)}) {
    if (candidate.squaredNorm() > best.squaredNorm()) best = candidate;
  }
  if (!(best.squaredNorm() > 1e-8 * lambda2 * lambda2 * lambda2 * lambda2)) {
    return eigenSolverFallback();
  }
  normal = (best / best.norm()).cast<float>();
  return true;
}

void estimateNormals(const VoxelGrid& grid, double radius_factor,
                     std::vector<Eigen::Vector3f>& normals, int threads) {
  const std::size_t num_voxels = grid.numVoxels();
  const float nan = std::numeric_limits<float>::quiet_NaN();
  normals.assign(num_voxels, Eigen::Vector3f(nan, nan, nan));
  const NormalNeighbourhood neighbourhood(grid, radius_factor);
  parallel::forShares(num_voxels, parallel::resolve(threads), 2048,
                      [&](int /*share*/, std::size_t begin, std::size_t end) {
                        for (std::size_t v = begin; v < end; ++v) {
                          const NormalNeighbourhood::Moments m = neighbourhood.moments(v);
                          if (m.count < 3) continue;
                          Eigen::Vector3f n;
                          if (!planeNormal(m.covariance(), n)) continue;
                          n.normalize();
                          normals[v] = n.z() < 0 ? Eigen::Vector3f(-n) : n;
                        }
                      });
}

}  // namespace hope
