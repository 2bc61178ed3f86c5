// Scoring LiDAR results the way a robot uses them: one plane for the ground, and how far from
// the sensor that plane reaches. Recall and precision are counted per range band (horizontal
// distance from the sensor), because a spinning LiDAR's rings grow sparse with range.
#pragma once

#include <functional>
#include <vector>

#include <Eigen/Core>

namespace hope {
namespace evaluation {

struct RangeBand {
  double min_range = 0, max_range = 0;  // metres, [min, max)
};

// The bands the docs report: 0–10, 10–20, 20–40, 40–80 m.
std::vector<RangeBand> standardRangeBands();

struct SurfaceScore {
  std::size_t truth_points = 0;                // points of the surface
  int plane = -1;                              // the found plane holding most of them (-1: none)
  double recall = 0;                           // share of the surface's points in that plane
  double precision = 0;                        // share of that plane's points on the surface
  int pieces = 0;                              // found planes whose points are mostly this surface
  std::vector<std::size_t> band_truth_points;  // per band
  std::vector<double> band_recall;             // per band; NaN where the band has no points
};

// Scores one ground-truth surface: the points for which `on_surface(truth label)` holds.
// `horizontal_range` gives each point's distance from the sensor in the horizontal plane;
// `found` the plane of each point (-1: none). All vectors have one entry per point.
SurfaceScore scoreSurface(const std::vector<int>& truth, const std::vector<int>& found,
                          const std::vector<double>& horizontal_range,
                          const std::function<bool(int)>& on_surface,
                          const std::vector<RangeBand>& bands = standardRangeBands());

// Horizontal distance of each point from `sensor` (NaN points: infinity).
std::vector<double> horizontalRanges(const std::vector<Eigen::Vector3f>& points,
                                     const Eigen::Vector3f& sensor = Eigen::Vector3f::Zero());

}  // namespace evaluation
}  // namespace hope
