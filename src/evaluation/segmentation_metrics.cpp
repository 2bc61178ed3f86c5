#include "hope/evaluation/segmentation_metrics.h"

#include <set>
#include <stdexcept>

namespace hope {
namespace evaluation {

HooverScores hooverScores(const std::vector<int>& truth, const std::vector<int>& found,
                          double threshold) {
  if (truth.size() != found.size()) {
    throw std::invalid_argument("hooverScores: one truth and one found label per point needed");
  }
  // Above 0.5 a region can pair correctly with at most one other, which the method relies on.
  if (!(threshold > 0.5 && threshold <= 1.0)) {
    throw std::invalid_argument("hooverScores: the overlap threshold must lie in (0.5, 1]");
  }
  std::map<int, double> truth_size, found_size;
  std::map<std::pair<int, int>, double> overlap;
  for (std::size_t i = 0; i < truth.size(); ++i) {
    if (truth[i] >= 0) ++truth_size[truth[i]];
    if (found[i] >= 0) ++found_size[found[i]];
    if (truth[i] >= 0 && found[i] >= 0) ++overlap[{truth[i], found[i]}];
  }
  HooverScores s;
  s.truth_regions = truth_size.size();
  s.found_regions = found_size.size();
  std::set<int> truth_done, found_done;

  for (const auto& [pair, common] : overlap) {
    const auto [m, n] = pair;
    if (common >= threshold * truth_size[m] && common >= threshold * found_size[n]) {
      ++s.correct;
      s.found_of_truth[m] = n;
      s.iou_of_truth[m] = common / (truth_size[m] + found_size[n] - common);
      truth_done.insert(m);
      found_done.insert(n);
    }
  }
  // Over-segmentation: found regions lying mostly inside one truth region and covering it.
  for (const auto& [m, size] : truth_size) {
    if (truth_done.count(m)) continue;
    std::vector<int> parts;
    double covered = 0;
    for (const auto& [pair, common] : overlap) {
      const int n = pair.second;
      if (pair.first == m && !found_done.count(n) && common >= threshold * found_size[n]) {
        parts.push_back(n);
        covered += common;
      }
    }
    if (parts.size() >= 2 && covered >= threshold * size) {
      ++s.over_segmented;
      truth_done.insert(m);
      found_done.insert(parts.begin(), parts.end());
    }
  }
  // Under-segmentation: truth regions lying mostly inside one found region and covering it.
  for (const auto& [n, size] : found_size) {
    if (found_done.count(n)) continue;
    std::vector<int> parts;
    double covered = 0;
    for (const auto& [pair, common] : overlap) {
      const int m = pair.first;
      if (pair.second == n && !truth_done.count(m) && common >= threshold * truth_size[m]) {
        parts.push_back(m);
        covered += common;
      }
    }
    if (parts.size() >= 2 && covered >= threshold * size) {
      ++s.under_segmented;
      found_done.insert(n);
      truth_done.insert(parts.begin(), parts.end());
    }
  }
  s.missed = s.truth_regions - truth_done.size();
  s.noise = s.found_regions - found_done.size();
  return s;
}

}  // namespace evaluation
}  // namespace hope
