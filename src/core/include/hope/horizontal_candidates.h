// Horizontal candidates (paper Eq 3): voxels whose normal lies within the error cone around z.
#pragma once

#include <cstdint>
#include <vector>

#include <Eigen/Core>

namespace hope {

// The bound of Eq 3, 1 / sqrt(1 + 2γ²): the steepest normal a voxel on a plane that Z
// clustering can still join (tilted by atan γ along the grid diagonal) may have.
double candidateNormalZBound(double gamma);

// Marks voxels with |n_z| > 1 / sqrt(1 + 2γ²); NaN normals are never candidates.
// Returns the number of candidates.
std::size_t selectHorizontalCandidates(const std::vector<Eigen::Vector3f>& normals, double gamma,
                                       std::vector<std::uint8_t>& is_candidate);

}  // namespace hope
