#include "hope/evaluation/lidar_metrics.h"

#include <cmath>
#include <limits>
#include <map>
#include <stdexcept>

namespace hope {
namespace evaluation {

std::vector<RangeBand> standardRangeBands() { return {{0, 10}, {10, 20}, {20, 40}, {40, 80}}; }

SurfaceScore scoreSurface(const std::vector<int>& truth, const std::vector<int>& found,
                          const std::vector<double>& horizontal_range,
                          const std::function<bool(int)>& on_surface,
                          const std::vector<RangeBand>& bands) {
  if (truth.size() != found.size() || truth.size() != horizontal_range.size()) {
    throw std::invalid_argument("scoreSurface: truth, found and range differ in length");
  }
  SurfaceScore score;
  // Per found plane: its points, and those of them on the surface.
  std::map<int, std::size_t> plane_points, plane_on_surface;
  for (std::size_t i = 0; i < truth.size(); ++i) {
    const bool on = on_surface(truth[i]);
    score.truth_points += on ? 1 : 0;
    if (found[i] < 0) continue;
    ++plane_points[found[i]];
    if (on) ++plane_on_surface[found[i]];
  }
  std::size_t best = 0;
  for (const auto& [plane, count] : plane_on_surface) {
    if (count > best) {
      best = count;
      score.plane = plane;
    }
    if (2 * count > plane_points[plane]) ++score.pieces;
  }
  if (score.plane >= 0) {
    score.recall = static_cast<double>(best) / static_cast<double>(score.truth_points);
    score.precision = static_cast<double>(best) / static_cast<double>(plane_points[score.plane]);
  }
  score.band_truth_points.assign(bands.size(), 0);
  std::vector<std::size_t> band_hits(bands.size(), 0);
  for (std::size_t i = 0; i < truth.size(); ++i) {
    if (!on_surface(truth[i])) continue;
    for (std::size_t b = 0; b < bands.size(); ++b) {
      if (horizontal_range[i] >= bands[b].min_range && horizontal_range[i] < bands[b].max_range) {
        ++score.band_truth_points[b];
        if (score.plane >= 0 && found[i] == score.plane) ++band_hits[b];
      }
    }
  }
  for (std::size_t b = 0; b < bands.size(); ++b) {
    score.band_recall.push_back(score.band_truth_points[b] == 0
                                    ? std::numeric_limits<double>::quiet_NaN()
                                    : static_cast<double>(band_hits[b]) /
                                          static_cast<double>(score.band_truth_points[b]));
  }
  return score;
}

std::vector<double> horizontalRanges(const std::vector<Eigen::Vector3f>& points,
                                     const Eigen::Vector3f& sensor) {
  std::vector<double> ranges(points.size(), std::numeric_limits<double>::infinity());
  for (std::size_t i = 0; i < points.size(); ++i) {
    if (points[i].allFinite()) ranges[i] = (points[i] - sensor).head<2>().cast<double>().norm();
  }
  return ranges;
}

}  // namespace evaluation
}  // namespace hope
