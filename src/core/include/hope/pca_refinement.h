// Refinement with PCA (paper §2.4, Eq 4–10): rejects clusters that passed Eq 3 and Z clustering
// but are not horizontal planes — gentle slopes, cones, the top of a lying tube, sphere caps.
#pragma once

#include <cstdint>
#include <vector>

#include <Eigen/Core>

namespace hope {

struct RefinementVerdict {
  bool horizontal = false;
  // Acute angle between the cluster's mean normal (Eq 4) and z, radians.
  double mean_tilt = 0.0;
  // Acute angle between the mean normals of the two PCA groups (Eq 9), radians. A flat plane
  // has both groups around z; a curved surface splits into two diverging groups.
  double group_angle = 0.0;
};

// Applies Eq 10 to the normals of `members`: horizontal when both angles are below atan γ.
// Normals are expected oriented with n_z >= 0 (as estimateNormals gives them).
RefinementVerdict refineWithPCA(const std::vector<Eigen::Vector3f>& normals,
                                const std::vector<std::uint32_t>& members, double gamma);

class VoxelGrid;

// The smaller principal variance of the cluster's footprint, in grid cells². A footprint one
// cell wide has about 0 (a 2 × 2 block has 0.25): such a cluster cannot show a slope across
// itself — a slope just steeper than atan γ falls apart under Z clustering into level strips
// one cell wide whose grid normals still look horizontal — so the extractor rejects
// footprints below kMinFootprintVariance.
double footprintMinorVariance(const VoxelGrid& grid, const std::vector<std::uint32_t>& members);
constexpr double kMinFootprintVariance = 0.2;

// §2.4 on every cluster of Z clustering: each one's verdict, and whether it is accepted
// (horizontal by Eq 10, with a footprint that is not a line).
struct ClusterRefinement {
  std::vector<RefinementVerdict> verdicts;
  std::vector<std::uint8_t> accepted;
};
ClusterRefinement refineClusters(const VoxelGrid& grid, const std::vector<Eigen::Vector3f>& normals,
                                 const std::vector<std::vector<std::uint32_t>>& clusters,
                                 double gamma);

}  // namespace hope
