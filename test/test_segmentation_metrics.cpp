// Hoover et al. (1996) region classification on hand-made segmentations.
#include <stdexcept>
#include <vector>

#include <gtest/gtest.h>

#include "hope/evaluation/segmentation_metrics.h"

namespace hope {
namespace evaluation {
namespace {

// `count` copies of `label` appended to `labels`.
void add(std::vector<int>& labels, int label, int count) {
  labels.insert(labels.end(), count, label);
}

TEST(HooverScores, CorrectDetectionWithItsIou) {
  std::vector<int> truth, found;
  add(truth, 0, 100);
  add(found, 7, 90);
  add(found, -1, 10);  // 10 points of the truth region not found
  const HooverScores s = hooverScores(truth, found);
  EXPECT_EQ(s.correct, 1u);
  EXPECT_EQ(s.found_of_truth.at(0), 7);
  EXPECT_DOUBLE_EQ(s.iou_of_truth.at(0), 0.9);
  EXPECT_EQ(s.missed + s.noise + s.over_segmented + s.under_segmented, 0u);
}

TEST(HooverScores, BelowTheThresholdIsMissedAndNoise) {
  std::vector<int> truth, found;
  add(truth, 0, 100);
  add(found, 7, 70);  // only 70 % of the truth region: not correct at T = 0.8
  add(found, -1, 30);
  const HooverScores s = hooverScores(truth, found, 0.8);
  EXPECT_EQ(s.correct, 0u);
  EXPECT_EQ(s.missed, 1u);
  EXPECT_EQ(s.noise, 1u);
  EXPECT_EQ(hooverScores(truth, found, 0.6).correct, 1u) << "correct at a laxer threshold";
}

TEST(HooverScores, OverAndUnderSegmentation) {
  std::vector<int> truth, found;
  // Truth region 0 split into found 1 and 2.
  add(truth, 0, 100);
  add(found, 1, 50);
  add(found, 2, 50);
  // Truth regions 3 and 4 merged into found 5.
  add(truth, 3, 60);
  add(truth, 4, 40);
  add(found, 5, 100);
  // A found region on nothing: noise. A truth region never found: missed.
  add(truth, -1, 20);
  add(found, 6, 20);
  add(truth, 8, 30);
  add(found, -1, 30);
  const HooverScores s = hooverScores(truth, found);
  EXPECT_EQ(s.truth_regions, 4u);
  EXPECT_EQ(s.found_regions, 4u);
  EXPECT_EQ(s.correct, 0u);
  EXPECT_EQ(s.over_segmented, 1u);
  EXPECT_EQ(s.under_segmented, 1u);
  EXPECT_EQ(s.noise, 1u);
  EXPECT_EQ(s.missed, 1u);
}

TEST(HooverScores, RejectsBadInput) {
  EXPECT_THROW(hooverScores({0, 1}, {0}), std::invalid_argument);
  EXPECT_THROW(hooverScores({0}, {0}, 0.5), std::invalid_argument);
  EXPECT_THROW(hooverScores({0}, {0}, 1.1), std::invalid_argument);
  const HooverScores empty = hooverScores({}, {});
  EXPECT_EQ(empty.truth_regions + empty.found_regions, 0u);
}

}  // namespace
}  // namespace evaluation
}  // namespace hope
