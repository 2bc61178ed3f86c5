#include "hope/evaluation/tracking_metrics.h"

#include <cmath>
#include <cstdint>
#include <stdexcept>

#include "hope/optimal_assignment.h"

namespace hope {
namespace evaluation {

std::vector<int> groundTruthOfPlanes(const Result& result, const std::vector<int>& point_truth,
                                     double min_purity) {
  if (point_truth.size() != result.point_labels.size()) {
    throw std::invalid_argument(
        "groundTruthOfPlanes: one ground-truth label per input point needed");
  }
  std::vector<std::map<int, std::size_t>> votes(result.planes.size());
  for (std::size_t i = 0; i < point_truth.size(); ++i) {
    const int plane = result.point_labels[i];
    if (plane >= 0) ++votes[plane][point_truth[i]];
  }
  std::vector<int> truth(result.planes.size(), -1);
  for (std::size_t k = 0; k < votes.size(); ++k) {
    std::size_t total = 0, best = 0;
    int best_label = -1;
    for (const auto& [label, count] : votes[k]) {
      total += count;
      if (count > best) {
        best = count;
        best_label = label;
      }
    }
    if (total > 0 && best >= min_purity * total) truth[k] = best_label;
  }
  return truth;
}

void IdentityScorer::addFrame(const std::vector<int>& ids, const std::vector<int>& truth,
                              const std::vector<std::size_t>& sizes, const std::set<int>& visible) {
  if (ids.size() != truth.size() || ids.size() != sizes.size()) {
    throw std::invalid_argument("IdentityScorer::addFrame: ids, truth and sizes differ in length");
  }
  ++scores_.frames;
  std::set<int> seen_ids;
  for (int id : ids) {
    if (!seen_ids.insert(id).second) ++scores_.duplicate_ids;
  }

  // Ids a surface had in the previous frame, and which of them survive on that surface now.
  std::map<int, std::set<int>> previous_ids_of_surface;
  for (const auto& [id, surface] : previous_truth_of_id_)
    previous_ids_of_surface[surface].insert(id);
  std::map<int, std::set<int>> kept_ids_of_surface;
  for (std::size_t k = 0; k < ids.size(); ++k) {
    const auto it = previous_truth_of_id_.find(ids[k]);
    if (truth[k] >= 0 && it != previous_truth_of_id_.end() && it->second == truth[k]) {
      kept_ids_of_surface[truth[k]].insert(ids[k]);
    }
  }

  std::map<int, std::size_t> largest_size;
  std::map<int, int> largest_id;
  for (std::size_t k = 0; k < ids.size(); ++k) {
    const int surface = truth[k];
    if (surface < 0) continue;
    ++scores_.planes;
    if (!first_) {
      ++scores_.pairs_checked;
      const auto it = previous_truth_of_id_.find(ids[k]);
      bool correct;
      if (it != previous_truth_of_id_.end()) {
        correct = it->second == surface;
      } else {
        // A new id is right only if no previous id of this surface was left unused.
        const auto& before = previous_ids_of_surface[surface];
        correct = kept_ids_of_surface[surface].size() == before.size();
      }
      scores_.pairs_correct += correct ? 1 : 0;
    }
    if (sizes[k] > largest_size[surface]) {
      largest_size[surface] = sizes[k];
      largest_id[surface] = ids[k];
    }
  }

  for (const auto& [surface, id] : largest_id) {
    const auto last = last_id_of_surface_.find(surface);
    if (last != last_id_of_surface_.end() && last->second != id) ++scores_.id_switches;
    last_id_of_surface_[surface] = id;
    if (interrupted_.erase(surface)) ++scores_.fragmentations;
  }
  for (int surface : previous_surfaces_) {
    if (!largest_id.count(surface) && visible.count(surface)) interrupted_.insert(surface);
  }
  for (auto it = interrupted_.begin(); it != interrupted_.end();) {
    it = visible.count(*it) ? std::next(it) : interrupted_.erase(it);  // left the view
  }

  previous_truth_of_id_.clear();
  previous_surfaces_.clear();
  for (std::size_t k = 0; k < ids.size(); ++k) {
    if (truth[k] < 0) continue;
    previous_truth_of_id_[ids[k]] = truth[k];
    previous_surfaces_.insert(truth[k]);
  }
  first_ = false;
}

void IdentityF1::addFrame(const std::vector<int>& ids, const std::vector<int>& truth,
                          const std::vector<double>& areas,
                          const std::map<int, double>& true_areas) {
  if (truth.size() != ids.size() || areas.size() != ids.size()) {
    throw std::invalid_argument("IdentityF1::addFrame: one truth and one area per plane needed");
  }
  for (std::size_t k = 0; k < ids.size(); ++k) {
    predicted_ += areas[k];
    if (truth[k] < 0) continue;
    // A plane is scored on the surface most of its points lie on, at most that surface's area.
    const auto surface = true_areas.find(truth[k]);
    const double area = surface == true_areas.end() ? 0.0 : std::min(areas[k], surface->second);
    overlap_[{ids[k], truth[k]}] += area;
  }
  for (const auto& [surface, area] : true_areas) true_ += area;
}

double IdentityF1::score() const {
  if (predicted_ + true_ <= 0) return 1.0;
  std::map<int, int> row_of_id, col_of_surface;
  for (const auto& [pair, area] : overlap_) {
    row_of_id.emplace(pair.first, static_cast<int>(row_of_id.size()));
    col_of_surface.emplace(pair.second, static_cast<int>(col_of_surface.size()));
  }
  if (overlap_.empty()) return 0.0;
  // The one-to-one pairing of ids and surfaces with the most shared area: a minimum-cost
  // assignment on the negated areas.
  Eigen::MatrixXd cost = Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(row_of_id.size()),
                                               static_cast<Eigen::Index>(col_of_surface.size()));
  for (const auto& [pair, area] : overlap_) {
    cost(row_of_id.at(pair.first), col_of_surface.at(pair.second)) = -area;
  }
  const std::vector<int> col_of_row = solveAssignment(cost);
  double true_positive = 0;
  for (std::size_t r = 0; r < col_of_row.size(); ++r) {
    if (col_of_row[r] >= 0) true_positive -= cost(static_cast<Eigen::Index>(r), col_of_row[r]);
  }
  return 2.0 * true_positive / (predicted_ + true_);
}

std::map<int, double> trueAreas(const AlignedPoints& points, const std::vector<int>& labels,
                                double cell) {
  if (points.size() != labels.size()) {
    throw std::invalid_argument("trueAreas: one label per point needed");
  }
  std::map<int, std::set<std::pair<std::int64_t, std::int64_t>>> cells;
  for (std::size_t i = 0; i < points.size(); ++i) {
    if (labels[i] < 0 || !points[i].allFinite()) continue;
    cells[labels[i]].emplace(static_cast<std::int64_t>(std::floor(points[i].x() / cell)),
                             static_cast<std::int64_t>(std::floor(points[i].y() / cell)));
  }
  std::map<int, double> areas;
  for (const auto& [label, occupied] : cells) {
    areas[label] = static_cast<double>(occupied.size()) * cell * cell;
  }
  return areas;
}

}  // namespace evaluation
}  // namespace hope
