// Scoring plane identities over a sequence against ground-truth surfaces.
#pragma once

#include <cstddef>
#include <map>
#include <set>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "hope/extractor.h"

namespace hope {
namespace evaluation {

// The ground-truth surface of each extracted plane: the label carried by most of its points
// (`point_truth` has one label per input point, -1 for none). A plane whose majority covers
// less than `min_purity` of its points, or whose majority is -1, gets -1 (a noise plane).
std::vector<int> groundTruthOfPlanes(const Result& result, const std::vector<int>& point_truth,
                                     double min_purity = 0.5);

struct IdentityScores {
  std::size_t frames = 0;
  std::size_t planes = 0;  // extracted planes with a ground-truth surface, over all frames
  // The paper's accuracy (§3.2, Table 2): over consecutive frames, the share of planes whose
  // id is right. A plane is right when its id was, in the previous frame, on the same surface;
  // or when its id is new and its surface was not seen in the previous frame, or all of that
  // surface's previous ids went to other parts of it (a surface split into parts counts each
  // part separately, as the paper says).
  std::size_t pairs_checked = 0;
  std::size_t pairs_correct = 0;
  double accuracy() const { return pairs_checked ? double(pairs_correct) / pairs_checked : 1.0; }
  // Times a surface's id (the id of its largest part) differs from the id it had when it was
  // last seen, however long ago (a re-numbering after an occlusion counts).
  std::size_t id_switches = 0;
  // Times a surface that had a plane lost it while it stayed in view, and got one back later
  // (an interrupted trajectory, as in the CLEAR-MOT fragmentation count).
  std::size_t fragmentations = 0;
  // Frames in which one id was given to two planes: must stay 0.
  std::size_t duplicate_ids = 0;
};

// Feed frames in order; read scores() at any time.
class IdentityScorer {
 public:
  // `ids`, `truth` and `sizes` (points) have one entry per extracted plane; `visible` holds
  // the surfaces in view in this frame (from the ground-truth labels), for fragmentations.
  void addFrame(const std::vector<int>& ids, const std::vector<int>& truth,
                const std::vector<std::size_t>& sizes, const std::set<int>& visible);
  const IdentityScores& scores() const { return scores_; }

 private:
  IdentityScores scores_;
  std::map<int, int> previous_truth_of_id_;  // id → surface, previous frame
  std::map<int, int> last_id_of_surface_;    // surface → id of its largest part, last seen
  std::set<int> previous_surfaces_;
  std::set<int> interrupted_;  // surfaces in view that lost their plane
  bool first_ = true;
};

// IDF1 (identity F1, Ristani et al. 2016): how much of what was observed carries the right
// identity, with ids and true surfaces paired one-to-one for the whole sequence (the pairing
// that maximizes the identity true positives). Counted per observation and weighted by area,
// so a floor split into four ids scores by the share its best id holds, and a robot's large
// surfaces weigh more than a book.
class IdentityF1 {
 public:
  // One frame: per extracted plane its id, true surface (-1: none, a noise plane) and area;
  // per true surface in view its area.
  void addFrame(const std::vector<int>& ids, const std::vector<int>& truth,
                const std::vector<double>& areas, const std::map<int, double>& true_areas);
  // 2 · IDTP / (area of every extracted plane + area of every true surface), over all frames.
  double score() const;

 private:
  std::map<std::pair<int, int>, double> overlap_;  // (id, surface) → area, summed over frames
  double predicted_ = 0, true_ = 0;
};

// The area (m², cells of `cell` metres in xy) of the points of each label >= 0: a surface's
// true footprint in the frame `points` are in (NaN points are skipped).
std::map<int, double> trueAreas(const AlignedPoints& points, const std::vector<int>& labels,
                                double cell);

}  // namespace evaluation
}  // namespace hope
