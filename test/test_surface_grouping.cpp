// Surface ids (surface_grouping.h): pieces of one surface in a frame share the largest one's id;
// a piece at another height, facing the other way or elsewhere keeps its own.
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
  p.facing = facing;
  return p;
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
  assignSurfaceIds(planes, 0.02);
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
  assignSurfaceIds(planes, 0.02);
  EXPECT_EQ(planes[0].surface_id, 0);
  EXPECT_EQ(planes[1].surface_id, 1);
  assignSurfaceIds(planes, 0.04);  // a coarser r_z joins them
  EXPECT_EQ(planes[0].surface_id, 0);
  EXPECT_EQ(planes[1].surface_id, 0);
}

TEST(SurfaceGrouping, AChainThatDriftsFromTheLargestPieceKeepsItsEnd) {
  // 0.750 - 0.765 - 0.780: each within 2 cm of the next, the last 3 cm from the largest.
  std::vector<HorizontalPlane> planes = {piece(0, 0.750, 0, 0, 2, 2), piece(1, 0.765, 1.5, 0, 3, 1),
                                         piece(2, 0.780, 2.8, 0, 3.5, 1)};
  assignSurfaceIds(planes, 0.02);
  EXPECT_EQ(planes[0].surface_id, 0);
  EXPECT_EQ(planes[1].surface_id, 0);
  EXPECT_EQ(planes[2].surface_id, 2);
}

}  // namespace
}  // namespace hope
