// Plane identities across frames: the paper's NNPM (Eq 11–14), the improved tracker, the
// optimal assignment and the identity scores.
#include <cmath>
#include <fstream>
#include <iterator>
#include <limits>
#include <map>
#include <random>
#include <set>

#include <gtest/gtest.h>

#include "helpers.h"
#include "hope/box_index.h"
#include "hope/evaluation/tracking_metrics.h"
#include "hope/optimal_assignment.h"
#include "hope/plane_matching.h"
#include "hope/plane_tracker.h"
#include "hope/synthetic/sequences.h"

namespace hope {
namespace {

HorizontalPlane makePlane(double height, double x0, double y0, double x1, double y1) {
  HorizontalPlane p;
  p.height = height;
  p.bbox = {x0, y0, x1, y1};
  p.centroid = Eigen::Vector3d(0.5 * (x0 + x1), 0.5 * (y0 + y1), height);
  return p;
}

std::vector<int> idsOf(const std::vector<HorizontalPlane>& planes) {
  std::vector<int> ids;
  for (const auto& p : planes) ids.push_back(p.id);
  return ids;
}

TrackerOptions mode(TrackingMode m) {
  TrackerOptions o;
  o.mode = m;
  return o;
}

TEST(PlaneMatching, NormalizesJointlyAsEquations11To14) {
  // z_mean over both frames: 1, 2 (previous) and 3, 6 (current): mean 3, population variance
  // (4 + 1 + 0 + 9) / 4 = 3.5. x_min: 0, 0, 2, 2: mean 1, std 1. y_min all 5: no spread.
  std::vector<PlaneFeatures> previous(2), current(2);
  previous[0] << 1, 0, 5, 1, 7;
  previous[1] << 2, 0, 5, 1, 8;
  current[0] << 3, 2, 5, 3, 9;
  current[1] << 6, 2, 5, 3, 10;
  normalizeJointly(previous, current);
  const double s = std::sqrt(3.5);
  EXPECT_NEAR(previous[0][0], -2 / s, 1e-12);
  EXPECT_NEAR(previous[1][0], -1 / s, 1e-12);
  EXPECT_NEAR(current[0][0], 0.0, 1e-12);
  EXPECT_NEAR(current[1][0], 3 / s, 1e-12);
  EXPECT_NEAR(previous[0][1], -1.0, 1e-12);
  EXPECT_NEAR(current[1][1], 1.0, 1e-12);
  for (const auto* set : {&previous, &current}) {
    for (const auto& f : *set) {
      EXPECT_EQ(f[2], 0.0) << "a feature without spread must become 0, not NaN";
      EXPECT_TRUE(f.allFinite());
    }
  }
  // y_max: 7, 8, 9, 10 → mean 8.5, std sqrt(1.25).
  EXPECT_NEAR(current[1][4], 1.5 / std::sqrt(1.25), 1e-12);
}

TEST(PlaneMatching, ClosestCurrentPlaneKeepsAContestedPreviousPlane) {
  const std::vector<HorizontalPlane> previous = {makePlane(0.0, 0, 0, 1, 1),
                                                 makePlane(1.0, 0, 0, 1, 1)};
  // Both current planes are nearest to previous[1]; the second is closer.
  const std::vector<HorizontalPlane> current = {makePlane(0.8, 0, 0, 1, 1),
                                                makePlane(0.95, 0, 0, 1, 1)};
  const auto matches = matchNearestNeighbors(previous, current);
  ASSERT_EQ(matches.size(), 2u);
  EXPECT_EQ(matches[0].previous, -1);
  EXPECT_EQ(matches[1].previous, 1);
}

TEST(PlaneMatching, SinglePlaneEachFrameMatchesDespiteZeroSpread) {
  // One plane per frame, identical: every feature has zero spread.
  const auto matches =
      matchNearestNeighbors({makePlane(0.7, 0, 0, 1, 1)}, {makePlane(0.7, 0, 0, 1, 1)});
  ASSERT_EQ(matches.size(), 1u);
  EXPECT_EQ(matches[0].previous, 0);
  EXPECT_EQ(matches[0].distance, 0.0);
}

TEST(OptimalAssignment, FindsTheMinimumTotalCost) {
  Eigen::MatrixXd cost(3, 3);
  // Greedy on the smallest entry (1 at 0,0) would give 1 + 5 + 9 = 15; the optimum is 2+2+2.
  cost << 1, 2, 9, 2, 5, 9, 9, 9, 2;
  cost(0, 1) = 2;
  cost(1, 0) = 2;
  const auto a = solveAssignment(cost);
  EXPECT_EQ(a, (std::vector<int>{1, 0, 2}));
  Eigen::MatrixXd wide(2, 4);
  wide << 5, 1, 7, 7, 1, 2, 7, 7;
  EXPECT_EQ(solveAssignment(wide), (std::vector<int>{1, 0}));
  EXPECT_EQ(solveAssignment(wide.transpose()), (std::vector<int>{1, 0, -1, -1}));
  EXPECT_TRUE(solveAssignment(Eigen::MatrixXd(0, 3)).empty());
}

TEST(OptimalAssignment, SparsePairsWithAnUnpairedCostPairOnlyWhatIsWorthIt) {
  // Rows 0-1 compete for columns 0-1 (optimum 2 + 2, not the greedy 1 + 5); row 2 and column 2
  // form their own component; row 3's only pair costs more than leaving both unpaired (2 x 3).
  const std::vector<CandidatePair> pairs = {{0, 0, 1}, {0, 1, 2},   {1, 0, 2},
                                            {1, 1, 5}, {2, 2, 0.5}, {3, 3, 7}};
  const SparseAssignment a = assignWithUnpairedCost(pairs, 4, 5, 3.0);
  EXPECT_EQ(a.col_of_row, (std::vector<int>{1, 0, 2, -1}));
  // Pairs 2 + 2 + 0.5, and row 3, columns 3 and 4 left out at 3 each.
  EXPECT_DOUBLE_EQ(a.total_cost, 4.5 + 3 * 3.0);
  // Above the exact size, the component is paired greedily: cheapest pair first.
  const SparseAssignment greedy = assignWithUnpairedCost(pairs, 4, 5, 3.0, 3);
  EXPECT_EQ(greedy.col_of_row, (std::vector<int>{0, 1, 2, -1}));
  EXPECT_TRUE(assignWithUnpairedCost({}, 0, 0, 1.0).col_of_row.empty());
}

TEST(BoxIndex, FindsEveryBoxWithinTheMarginsOnceAndFewOthers) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(0.0, 20.0);
  std::vector<BoxIndex::Box> boxes;
  std::vector<double> heights;
  for (int i = 0; i < 400; ++i) {
    const double x = u(rng), y = u(rng);
    boxes.push_back({x, y, x + 0.05 * u(rng), y + 0.05 * u(rng)});
    heights.push_back(0.1 * u(rng));
  }
  boxes.push_back({-5, -5, 30, 30});  // a floor under everything
  heights.push_back(0.0);
  boxes.push_back({NAN, 0, 1, 1});  // never found
  heights.push_back(0.0);
  boxes.push_back({1e9, 1e9, 1e9 + 1, 1e9 + 1});  // far out: found by nearby queries only
  heights.push_back(0.0);
  BoxIndex index;
  index.rebuild(boxes, heights, 0.8, 0.1);
  const double margin = 0.4, height_margin = 0.05;
  std::size_t near = 0, visited = 0;
  for (std::size_t q = 0; q < boxes.size(); ++q) {
    const BoxIndex::Box& query = boxes[q];
    std::vector<int> count(boxes.size(), 0);
    index.forEachNear(query, heights[q], margin, height_margin, [&](int i) { ++count[i]; });
    for (std::size_t i = 0; i < boxes.size(); ++i) {
      const double gx = std::max({query[0] - boxes[i][2], boxes[i][0] - query[2], 0.0});
      const double gy = std::max({query[1] - boxes[i][3], boxes[i][1] - query[3], 0.0});
      const bool finite = std::isfinite(boxes[i][0]) && std::isfinite(query[0]);
      const bool within = finite && std::hypot(gx, gy) <= margin &&
                          std::fabs(heights[i] - heights[q]) <= height_margin;
      EXPECT_LE(count[i], 1);
      if (within) {
        EXPECT_EQ(count[i], 1) << "box " << i << " missed by query " << q;
      }
      near += within ? 1 : 0;
      visited += count[i];
    }
  }
  EXPECT_GT(near, boxes.size());  // more than each box finding itself
  // Far fewer candidates than all pairs (403²): the index prunes.
  EXPECT_LT(visited, boxes.size() * boxes.size() / 10);
}

TEST(PlaneTracker, ThousandFragmentsOfOneSurfaceAreTrackedWithoutSolvingOneHugeProblem) {
  // 1,000 small fragments of one table top (what r_xy = 1 mm makes of it), all within each
  // other's gates: one component far beyond the exact size. Each fragment keeps its id.
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<HorizontalPlane> scene;
  for (int i = 0; i < 1000; ++i) {
    const double x = 2 * u(rng), y = u(rng);
    scene.push_back(makePlane(0.75, x, y, x + 0.03, y + 0.03));
  }
  PlaneTracker tracker(mode(TrackingMode::kImproved));
  std::vector<HorizontalPlane> frame = scene;
  tracker.update(frame, 0.0);
  const std::vector<int> first = idsOf(frame);
  frame = scene;
  tracker.update(frame, 0.1);
  EXPECT_EQ(idsOf(frame), first);
}

TEST(PlaneTracker, FirstFrameIdsFollowExtractionOrderAndPlanesKeepThem) {
  for (auto m : {TrackingMode::kPaper, TrackingMode::kImproved}) {
    PlaneTracker tracker(mode(m));
    std::vector<HorizontalPlane> frame1 = {makePlane(0.0, -2, -2, 2, 2),
                                           makePlane(0.75, 0, 0, 1.2, 0.8),
                                           makePlane(0.45, -1.5, 0, -1, 0.6)};
    tracker.update(frame1, 0.0);
    EXPECT_EQ(idsOf(frame1), (std::vector<int>{0, 1, 2})) << toString(m);
    // Next frame: other extraction order, slightly shifted, one part of the floor unseen.
    std::vector<HorizontalPlane> frame2 = {makePlane(0.46, -1.48, 0.02, -1, 0.6),
                                           makePlane(0.01, -2, -1.5, 1.9, 2),
                                           makePlane(0.75, 0.05, 0, 1.2, 0.8)};
    tracker.update(frame2, 0.033);
    EXPECT_EQ(idsOf(frame2), (std::vector<int>{2, 0, 1})) << toString(m);
    EXPECT_EQ(frame2[0].age, 2);
    EXPECT_DOUBLE_EQ(frame2[0].last_seen, 0.033);
  }
}

TEST(PlaneTracker, ImprovedModeGivesAPlaneHiddenForThreeFramesItsIdBack) {
  const HorizontalPlane table = makePlane(0.75, 0, 0, 1.2, 0.8), floor = makePlane(0, -2, -2, 2, 2),
                        shelf = makePlane(1.2, -1, 1, -0.5, 1.3);
  PlaneTracker improved(mode(TrackingMode::kImproved)), paper(mode(TrackingMode::kPaper));
  for (PlaneTracker* tracker : {&improved, &paper}) {
    std::vector<HorizontalPlane> all = {floor, table, shelf};
    tracker->update(all, 0);
    for (int hidden = 1; hidden <= 3; ++hidden) {
      std::vector<HorizontalPlane> without_table = {floor, shelf};
      tracker->update(without_table, hidden);
      EXPECT_EQ(idsOf(without_table), (std::vector<int>{0, 2}));
    }
    std::vector<HorizontalPlane> back = {floor, table, shelf};
    const auto events = tracker->update(back, 4);
    if (tracker == &improved) {
      EXPECT_EQ(idsOf(back), (std::vector<int>{0, 1, 2}));
      ASSERT_FALSE(events.empty());
      EXPECT_EQ(events[0].kind, TrackEvent::Kind::kRecovered);
      EXPECT_EQ(events[0].other_id, 3) << "missed frames";
      EXPECT_EQ(back[1].age, 2);
    } else {
      EXPECT_EQ(back[1].id, 3) << "the paper's NNPM has no memory: the table is re-numbered";
    }
  }
}

TEST(PlaneTracker, ImprovedModeFollowsASensorThatMovesOnAsItMoved) {
  // Five 10 cm planes at heights 15 cm apart, 0.5 m apart, seen by a sensor that speeds up to
  // 28 cm a frame (a hand-held camera walking at 3 Hz with an orientation only: the scene moves
  // by the sensor's motion), then stops dead. From 20 cm a frame on, a plane's box is more than
  // the 9 cm the cost allows clear of its old box (at 20 cm: 1 + 7.2 + 1.0 = 9.2); after the
  // last frame's motion it lies a few centimetres off (the motion measured from the planes'
  // centroids reads part of a shift as a turn). Every plane is the same surface throughout: its
  // first id, in every frame.
  const double velocity[] = {0.04, 0.08, 0.12, 0.16, 0.20, 0.24, 0.28, 0.28, 0.28, 0.0, 0.0};
  PlaneTracker tracker(mode(TrackingMode::kImproved));
  const auto scene = [](double shift) {
    std::vector<HorizontalPlane> planes;
    for (int k = 0; k < 5; ++k) {
      const double x = shift + 0.5 * k, y = 1.0 + 0.5 * (k % 2);
      planes.push_back(makePlane(0.3 + 0.15 * k, x, y, x + 0.1, y + 0.1));
    }
    return planes;
  };
  std::vector<HorizontalPlane> first = scene(0.0);
  tracker.update(first, 0);
  const std::vector<int> ids = idsOf(first);
  double shift = 0.0;
  for (std::size_t f = 0; f < std::size(velocity); ++f) {
    shift += velocity[f];
    std::vector<HorizontalPlane> planes = scene(shift);
    tracker.update(planes, static_cast<double>(f + 1));
    EXPECT_EQ(idsOf(planes), ids) << "frame " << f + 1 << ", moved " << velocity[f] << " m";
  }
}

TEST(PlaneTracker, ImprovedModeFollowsAHandHeldCameraTurning8DegreesAFrameAt3Hz) {
  // An orientation only (an accelerometer): the reference frame turns and moves with the
  // camera, which turns 8° and steps 5 cm between frames a third of a second apart (kitchen_dev's
  // camera turns up to 10° so). Five surfaces 20-30 cm across, 2.7-3.5 m away, move by 38-49 cm
  // a frame, past the 9 cm any pair reaches and further than the last frame's motion predicts on
  // the first turn; the motion searched within what a sensor can do in 1/3 s (45°/s, 0.75 m/s)
  // pairs them (the tracker lost them before it searched). Every surface keeps its first id in
  // every frame.
  struct Rectangle {
    double height, x0, y0, x1, y1;
  };
  const Rectangle room[] = {{0.75, 2.6, 0.4, 2.9, 0.7},
                            {0.45, 2.8, -1.0, 3.0, -0.7},
                            {1.10, 3.2, -0.2, 3.4, 0.1},
                            {0.90, 2.4, 1.4, 2.7, 1.6},
                            {0.30, 2.9, -1.8, 3.1, -1.5}};
  // The room as seen after the scene turned by `yaw` about the sensor and shifted by `shift`.
  const auto seen = [&](double yaw, const Eigen::Vector2d& shift) {
    std::vector<HorizontalPlane> planes;
    const Eigen::Rotation2Dd turn(yaw);
    for (const Rectangle& r : room) {
      HorizontalPlane p = makePlane(r.height, 0, 0, 0, 0);
      Eigen::Vector2d lo(HUGE_VAL, HUGE_VAL), hi(-HUGE_VAL, -HUGE_VAL);
      for (const Eigen::Vector2d& c : {Eigen::Vector2d(r.x0, r.y0), Eigen::Vector2d(r.x1, r.y0),
                                       Eigen::Vector2d(r.x1, r.y1), Eigen::Vector2d(r.x0, r.y1)}) {
        const Eigen::Vector2d q = turn * c + shift;
        p.hull.emplace_back(q.x(), q.y(), r.height);
        lo = lo.cwiseMin(q);
        hi = hi.cwiseMax(q);
      }
      p.bbox = {lo.x(), lo.y(), hi.x(), hi.y()};
      const Eigen::Vector2d centre =
          turn * Eigen::Vector2d(0.5 * (r.x0 + r.x1), 0.5 * (r.y0 + r.y1)) + shift;
      p.centroid = Eigen::Vector3d(centre.x(), centre.y(), r.height);
      p.num_points = static_cast<std::size_t>(1e4 * (r.x1 - r.x0) * (r.y1 - r.y0));
      planes.push_back(p);
    }
    return planes;
  };
  PlaneTracker tracker(mode(TrackingMode::kImproved));
  std::vector<HorizontalPlane> first = seen(0.0, Eigen::Vector2d::Zero());
  tracker.update(first, 0.0);
  const std::vector<int> ids = idsOf(first);
  double yaw = 0.0;
  Eigen::Vector2d shift = Eigen::Vector2d::Zero();
  for (int frame = 1; frame <= 8; ++frame) {
    // The camera turns left and steps forward: the scene turns right and comes closer.
    yaw -= 8.0 * M_PI / 180.0;
    shift = Eigen::Rotation2Dd(-8.0 * M_PI / 180.0) * shift + Eigen::Vector2d(-0.05, 0.0);
    std::vector<HorizontalPlane> planes = seen(yaw, shift);
    tracker.update(planes, frame / 3.0);
    EXPECT_EQ(idsOf(planes), ids) << "frame " << frame << ", turned " << frame * 8 << " deg";
  }
}

TEST(PlaneTracker, ImprovedModeRejectsAHeightJumpThatPaperModeAccepts) {
  // The only plane jumps 30 cm: another surface. NNPM with one plane per frame matches
  // anything (all features have zero or maximal normalized spread).
  for (auto m : {TrackingMode::kPaper, TrackingMode::kImproved}) {
    PlaneTracker tracker(mode(m));
    std::vector<HorizontalPlane> a = {makePlane(0.45, 0, 0, 1, 1)};
    tracker.update(a, 0);
    std::vector<HorizontalPlane> b = {makePlane(0.75, 0, 0, 1, 1)};
    tracker.update(b, 1);
    EXPECT_EQ(b[0].id, m == TrackingMode::kPaper ? 0 : 1) << toString(m);
  }
}

TEST(PlaneTracker, PairsPlanesThatMovedApartAsFarAsTheCostAllowsAndNoFurther) {
  // A 20 cm plane that jumps sideways clear of its old box (overlap and IoU 0) costs
  // 1 + 0.8·max_match_cost + (gap / xy_scale)², a pair only below max_match_cost, and never
  // beyond the max_xy_gap gate. The search near each track must reach every such pair.
  struct Case {
    double xy_scale, gap;
    bool same_id;
  };
  const Case cases[] = {
      {0.10, 0.089, true},   // 8.2 + 0.7921 < 9 (the limit is at a gap of 0.0894)
      {0.10, 0.095, false},  // 8.2 + 0.9025 > 9
      {0.40, 0.357, true},   // 8.2 + 0.7966 < 9 (limit 0.3578), inside the 0.4 m gate
      {0.40, 0.365, false},  // 8.2 + 0.8327 > 9
      {1.00, 0.399, true},   // cost 8.36: far below the limit, inside the 0.4 m gate
      {1.00, 0.410, false},  // cost 8.37, but beyond the 0.4 m gate
  };
  // The scene is placed at 100 offsets 1 cm apart, so that wherever the search's cells are,
  // some placements put a cell border inside the gap; 200 planes 2 m higher fill the search's
  // index, as a real scene would (with one plane it is cheaper to look at all).
  std::vector<HorizontalPlane> shelves;
  for (int i = 0; i < 200; ++i) {
    shelves.push_back(makePlane(2.75, 0.3 * (i % 20), 0.3 * (i / 20), 0.3 * (i % 20) + 0.2,
                                0.3 * (i / 20) + 0.2));
  }
  for (const Case& c : cases) {
    for (int k = 0; k < 100; ++k) {
      TrackerOptions o = mode(TrackingMode::kImproved);
      o.xy_scale = c.xy_scale;
      o.max_match_cost = 9.0;
      o.max_xy_gap = 0.4;
      PlaneTracker tracker(o);
      const double x = 0.01 * k;
      std::vector<HorizontalPlane> before = shelves, after = shelves;
      before.push_back(makePlane(0.75, x, 0, x + 0.2, 0.2));
      tracker.update(before, 0);
      const double x0 = x + 0.2 + c.gap;
      after.push_back(makePlane(0.75, x0, 0, x0 + 0.2, 0.2));
      tracker.update(after, 1);
      EXPECT_EQ(after.back().id == before.back().id, c.same_id)
          << "xy_scale " << c.xy_scale << ", gap " << c.gap << ", at x " << x;
    }
  }
}

TEST(PlaneTracker, MergeKeepsTheLargerPartsIdAndSplitNamesItsParent) {
  PlaneTracker tracker;
  std::vector<HorizontalPlane> parts = {makePlane(0.75, 0, 0, 0.7, 1),
                                        makePlane(0.75, 0.8, 0, 1.2, 1)};
  tracker.update(parts, 0);
  std::vector<HorizontalPlane> merged = {makePlane(0.75, 0, 0, 1.2, 1)};
  auto events = tracker.update(merged, 1);
  EXPECT_EQ(merged[0].id, 0) << "the part covering most of the merged plane keeps its id";
  bool merge_reported = false;
  for (const auto& e : events)
    merge_reported |= e.kind == TrackEvent::Kind::kMerged && e.id == 1 && e.other_id == 0;
  EXPECT_TRUE(merge_reported);
  EXPECT_TRUE(tracker.lostPlanes().empty()) << "a merged plane is not remembered as lost";

  std::vector<HorizontalPlane> split = {makePlane(0.75, 0.7, 0, 1.2, 1),
                                        makePlane(0.75, 0, 0, 0.6, 1)};
  events = tracker.update(split, 4);
  // The larger part (the second, with the old box's corner) or the first keeps 0; the other
  // part is new and names 0 as its parent.
  const int keeper = split[0].id == 0 ? 0 : 1;
  EXPECT_EQ(split[keeper].id, 0);
  EXPECT_EQ(split[1 - keeper].split_from, 0);
  EXPECT_GE(split[1 - keeper].id, 2) << "new ids are never reused";
}

TEST(PlaneTracker, NeverGivesOneIdToTwoPlanesNorReusesAnEndedId) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (auto m : {TrackingMode::kPaper, TrackingMode::kImproved}) {
    PlaneTracker tracker(mode(m));
    std::set<int> ended;
    int max_id = -1;
    for (int frame = 0; frame < 300; ++frame) {
      const int highest_before = max_id;
      std::vector<HorizontalPlane> planes;
      const int count = static_cast<int>(u(rng) * 12);
      for (int k = 0; k < count; ++k) {
        const double x = std::floor(u(rng) * 4), h = 0.1 * std::floor(u(rng) * 5);
        planes.push_back(makePlane(h + 0.005 * u(rng), x, 0, x + 0.5 + 0.5 * u(rng), 1));
      }
      const auto events = tracker.update(planes, frame);
      std::set<int> ids;
      for (const auto& p : planes) {
        EXPECT_TRUE(ids.insert(p.id).second) << "id " << p.id << " twice in frame " << frame;
        EXPECT_EQ(ended.count(p.id), 0u) << "ended id " << p.id << " came back";
        max_id = std::max(max_id, p.id);
      }
      for (const auto& e : events) {
        if (e.kind == TrackEvent::Kind::kEnded || e.kind == TrackEvent::Kind::kMerged)
          ended.insert(e.id);
        if (e.kind == TrackEvent::Kind::kNew) {
          EXPECT_GT(e.id, highest_before) << "a new id was reused";
        }
      }
    }
  }
}

TEST(PlaneTracker, RejectsBadOptions) {
  TrackerOptions o;
  o.max_height_change = -1;
  EXPECT_THROW(PlaneTracker{o}, std::invalid_argument);
  o = TrackerOptions();
  o.height_scale = std::nan("");
  EXPECT_THROW(PlaneTracker{o}, std::invalid_argument);
  o = TrackerOptions();
  o.merge_split_overlap = 0.0;  // every plane at a height would be part of every other
  EXPECT_THROW(PlaneTracker{o}, std::invalid_argument);
  EXPECT_THROW(trackingModeFromString("best"), std::invalid_argument);
  EXPECT_EQ(trackingModeFromString("paper"), TrackingMode::kPaper);
}

TEST(IdentityScorer, CountsAccuracySwitchesAndFragmentations) {
  evaluation::IdentityScorer scorer;
  const std::set<int> both = {0, 1};
  scorer.addFrame({0, 1}, {0, 1}, {100, 50}, both);
  scorer.addFrame({0, 1}, {0, 1}, {100, 50}, both);  // 2 right
  scorer.addFrame({1, 0}, {0, 1}, {100, 50}, both);  // ids swapped: 2 wrong, 2 switches
  scorer.addFrame({1}, {0}, {100}, both);            // 1 right; surface 1 lost while in view
  scorer.addFrame({1, 7}, {0, 1}, {100, 50}, both);  // 1 right, new id 7 right (1 unseen)
  // Surface 0 split in two: the old id on one part, a new id on the other: both right.
  scorer.addFrame({1, 8, 7}, {0, 0, 1}, {60, 40, 50}, both);
  const auto& s = scorer.scores();
  EXPECT_EQ(s.frames, 6u);
  EXPECT_EQ(s.pairs_checked, 2u + 2u + 1u + 2u + 3u);
  EXPECT_EQ(s.pairs_correct, 2u + 0u + 1u + 2u + 3u);
  EXPECT_EQ(s.id_switches, 2u + 1u) << "swap twice, then surface 1 came back as 7";
  EXPECT_EQ(s.fragmentations, 1u);
  EXPECT_EQ(s.duplicate_ids, 0u);
  scorer.addFrame({3, 3}, {0, 1}, {1, 1}, both);
  EXPECT_EQ(scorer.scores().duplicate_ids, 1u);
}

TEST(IdentityF1, PairsIdsWithSurfacesOnceAndWeighsByArea) {
  // Two frames; the floor (surface 0, 4 m²) and a table (1, 1 m²) in view in both.
  const std::map<int, double> areas = {{0, 4.0}, {1, 1.0}};
  evaluation::IdentityF1 steady;
  steady.addFrame({7, 8}, {0, 1}, {4.0, 1.0}, areas);
  steady.addFrame({7, 8}, {0, 1}, {4.0, 1.0}, areas);
  EXPECT_DOUBLE_EQ(steady.score(), 1.0);

  // The floor in two halves under two ids, the second frame under a third id: the best id
  // holds 2 of the floor's 8 m² (ids pair with one surface each for the whole sequence).
  evaluation::IdentityF1 split;
  split.addFrame({1, 2, 8}, {0, 0, 1}, {2.0, 2.0, 1.0}, areas);
  split.addFrame({3, 4, 8}, {0, 0, 1}, {2.0, 2.0, 1.0}, areas);
  // IDTP = 2 (floor, one id) + 2 (table): 2·4 / (10 + 10).
  EXPECT_DOUBLE_EQ(split.score(), 2.0 * 4.0 / 20.0);

  // A noise plane counts against precision only; a missed surface against recall only.
  evaluation::IdentityF1 noisy;
  noisy.addFrame({7, 9}, {0, -1}, {4.0, 1.0}, areas);  // the table missed, a noise plane
  EXPECT_DOUBLE_EQ(noisy.score(), 2.0 * 4.0 / (5.0 + 5.0));
}

TEST(IdentityF1, TrueAreasCountOccupiedCellsPerLabel) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const std::vector<Eigen::Vector3f> points = {
      {0.01f, 0.01f, 0}, {0.02f, 0.03f, 0}, {0.07f, 0.01f, 0}, {0.5f, 0.5f, 1}, {nan, nan, nan}};
  const auto areas = evaluation::trueAreas(points, {0, 0, 0, 1, 1}, 0.05);
  ASSERT_EQ(areas.size(), 2u);
  EXPECT_NEAR(areas.at(0), 2 * 0.0025, 1e-12);  // two cells
  EXPECT_NEAR(areas.at(1), 0.0025, 1e-12);      // the NaN point is not counted
}

// With the fragment merge, the floor and the table keep one id each while a pillar passes in
// front of them and the camera moves (without it, the pillar's shadow splits the floor and
// each part gets its own id).
TEST(Tracking, FloorAndTableKeepOneIdThroughAnOcclusionWhenFragmentsMerge) {
  const synthetic::TrackingScene scene;
  for (const std::string name : {"occlusion", "pan"}) {
    const auto sequence = synthetic::makeTrackingSequence(name, 45, 320);
    Extractor extractor;  // merge on by default
    PlaneTracker tracker;
    std::set<int> floor_ids, table_ids;
    for (std::size_t f = 0; f < sequence.frames.size(); ++f) {
      const auto& frame = sequence.frames[f];
      synthetic::SensorNoise noise;
      noise.seed = static_cast<std::uint32_t>(f + 1);
      const auto rendered = scene.render(frame.camera, frame.occluder_xy, noise);
      const Result result =
          extractor.extract(depthToCloud(rendered.depth, frame.camera.intrinsics, 1.0),
                            Orientation::fromTransform(frame.camera.pose));
      const std::vector<int> truth = evaluation::groundTruthOfPlanes(
          result, std::vector<int>(rendered.labels.begin<std::int32_t>(),
                                   rendered.labels.end<std::int32_t>()));
      std::vector<HorizontalPlane> planes = result.planes;
      tracker.update(planes, frame.stamp);
      // The largest plane on each surface carries its id; on the floor it holds nearly all
      // of the floor's extracted points.
      int floor = -1, table = -1;
      std::size_t floor_points = 0;
      for (std::size_t k = 0; k < planes.size(); ++k) {
        if (truth[k] == 0) floor_points += planes[k].num_points;
        if (truth[k] == 0 && (floor < 0 || planes[k].num_points > planes[floor].num_points)) {
          floor = static_cast<int>(k);
        }
        if (truth[k] == 1 && (table < 0 || planes[k].num_points > planes[table].num_points)) {
          table = static_cast<int>(k);
        }
      }
      ASSERT_GE(floor, 0) << name << " frame " << f << ": the floor is in every frame";
      EXPECT_GE(planes[floor].num_points, 0.95 * floor_points)
          << name << " frame " << f << ": the floor is one plane; " << test::describe(result);
      floor_ids.insert(planes[floor].id);
      if (table >= 0) table_ids.insert(planes[table].id);
    }
    EXPECT_EQ(floor_ids.size(), 1u) << name;
    EXPECT_EQ(table_ids.size(), 1u) << name;
  }
}

// Renders the tracking scene from two camera poses and returns the planes of each, with the
// ground-truth surface of each plane.
struct Seen {
  std::vector<HorizontalPlane> planes;
  std::vector<int> truth;
};

Seen see(const synthetic::TrackingScene& scene, const synthetic::Camera& camera, bool full_pose) {
  synthetic::SensorNoise noise;
  const auto frame = scene.render(camera, Eigen::Vector2d(100, 100), noise);
  Extractor extractor;  // default r_xy, r_z
  const auto cloud = depthToCloud(frame.depth, camera.intrinsics, 1.0);
  Orientation orientation = Orientation::fromTransform(camera.pose);
  if (!full_pose) {
    const Eigen::Vector3d up = camera.pose.linear().transpose() * Eigen::Vector3d::UnitZ();
    orientation = Orientation::fromGravity(up.x(), up.y(), up.z());
  }
  const Result result = extractor.extract(cloud, orientation);
  std::vector<int> point_truth(frame.labels.begin<std::int32_t>(),
                               frame.labels.end<std::int32_t>());
  // Only clean planes: the default r_z joins the pattern object's base with its lowest blocks
  // 2 cm above, a plane that belongs to no single surface.
  return {result.planes, evaluation::groundTruthOfPlanes(result, point_truth, 0.8)};
}

// The id of each surface's largest part, for surfaces seen substantially (300+ points).
std::map<int, int> idOfSurface(const Seen& seen) {
  std::map<int, std::size_t> largest;
  std::map<int, int> id;
  for (std::size_t k = 0; k < seen.planes.size(); ++k) {
    const int surface = seen.truth[k];
    if (surface >= 0 && seen.planes[k].num_points >= 300 &&
        seen.planes[k].num_points > largest[surface]) {
      largest[surface] = seen.planes[k].num_points;
      id[surface] = seen.planes[k].id;
    }
  }
  return id;
}

// Every surface seen in both frames keeps its id (that of its largest part).
void expectIdsKept(const Seen& before, const Seen& after, const std::string& what) {
  const auto id_before = idOfSurface(before);
  int checked = 0;
  for (const auto& [surface, id] : idOfSurface(after)) {
    if (!id_before.count(surface)) continue;
    EXPECT_EQ(id, id_before.at(surface))
        << what << ": " << synthetic::TrackingScene::surfaceName(surface) << " (" << surface << ")";
    ++checked;
  }
  EXPECT_GE(checked, 3) << what << ": too few surfaces seen twice to mean anything";
}

TEST(PlaneTrackerOnRenderedScenes, IdsSurviveACameraTranslationAndA20DegreeYaw) {
  const synthetic::TrackingScene scene;
  const auto start = synthetic::makeTrackingSequence("pan", 2, 640).frames[0].camera;
  synthetic::Camera moved = start;
  moved.pose.translation() += Eigen::Vector3d(0.3, 0.2, 0.0);
  synthetic::Camera yawed = moved;
  yawed.pose.linear() =
      Eigen::AngleAxisd(20 * M_PI / 180, Eigen::Vector3d::UnitZ()).toRotationMatrix() *
      moved.pose.linear();
  for (auto m : {TrackingMode::kPaper, TrackingMode::kImproved}) {
    PlaneTracker tracker(mode(m));
    Seen a = see(scene, start, true), b = see(scene, moved, true), c = see(scene, yawed, true);
    tracker.update(a.planes, 0);
    tracker.update(b.planes, 1);
    expectIdsKept(a, b, std::string(toString(m)) + ", translation by (0.3, 0.2) m");
    tracker.update(c.planes, 2);
    expectIdsKept(b, c, std::string(toString(m)) + ", 20° yaw");
  }
}

TEST(PlaneTrackerOnRenderedScenes, ImprovedModeKeepsIdsThroughAYawWithGravityOnly) {
  // Gravity only (an accelerometer): the reference frame turns with the camera, so every
  // plane's box moves; 20° in 2° steps.
  const synthetic::TrackingScene scene;
  const auto start = synthetic::makeTrackingSequence("pan", 2, 640).frames[0].camera;
  PlaneTracker tracker;
  Seen first = see(scene, start, false);
  tracker.update(first.planes, 0);
  Seen last = first;
  for (int step = 1; step <= 10; ++step) {
    synthetic::Camera cam = start;
    cam.pose.linear() =
        Eigen::AngleAxisd(step * 2 * M_PI / 180, Eigen::Vector3d::UnitZ()).toRotationMatrix() *
        start.pose.linear();
    Seen now = see(scene, cam, false);
    tracker.update(now.planes, step);
    expectIdsKept(last, now, "gravity only, yaw step " + std::to_string(step));
    last = now;
  }
}

TEST(PatternObject, MatchesThePapersModelWhenPresent) {
  const std::string path = test::sharedData("pattern_object/pattern_object.STL");
  std::ifstream stl(path, std::ios::binary);
  if (!stl) {
    GTEST_SKIP() << "no " << path << " (../shared/data absent): STL check skipped";
  }
  // Binary STL: 80-byte header, triangle count, then per triangle normal, 3 vertices, 2 bytes.
  stl.ignore(80);
  std::uint32_t count = 0;
  stl.read(reinterpret_cast<char*>(&count), 4);
  ASSERT_GT(count, 0u);
  std::map<int, double> stl_area_by_height_mm;
  for (std::uint32_t i = 0; i < count; ++i) {
    float v[12];
    std::uint16_t attribute;
    stl.read(reinterpret_cast<char*>(v), sizeof(v));
    stl.read(reinterpret_cast<char*>(&attribute), 2);
    ASSERT_TRUE(stl) << "truncated STL";
    if (v[2] < 0.99f) continue;  // only upward faces
    const Eigen::Vector3d a(v[3], v[4], v[5]), b(v[6], v[7], v[8]), c(v[9], v[10], v[11]);
    stl_area_by_height_mm[static_cast<int>(std::lround(a.z() * 1000))] +=
        0.5 * (b - a).cross(c - a).norm();
  }
  // The generator's upward faces, by height, from a dense scan from above.
  synthetic::Scene scene;
  synthetic::addPatternObject(scene, Eigen::Isometry3d::Identity(), 0);
  const double step = 0.002;
  const auto scan = scene.scanFromAbove(step / 2, step / 2, 0.96 - step / 2, 0.96 - step / 2, step);
  std::map<int, double> generated_area_by_height_mm;
  std::set<int> labels;
  for (std::size_t i = 0; i < scan.cloud.size(); ++i) {
    generated_area_by_height_mm[static_cast<int>(std::lround(scan.cloud[i].z * 1000))] +=
        step * step;
    labels.insert(scan.labels[i]);
  }
  EXPECT_EQ(labels.size(), static_cast<std::size_t>(synthetic::kPatternObjectFaces));
  ASSERT_EQ(stl_area_by_height_mm.size(), generated_area_by_height_mm.size());
  for (const auto& [height_mm, area] : stl_area_by_height_mm) {
    EXPECT_NEAR(generated_area_by_height_mm[height_mm], area, 0.002)
        << "upward area at " << height_mm << " mm";
  }
}

}  // namespace
}  // namespace hope
