// The paper's evaluation at a small scale: the pattern object generator, and the headline
// claims of docs/evaluation.md (26 faces at the paper's setting, no sloped plane above the
// threshold, no Fig 3 primitive), plus the baselines' plumbing.
#include <gtest/gtest.h>

#include "hope/evaluation/baselines.h"
#include "hope/evaluation/segmentation_metrics.h"
#include "hope/extractor.h"
#include "hope/synthetic/paper_scenes.h"

namespace hope {
namespace {

using synthetic::TiltAxis;

Params paperSetting() {
  Params p;
  p.r_xy = 0.009;
  p.r_z = 0.002;
  return p;
}

synthetic::LabeledCloud scanPattern(double tilt = 0.0, TiltAxis axis = TiltAxis::kPlusX) {
  return synthetic::patternObjectScene(tilt, axis)
      .scanFromAbove(-0.55, -0.55, 0.55, 0.55, 0.004, 0.0003, 5);
}

// A small camera straight above `xy` at 1.5 m, looking down.
synthetic::Camera cameraAbove(double x, double y) {
  synthetic::Camera camera =
      synthetic::Camera::lookingAt(Eigen::Vector3d(x, y, 1.5), Eigen::Vector3d(x, y, 0.0));
  camera.width = 64;
  camera.height = 48;
  camera.intrinsics = {50.0, 50.0, 32.0, 24.0};
  return camera;
}

TEST(PatternObject, AKnownPixelLandsOnAKnownFace) {
  const synthetic::Scene scene = synthetic::patternObjectScene();
  synthetic::SensorNoise exact;
  exact.enabled = false;
  // Block (4, 4), the tallest, spans [0.60, 0.96]² in object coordinates: its centre is at
  // (0.30, 0.30) with the object centred on the origin; top at 0.20 m, face label 25.
  auto frame = scene.render(cameraAbove(0.30, 0.30), exact);
  EXPECT_EQ(frame.labels.at<std::int32_t>(24, 32), 25);
  EXPECT_NEAR(frame.depth.at<float>(24, 32), 1.5 - 0.20, 1e-5);
  EXPECT_DOUBLE_EQ(synthetic::patternFaceHeight(25), 0.20);
  // (0.03, 0.03) in object coordinates is the gap between the two smallest blocks: the base.
  frame = scene.render(cameraAbove(0.03 - 0.48, 0.03 - 0.48), exact);
  EXPECT_EQ(frame.labels.at<std::int32_t>(24, 32), 0);
  EXPECT_NEAR(frame.depth.at<float>(24, 32), 1.5 - 0.10, 1e-5);
  // Block (1, 3): row 1 along y [0.04, 0.08], column 3 along x [0.28, 0.44]; top 0.14 m.
  frame = scene.render(cameraAbove(0.36 - 0.48, 0.06 - 0.48), exact);
  EXPECT_EQ(frame.labels.at<std::int32_t>(24, 32), 1 + 5 * 1 + 3);
  EXPECT_NEAR(frame.depth.at<float>(24, 32), 1.5 - 0.14, 1e-5);
}

TEST(PaperEvaluation, AllTwentySixFacesCorrectAtThePapersSettingWithNoNoise) {
  const auto scan = scanPattern();
  Extractor extractor(paperSetting());
  const Result result = extractor.extract(scan.cloud, Orientation::identity());
  const std::vector<int> found(result.point_labels.begin(), result.point_labels.end());
  const auto scores = evaluation::hooverScores(scan.labels, found, 0.8);
  EXPECT_EQ(scores.truth_regions, 26u);
  EXPECT_EQ(scores.correct, 26u);
  EXPECT_EQ(scores.noise, 0u);
  EXPECT_EQ(scores.over_segmented + scores.under_segmented + scores.missed, 0u);
  for (const auto& [face, plane] : scores.found_of_truth) {
    EXPECT_NEAR(result.planes[plane].height, synthetic::patternFaceHeight(face), 0.001)
        << "face " << face;
  }
}

TEST(PaperEvaluation, NoSlopedPlaneSurvivesATiltAboveTheThreshold) {
  const Params paper = paperSetting();
  ASSERT_NEAR(paper.maxSlope(), 0.2187, 1e-4);
  for (TiltAxis axis : {TiltAxis::kPlusX, TiltAxis::kMinusY}) {
    Extractor extractor(paper);
    // threshold + 0.01 rad up to the end of the paper's sweep (Fig 9, 0.23 rad): every face is
    // too steep. (Steeper tilts still leave a few strips: see docs/evaluation.md.)
    for (double tilt : {0.2287, 0.23}) {
      const Result above =
          extractor.extract(scanPattern(tilt, axis).cloud, Orientation::identity());
      EXPECT_EQ(above.planes.size(), 0u) << "tilt " << tilt;
    }
    // Well below the threshold the faces are horizontal by definition and kept.
    const Result below = extractor.extract(scanPattern(0.15, axis).cloud, Orientation::identity());
    EXPECT_GE(below.planes.size(), 20u);
  }
}

TEST(PaperEvaluation, EveryFigure3PrimitiveIsRejected) {
  for (const Params& params : {Params(), paperSetting()}) {
    Extractor extractor(params);
    for (auto& primitive : synthetic::falsePositivePrimitives(params.maxSlope() + 0.1)) {
      const auto scan = primitive.scene.scanFromAbove(-0.5, -0.5, 0.5, 0.5, 0.004, 0.0003);
      ASSERT_GT(scan.cloud.size(), 1000u) << primitive.name;
      const Result result = extractor.extract(scan.cloud, Orientation::identity());
      EXPECT_EQ(result.planes.size(), 0u) << primitive.name << " at r_xy " << params.r_xy;
    }
  }
}

TEST(Baselines, LabelEveryPointAndFindTheLargestFace) {
  const auto scan = scanPattern();
  const Params paper = paperSetting();
  const auto grid = evaluation::gridded(scan.cloud, paper);
  ASSERT_EQ(grid.point_voxel.size(), scan.cloud.size());
  for (bool ransac : {true, false}) {
    const auto r = ransac ? evaluation::ransacPlanes(grid, paper)
                          : evaluation::regionGrowingPlanes(grid, paper);
    ASSERT_EQ(r.point_labels.size(), scan.cloud.size());
    ASSERT_FALSE(r.heights.empty());
    // The base (face 0, the largest) is found as one plane at 0.10 m by both.
    const auto scores = evaluation::hooverScores(scan.labels, r.point_labels, 0.8);
    ASSERT_TRUE(scores.found_of_truth.count(0)) << (ransac ? "RANSAC" : "region growing");
    EXPECT_NEAR(r.heights[scores.found_of_truth.at(0)], 0.10, 0.002);
  }
}

}  // namespace
}  // namespace hope
