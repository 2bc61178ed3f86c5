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
  // One region of one side split into two or more regions of the other: each part lies
  // mostly inside it and together they cover it. Over-segmentation splits a truth region into
  // found ones, under-segmentation the other way round.
  auto countSplits = [&](bool truth_is_whole) {
    const auto& whole_size = truth_is_whole ? truth_size : found_size;
    const auto& part_size = truth_is_whole ? found_size : truth_size;
    auto& whole_done = truth_is_whole ? truth_done : found_done;
    auto& part_done = truth_is_whole ? found_done : truth_done;
    std::size_t splits = 0;
    for (const auto& [whole, size] : whole_size) {
      if (whole_done.count(whole)) continue;
      std::vector<int> parts;
      double covered = 0;
      for (const auto& [pair, common] : overlap) {
        const int w = truth_is_whole ? pair.first : pair.second;
        const int part = truth_is_whole ? pair.second : pair.first;
        if (w == whole && !part_done.count(part) && common >= threshold * part_size.at(part)) {
          parts.push_back(part);
          covered += common;
        }
      }
      if (parts.size() >= 2 && covered >= threshold * size) {
        ++splits;
        whole_done.insert(whole);
        part_done.insert(parts.begin(), parts.end());
      }
    }
    return splits;
  };
  s.over_segmented = countSplits(true);
  s.under_segmented = countSplits(false);
  s.missed = s.truth_regions - truth_done.size();
  s.noise = s.found_regions - found_done.size();
  return s;
}

}  // namespace evaluation
}  // namespace hope
