// Normals (paper §2.2): the normal of every voxel is the least-variance direction of the
// centroids of its neighbouring voxels, found through the grid's column index instead of a
// k-d tree.
//
// Neighbourhood. The paper takes the voxel centroids within δ·r_xy (δ = 1.01). Measured
// between centroids that radius is fragile: a centroid sits wherever the points inside its
// cell happen to be, so grid neighbours drift beyond 1.01·r_xy at random (a flat 1 × 1 m sheet
// sampled on a regular grid lost enough normals to split into three planes), and on any slope
// steeper than acos(1 / 1.01) ≈ 0.14 rad the 4-neighbours are always out of reach, so slopes
// near atan(γ) get no normal at all. hope measures δ·r_xy between grid column centres instead
// (δ = 1.01 selects the column and its 4 neighbours; δ ≥ √2 adds the diagonals) and accepts
// those columns' voxels whose centroid lies within 2·r_z in height: steep enough for every
// slope Eq 3 lets through (atan(√2·γ)), tight enough to keep a plane 3·r_z above out.
#pragma once

#include <utility>
#include <vector>

#include <Eigen/Core>

#include "hope/grid_filter.h"

namespace hope {

// The neighbourhood of one voxel described above, as the moments of its neighbours' centroids
// taken relative to the voxel's own centroid (the voxel itself included).
class NormalNeighbourhood {
 public:
  NormalNeighbourhood(const VoxelGrid& grid, double radius_factor);
  struct Moments {
    Eigen::Vector3f sum = Eigen::Vector3f::Zero();
    Eigen::Matrix3f outer = Eigen::Matrix3f::Zero();
    int count = 0;
    Eigen::Matrix3f covariance() const;  // count > 0
  };
  Moments moments(std::size_t v) const;

 private:
  const VoxelGrid& grid_;
  std::vector<std::pair<int, int>> offsets_;
  float max_dz_;
  int reach_z_ = 1;
};

// The normal of a neighbourhood from its covariance: the eigenvector of the smallest
// eigenvalue, when the middle eigenvalue is at least 5 % of the largest (otherwise the
// neighbours lie on a line or at one point and fix no plane: false). Solved in closed form
// (Newton's method on the characteristic polynomial, then a cross product of two rows), in
// double; a round neighbourhood, where that eigenvector is ill-defined, goes to Eigen's solver.
// The sign is arbitrary.
bool planeNormal(const Eigen::Matrix3f& covariance, Eigen::Vector3f& normal);

// Writes one unit normal per voxel, oriented so that n_z >= 0 (the sign of a PCA normal is
// arbitrary; §2.2 takes |n_z| for the same reason). A voxel with fewer than 3 neighbours
// (itself included), or whose neighbours lie on a line, gets a NaN normal and can never be a
// horizontal candidate.
// `threads` as Params::threads (0: every core); each voxel's normal is computed alone.
void estimateNormals(const VoxelGrid& grid, double radius_factor,
                     std::vector<Eigen::Vector3f>& normals, int threads = 1);

}  // namespace hope
