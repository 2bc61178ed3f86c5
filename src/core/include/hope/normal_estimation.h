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

#include <cstdint>
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
  // The moments of every voxel of one column: voxels [first, last), the column's whole range as
  // VoxelGrid::columnVoxels gives it, into out[0, last - first). The same sums, bit for bit, as
  // moments() of each voxel: the neighbours are visited in the same order. The neighbour
  // columns are looked up once per column, and in each of them the window of z cells within
  // reach slides up with the voxel (a column's voxels are sorted by z cell) instead of being
  // searched for again. `windows` is scratch space, kept by the caller across columns.
  void columnMoments(std::uint32_t first, std::uint32_t last, Moments* out,
                     std::vector<std::pair<std::uint32_t, std::uint32_t>>& windows) const;

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

namespace detail {

// planeNormal's steps, exposed for tests. The covariance scaled to entries of at most 1 in
// magnitude, in double: the characteristic polynomial's coefficients then carry the smallest
// eigenvalue of a flat neighbourhood (many orders of magnitude below the others) to far more
// digits than float would.
struct CharacteristicCubic {
  double a00, a01, a02, a11, a12, a22;
  double c2, c1, c0;  // det(λI − A) = λ³ − c2·λ² + c1·λ − c0
};
// The cubic's smallest root λ0 by Newton's method from 0.
double smallestRoot(const CharacteristicCubic& cubic);
// smallestRoot of two cubics at once (SSE2), bit for bit: the same operations in the same order
// in each lane, and a lane that has stopped keeps its value.
void smallestRoots(const CharacteristicCubic& a, const CharacteristicCubic& b, double& root_a,
                   double& root_b);

}  // namespace detail

// Writes one unit normal per voxel, oriented so that n_z >= 0 (the sign of a PCA normal is
// arbitrary; §2.2 takes |n_z| for the same reason). A voxel with fewer than 3 neighbours
// (itself included), or whose neighbours lie on a line, gets a NaN normal and can never be a
// horizontal candidate.
// `threads` as Params::threads (0: every core); each voxel's normal is computed alone.
void estimateNormals(const VoxelGrid& grid, double radius_factor,
                     std::vector<Eigen::Vector3f>& normals, int threads = 1);

}  // namespace hope
