// Scoring a segmentation against ground truth the way Hoover et al. (1996) do: each region is
// a correct detection, part of an over- or under-segmentation, missed, or noise.
#pragma once

#include <cstddef>
#include <map>
#include <vector>

namespace hope {
namespace evaluation {

struct HooverScores {
  std::size_t truth_regions = 0;
  std::size_t found_regions = 0;
  std::size_t correct = 0;          // one-to-one pairs
  std::size_t over_segmented = 0;   // truth regions split into 2+ found regions
  std::size_t under_segmented = 0;  // found regions covering 2+ truth regions
  std::size_t missed = 0;           // truth regions in none of the above
  std::size_t noise = 0;            // found regions in none of the above
  // Each correct pair: truth label → found label, and its intersection over union of points.
  std::map<int, int> found_of_truth;
  std::map<int, double> iou_of_truth;
};

// `truth` and `found` give one region label per point (-1: no region); both the same length.
// Overlap threshold T in (0.5, 1]: a correct pair shares at least T of each region's points;
// an over-segmentation's parts each lie at least T inside one truth region and together cover
// at least T of it; an under-segmentation likewise the other way round. Correct detections
// are classified first, so a region counts once. Throws std::invalid_argument on length
// mismatch or T outside (0.5, 1].
HooverScores hooverScores(const std::vector<int>& truth, const std::vector<int>& found,
                          double threshold = 0.8);

}  // namespace evaluation
}  // namespace hope
