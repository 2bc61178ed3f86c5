#include "hope/horizontal_candidates.h"

#include <cmath>

namespace hope {

double candidateNormalZBound(double gamma) { return 1.0 / std::sqrt(1.0 + 2.0 * gamma * gamma); }

std::size_t selectHorizontalCandidates(const std::vector<Eigen::Vector3f>& normals, double gamma,
                                       std::vector<std::uint8_t>& is_candidate) {
  const float bound = static_cast<float>(candidateNormalZBound(gamma));
  is_candidate.resize(normals.size());
  std::size_t count = 0;
  for (std::size_t v = 0; v < normals.size(); ++v) {
    // NaN compares false, so voxels without a normal drop out here.
    const bool candidate = std::fabs(normals[v].z()) > bound;
    is_candidate[v] = candidate ? 1 : 0;
    count += candidate ? 1 : 0;
  }
  return count;
}

}  // namespace hope
