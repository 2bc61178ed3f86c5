#include "hope/pca_refinement.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Eigenvalues>

#include "hope/grid_filter.h"

namespace hope {

namespace {

double acuteAngle(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  const double denom = a.norm() * b.norm();
  if (denom <= 0.0) return 0.0;
  return std::acos(std::min(1.0, std::fabs(a.dot(b)) / denom));
}

// Principal axis (eigenvector of the larger eigenvalue, Eq 7–8) of the symmetric 2×2 matrix
// [[a, b], [b, c]], in closed form.
Eigen::Vector2d principalAxis(double a, double b, double c) {
  const double half_diff = 0.5 * (a - c);
  const double largest = 0.5 * (a + c) + std::sqrt(half_diff * half_diff + b * b);
  Eigen::Vector2d axis;
  if (std::fabs(b) > 1e-12 * std::max(std::fabs(a), std::fabs(c)) && b != 0.0) {
    axis = Eigen::Vector2d(largest - c, b);
  } else {
    axis = a >= c ? Eigen::Vector2d(1, 0) : Eigen::Vector2d(0, 1);
  }
  return axis.normalized();
}

}  // namespace

RefinementVerdict refineWithPCA(const std::vector<Eigen::Vector3f>& normals,
                                const std::vector<std::uint32_t>& members, double gamma) {
  RefinementVerdict verdict;
  const std::size_t k = members.size();
  if (k < 3) return verdict;  // §2.4: two normals or fewer do not form a plane
  const double limit = std::atan(gamma);

  // Eq 4: the mean normal.
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (std::uint32_t v : members) mean += normals[v].cast<double>();
  mean /= static_cast<double>(k);
  verdict.mean_tilt = acuteAngle(mean, Eigen::Vector3d::UnitZ());

  // Eq 5–6: covariance of the normals projected onto xy (μ is mean.head<2>()).
  const Eigen::Vector2d mu = mean.head<2>();
  double sxx = 0, sxy = 0, syy = 0;
  for (std::uint32_t v : members) {
    const Eigen::Vector2d b = normals[v].head<2>().cast<double>() - mu;
    sxx += b.x() * b.x();
    sxy += b.x() * b.y();
    syy += b.y() * b.y();
  }
  const double scale = 1.0 / static_cast<double>(k - 1);
  // Eq 7–8: the first principal component.
  const Eigen::Vector2d a0 = principalAxis(sxx * scale, sxy * scale, syy * scale);

  // Eq 9: split by the side of the principal axis each centred normal falls on.
  Eigen::Vector3d group1 = Eigen::Vector3d::Zero(), group2 = Eigen::Vector3d::Zero();
  std::size_t n1 = 0, n2 = 0;
  for (std::uint32_t v : members) {
    const Eigen::Vector2d b = normals[v].head<2>().cast<double>() - mu;
    if (a0.dot(b) > 0) {
      group1 += normals[v].cast<double>();
      ++n1;
    } else {
      group2 += normals[v].cast<double>();
      ++n2;
    }
  }
  // Identical normals leave one group empty: no spread at all, the flattest case there is.
  verdict.group_angle = (n1 == 0 || n2 == 0) ? 0.0 : acuteAngle(group1 / n1, group2 / n2);

  // Eq 10.
  verdict.horizontal = verdict.mean_tilt < limit && verdict.group_angle < limit;
  return verdict;
}

double footprintMinorVariance(const VoxelGrid& grid, const std::vector<std::uint32_t>& members) {
  if (members.empty()) return 0.0;
  Eigen::Vector2d mean = Eigen::Vector2d::Zero();
  for (std::uint32_t v : members) mean += Eigen::Vector2d(grid.cellX(v), grid.cellY(v));
  mean /= static_cast<double>(members.size());
  Eigen::Matrix2d covariance = Eigen::Matrix2d::Zero();
  for (std::uint32_t v : members) {
    const Eigen::Vector2d d = Eigen::Vector2d(grid.cellX(v), grid.cellY(v)) - mean;
    covariance += d * d.transpose();
  }
  covariance /= static_cast<double>(members.size());
  return Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d>(covariance).eigenvalues()[0];
}

ClusterRefinement refineClusters(const VoxelGrid& grid, const std::vector<Eigen::Vector3f>& normals,
                                 const std::vector<std::vector<std::uint32_t>>& clusters,
                                 double gamma) {
  ClusterRefinement refinement;
  refinement.verdicts.resize(clusters.size());
  refinement.accepted.assign(clusters.size(), 0);
  for (std::size_t c = 0; c < clusters.size(); ++c) {
    refinement.verdicts[c] = refineWithPCA(normals, clusters[c], gamma);
    refinement.accepted[c] = refinement.verdicts[c].horizontal &&
                             footprintMinorVariance(grid, clusters[c]) >= kMinFootprintVariance;
  }
  return refinement;
}

}  // namespace hope
