// Surface ids (surface_grouping.h): pieces of one surface in a frame share one id (the largest
// piece's in a first frame; a surface keeps its id from frame to frame); a piece at another
// height, facing the other way or elsewhere is a surface of its own. How far apart in
// height two pieces may be follows the sensor's noise at their ranges and the up's error across
// the distance between them; where a piece lies follows where its id was seen in the last second.
#include <cmath>
#include <optional>
#include <vector>

#include <gtest/gtest.h>

#include "hope/surface_grouping.h"

namespace hope {
namespace {

HorizontalPlane piece(int id, double height, double x0, double y0, double x1, double y1,
                      Facing facing = Facing::kUp) {
  HorizontalPlane p;
  p.id = id;
  p.height = height;
  p.bbox = {{x0, y0, x1, y1}};
  p.area = (x1 - x0) * (y1 - y0);
  p.centroid = Eigen::Vector3d((x0 + x1) / 2, (y0 + y1) / 2, height);
  p.facing = facing;
  return p;
}

// One frame with no range noise: the step and the up's error (1° by default) decide.
void assignOneFrame(std::vector<HorizontalPlane>& planes, double step) {
  SurfaceGroupingOptions options;
  options.max_height_step = step;
  SurfaceGrouping(options).assign(planes, 0.0, std::nullopt, std::nullopt);
}

TEST(SurfaceGrouping, PiecesOfOneSurfaceShareTheLargestPiecesId) {
  std::vector<HorizontalPlane> planes = {
      piece(4, 0.755, 0.8, 0.2, 1.5, 0.6),  // overlaps the table top, 5 mm up: a piece of it
      piece(7, 0.750, 0.0, 0.0, 1.0, 1.0),  // the table top, the largest piece
      piece(9, 0.745, 1.4, 0.5, 1.8, 0.9),  // overlaps piece 4 only: one surface through it
      piece(2, 0.800, 0.2, 0.2, 0.4, 0.4),  // a book on the table, 5 cm up
      piece(3, 0.750, 3.0, 0.0, 4.0, 1.0),  // another table at the same height, elsewhere
      piece(5, 0.752, 0.1, 0.1, 0.3, 0.3, Facing::kDown),  // seen from below: not the top
  };
  assignOneFrame(planes, 0.02);
  EXPECT_EQ(planes[0].surface_id, 7);
  EXPECT_EQ(planes[1].surface_id, 7);
  EXPECT_EQ(planes[2].surface_id, 7);
  EXPECT_EQ(planes[3].surface_id, 2);
  EXPECT_EQ(planes[4].surface_id, 3);
  EXPECT_EQ(planes[5].surface_id, 5);
}

TEST(SurfaceGrouping, HeightsFurtherApartThanTheStepAreTwoSurfaces) {
  std::vector<HorizontalPlane> planes = {piece(0, 0.70, 0, 0, 1, 1),
                                         piece(1, 0.73, 0.5, 0, 1.2, 1)};
  assignOneFrame(planes, 0.02);
  EXPECT_EQ(planes[0].surface_id, 0);
  EXPECT_EQ(planes[1].surface_id, 1);
  assignOneFrame(planes, 0.04);  // a coarser r_z joins them
  EXPECT_EQ(planes[0].surface_id, 0);
  EXPECT_EQ(planes[1].surface_id, 0);
}

TEST(SurfaceGrouping, AChainThatDriftsFromTheLargestPieceKeepsItsEnd) {
  // 0.750 - 0.765 - 0.780: each within 2 cm of the next, the last 3 cm from the largest, whose
  // centre is 1.25 m away (an up 1° off explains 2.2 cm there, not 3).
  std::vector<HorizontalPlane> planes = {
      piece(0, 0.750, 0, 0, 1, 1), piece(1, 0.765, 0.8, 0, 1.6, 1), piece(2, 0.780, 1.5, 0, 2, 1)};
  assignOneFrame(planes, 0.02);
  EXPECT_EQ(planes[0].surface_id, 0);
  EXPECT_EQ(planes[1].surface_id, 0);
  EXPECT_EQ(planes[2].surface_id, 2);
}

// A floor 1.2 m below a depth camera, read in two pieces 3 cm apart in height: far away that
// is the camera's noise (σ 1.2 + 1.9 (d − 0.4)² mm: 22 and 27 mm at 3.7 and 4.1 m, 34 mm for a
// difference), close by it is not (at 1.2 m σ is 2.4 mm: 3 cm is more than r_z, a thing 3 cm up).
TEST(SurfaceGrouping, HowFarApartOneSurfacesPiecesMayBeFollowsTheNoiseAtTheirRange) {
  const Eigen::Vector3d camera(0, 0, 1.2);
  SurfaceGrouping grouping;  // r_z 0.02
  std::vector<HorizontalPlane> far = {piece(0, 0.00, 3.0, -0.5, 4.0, 0.5),
                                      piece(1, 0.03, 3.5, 0.3, 4.2, 0.9)};
  grouping.assign(far, 0.0, camera, RangeNoise::depthCamera(), false);
  EXPECT_EQ(far[1].surface_id, 0) << "3 cm at 3.7-4.1 m is within the noise of one surface";
  std::vector<HorizontalPlane> near = {piece(0, 0.00, 0.2, -0.5, 1.0, 0.5),
                                       piece(1, 0.03, 0.6, 0.3, 1.2, 0.9)};
  grouping.assign(near, 1.0, camera, RangeNoise::depthCamera(), false);
  EXPECT_EQ(near[1].surface_id, 1) << "3 cm at 1.3 m is a thing 3 cm up";
  // Without a noise model (or a viewpoint) the step and the up's error (1.2 cm across the 0.7 m
  // between the pieces' centres) decide, far away too.
  grouping.assign(far, 2.0, std::nullopt, RangeNoise::depthCamera(), false);
  EXPECT_EQ(far[1].surface_id, 1);
  grouping.assign(far, 3.0, camera, std::nullopt, false);
  EXPECT_EQ(far[1].surface_id, 1);
}

// A floor levelled by an up 0.9° off reads 3.1 cm higher 2 m further on (2 m · tan 0.9°): two
// pieces whose centres are 2 m apart are one surface when the up's error is 1°, two when the up
// is taken as exact.
// Two faces 2.5 cm apart in height side by side (centres 0.4 m apart: 7 mm at 1°) stay apart.
TEST(SurfaceGrouping, AnUpADegreeOffLeavesTheFarPiecesOfOneFloorOneSurface) {
  const double rise = 2.0 * std::tan(0.9 * M_PI / 180.0);
  auto floor = [rise] {
    return std::vector<HorizontalPlane>{piece(0, 0.0, 0.0, 0.0, 2.0, 1.0),
                                        piece(1, rise, 1.8, 0.0, 4.2, 1.0)};
  };
  std::vector<HorizontalPlane> planes = floor();
  SurfaceGrouping().assign(planes, 0.0, std::nullopt, std::nullopt, false);
  EXPECT_EQ(planes[1].surface_id, 1) << "the larger piece names the surface";
  EXPECT_EQ(planes[0].surface_id, 1) << rise << " m across 2 m is the up's 1°";
  SurfaceGroupingOptions exact_up;
  exact_up.up_error_deg = 0.0;
  planes = floor();
  SurfaceGrouping(exact_up).assign(planes, 0.0, std::nullopt, std::nullopt, false);
  EXPECT_EQ(planes[0].surface_id, 0) << "more than r_z apart with an exact up";
  EXPECT_EQ(planes[1].surface_id, 1);
  std::vector<HorizontalPlane> steps = {piece(0, 0.10, 0.0, 0.0, 0.5, 0.5),
                                        piece(1, 0.125, 0.4, 0.0, 0.9, 0.4)};
  SurfaceGrouping().assign(steps, 0.0, std::nullopt, std::nullopt, false);
  EXPECT_EQ(steps[0].surface_id, 0);
  EXPECT_EQ(steps[1].surface_id, 1) << "a face 2.5 cm up beside the other";
  // The same faces 2.7–2.8 m from a depth camera: 16.7 mm of noise in the difference of their
  // readings (σ 12.0 and 11.5 mm), 18.1 mm with the up's 7 mm, less than the 2.5 cm between them.
  const Eigen::Vector3d camera(0.45, -2.5, 0.5);
  steps = {piece(0, 0.10, 0.0, 0.0, 0.5, 0.5), piece(1, 0.125, 0.4, 0.0, 0.9, 0.4)};
  SurfaceGrouping().assign(steps, 0.0, camera, RangeNoise::depthCamera(), false);
  EXPECT_EQ(steps[0].surface_id, 0);
  EXPECT_EQ(steps[1].surface_id, 1) << "2.5 cm up at 2.5 m";
  // A platform 5 cm up whose centre is 3 m from the floor's (5.2 cm at 1°): the up's share is
  // held to two steps (4 cm), and the platform stays apart.
  std::vector<HorizontalPlane> room = {piece(0, 0.0, 0.0, 0.0, 6.0, 4.0),
                                       piece(1, 0.05, 5.5, 1.5, 6.5, 2.5)};
  SurfaceGrouping().assign(room, 0.0, std::nullopt, std::nullopt, false);
  EXPECT_EQ(room[1].surface_id, 1) << "a platform 5 cm up";
}

TEST(SurfaceGrouping, OptionsOutOfRangeAreRefusedByName) {
  SurfaceGroupingOptions options;
  options.up_error_deg = 90.0;
  EXPECT_THROW(SurfaceGrouping{options}, std::invalid_argument);
  options.up_error_deg = -1.0;
  EXPECT_THROW(SurfaceGrouping{options}, std::invalid_argument);
  options.up_error_deg = std::nan("");
  EXPECT_THROW(SurfaceGrouping{options}, std::invalid_argument);
  options = SurfaceGroupingOptions();
  options.max_height_step = 0.0;
  EXPECT_THROW(SurfaceGrouping{options}, std::invalid_argument);
  options = SurfaceGroupingOptions();
  options.memory_s = -1.0;
  EXPECT_THROW(SurfaceGrouping{options}, std::invalid_argument);
  EXPECT_NO_THROW(SurfaceGrouping{SurfaceGroupingOptions()});
}

// A table top seen whole, then cut by a box standing on it into a large piece and a strip beside
// it whose box does not reach the large piece's (the box's shadow between them): where the
// table was seen a moment ago says the strip is the table's. A second later, or after the clock
// went back, that is no longer known.
TEST(SurfaceGrouping, PiecesApartNowAreOneSurfaceWhereTheirIdsWereSeenOne) {
  SurfaceGrouping grouping;
  std::vector<HorizontalPlane> whole = {piece(7, 0.75, 0.0, 0.0, 1.2, 0.8)};
  grouping.assign(whole, 10.0, std::nullopt, std::nullopt);
  auto cut = [] {
    return std::vector<HorizontalPlane>{piece(7, 0.75, 0.0, 0.0, 0.8, 0.8),
                                        piece(12, 0.755, 1.0, 0.0, 1.2, 0.8)};
  };
  // The strip's own id was seen across the table a moment ago (the tracker kept it apart).
  std::vector<HorizontalPlane> strip_seen = {piece(12, 0.755, 0.5, 0.0, 1.2, 0.8)};
  grouping.assign(strip_seen, 10.2, std::nullopt, std::nullopt);
  std::vector<HorizontalPlane> now = cut();
  grouping.assign(now, 10.4, std::nullopt, std::nullopt);
  EXPECT_EQ(now[1].surface_id, 7) << "the strip's id was seen where the table is";
  // Told not to remember, the frame's own boxes alone decide: they do not meet.
  now = cut();
  SurfaceGrouping fresh;
  fresh.assign(now, 10.4, std::nullopt, std::nullopt, false);
  EXPECT_EQ(now[1].surface_id, 12);
  // Over a second after those frames, the earlier boxes are forgotten.
  now = cut();
  grouping.assign(now, 12.0, std::nullopt, std::nullopt);
  EXPECT_EQ(now[1].surface_id, 12);
  // A clock that went back forgets them too.
  grouping.assign(strip_seen, 20.0, std::nullopt, std::nullopt);
  now = cut();
  grouping.assign(now, 5.0, std::nullopt, std::nullopt);
  EXPECT_EQ(now[1].surface_id, 12);
}

// A table top in two pieces, then seen whole as one piece that carries the smaller piece's id
// (the tracker paired it so): the table is one surface throughout, and keeps the id it had. A
// moment later a second piece joins it again; after memory_s unseen, the name is forgotten.
TEST(SurfaceGrouping, ASurfaceKeepsItsIdWhenItsPiecesChange) {
  SurfaceGrouping grouping;
  std::vector<HorizontalPlane> two = {piece(97, 0.75, 0.0, 0.0, 0.6, 0.8),
                                      piece(103, 0.752, 0.55, 0.0, 1.0, 0.8)};
  grouping.assign(two, 10.0, std::nullopt, std::nullopt);
  ASSERT_EQ(two[0].surface_id, 97) << "the larger piece names the surface";
  ASSERT_EQ(two[1].surface_id, 97);
  std::vector<HorizontalPlane> whole = {piece(103, 0.751, 0.0, 0.0, 1.0, 0.8)};
  grouping.assign(whole, 10.3, std::nullopt, std::nullopt);
  EXPECT_EQ(whole[0].surface_id, 97) << "the same table, seen whole under its other piece's id";
  std::vector<HorizontalPlane> again = {piece(103, 0.751, 0.0, 0.0, 0.9, 0.8),
                                        piece(110, 0.75, 0.85, 0.0, 1.0, 0.8)};
  grouping.assign(again, 10.6, std::nullopt, std::nullopt);
  EXPECT_EQ(again[0].surface_id, 97);
  EXPECT_EQ(again[1].surface_id, 97) << "a new piece of it joins its surface";
  whole = {piece(103, 0.751, 0.0, 0.0, 1.0, 0.8)};
  grouping.assign(whole, 12.0, std::nullopt, std::nullopt);
  EXPECT_EQ(whole[0].surface_id, 103) << "over memory_s later its surface is not remembered";
}

// A shelf seen as one surface in two pieces (7 names it), then the pieces apart in height (they
// were two shelves): the piece that named the surface keeps the name even where the other is
// now larger, the other is a surface of its own, and no two surfaces of the frame share an id.
TEST(SurfaceGrouping, WhenASurfacePartsThePieceThatNamedItKeepsTheName) {
  SurfaceGrouping grouping;
  std::vector<HorizontalPlane> one = {piece(7, 1.00, 0.0, 0.0, 1.0, 0.5),
                                      piece(12, 1.005, 0.9, 0.0, 1.4, 0.5)};
  grouping.assign(one, 3.0, std::nullopt, std::nullopt);
  ASSERT_EQ(one[1].surface_id, 7);
  std::vector<HorizontalPlane> apart = {piece(7, 1.00, 0.0, 0.0, 0.5, 0.5),
                                        piece(12, 1.10, 0.9, 0.0, 2.0, 0.5)};
  grouping.assign(apart, 3.3, std::nullopt, std::nullopt);
  EXPECT_EQ(apart[0].surface_id, 7);
  EXPECT_EQ(apart[1].surface_id, 12);
  // Told not to remember, a frame's surfaces are named by their largest pieces.
  std::vector<HorizontalPlane> whole = {piece(12, 1.005, 0.0, 0.0, 1.4, 0.5)};
  grouping.assign(whole, 3.6, std::nullopt, std::nullopt, false);
  EXPECT_EQ(whole[0].surface_id, 12);
}

}  // namespace
}  // namespace hope
