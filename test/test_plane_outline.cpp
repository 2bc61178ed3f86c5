// The plane outline: the true shape of a plane, holes and concave corners included.
#include "helpers.h"
#include "hope/plane_outline.h"

namespace hope {
namespace test {

namespace {

using Cells = std::vector<std::pair<std::int64_t, std::int64_t>>;

double signedArea2D(const std::vector<Eigen::Vector2d>& ring) {
  double twice = 0;
  for (std::size_t k = 0; k < ring.size(); ++k) {
    const auto& a = ring[k];
    const auto& b = ring[(k + 1) % ring.size()];
    twice += a.x() * b.y() - b.x() * a.y();
  }
  return 0.5 * twice;
}

}  // namespace

TEST(PlaneOutline, ABlockWithAHoleIsACounterClockwiseRingAndAClockwiseOne) {
  Cells cells;
  for (int x = 0; x < 3; ++x) {
    for (int y = 0; y < 3; ++y) {
      if (x != 1 || y != 1) cells.emplace_back(x, y);
    }
  }
  const auto rings = traceOutline(cells, Eigen::Vector2d(10, 20), 0.5, 0.0, 1);
  ASSERT_EQ(rings.size(), 2u);
  EXPECT_DOUBLE_EQ(signedArea2D(rings[0]), 9 * 0.25);   // the block, counter-clockwise
  EXPECT_DOUBLE_EQ(signedArea2D(rings[1]), -1 * 0.25);  // the hole, clockwise
  EXPECT_EQ(rings[0].size(), 4u);                       // four corners, nothing in between
  for (const auto& q : rings[0]) {
    EXPECT_TRUE(q.x() == 10.0 || q.x() == 11.5) << q.transpose();
    EXPECT_TRUE(q.y() == 20.0 || q.y() == 21.5) << q.transpose();
  }
  // A hole smaller than min_hole_cells is a missing measurement: filled.
  EXPECT_EQ(traceOutline(cells, Eigen::Vector2d(0, 0), 0.5, 0.0, 4).size(), 1u);
}

TEST(PlaneOutline, CellsTouchingAtACornerAreBoundedSeparately) {
  const Cells cells = {{0, 0}, {1, 1}, {1, 1}};  // repeated cells are fine
  const auto rings = traceOutline(cells, Eigen::Vector2d(0, 0), 1.0, 0.0);
  ASSERT_EQ(rings.size(), 2u);
  for (const auto& ring : rings) EXPECT_DOUBLE_EQ(signedArea2D(ring), 1.0);
}

TEST(PlaneOutline, LShapedTableExcludesTheEmptyCornerAndMatchesTheOccupiedArea) {
  // An L of two sheets at 0.75 m over a floor, z-up: the convex hull covers the corner
  // near its inner corner (x + y < 3 with x, y > 1), the outline must not.
  LabeledCloud cloud;
  addSheet(cloud, 0, 0, 2, 1, 0.75, 0.01, 1);
  addSheet(cloud, 0, 1.01, 1, 2, 0.75, 0.01, 1);
  const Result result = extractZUp(cloud.cloud);
  const int table = planeNear(result, 0.75, 0.005);
  ASSERT_GE(table, 0) << describe(result);
  const HorizontalPlane& plane = result.planes[table];
  EXPECT_NEAR(outlineArea(plane), plane.area, 0.1 * plane.area);
  EXPECT_NEAR(plane.area, 3.0, 0.3);  // the sheets' 3 m²
  EXPECT_FALSE(outlineContains(plane, 1.3, 1.3));
  EXPECT_TRUE(outlineContains(plane, 0.5, 1.5));
  EXPECT_TRUE(outlineContains(plane, 1.5, 0.5));
  // The convex hull does cover the corner: that is why the outline exists.
  HorizontalPlane hull_only = plane;
  hull_only.outline = {plane.hull};
  EXPECT_TRUE(outlineContains(hull_only, 1.3, 1.3));
  for (const auto& ring : plane.outline) EXPECT_GT(ringArea(ring), 0.0);  // no hole
  EXPECT_LE(plane.outline.front().size(), 8u) << "an L needs six corners, a few more at most";
}

TEST(PlaneOutline, ABoxStandingInTheMiddleOfATableIsAHoleInItsOutline) {
  synthetic::Scene scene;
  scene.add<synthetic::Box>(V3(-1, -1, 0), V3(1, 1, 0.75), 1);
  scene.add<synthetic::Box>(V3(-0.2, -0.2, 0.75), V3(0.2, 0.2, 1.1), 2);
  const LabeledCloud scan = scene.scanFromAbove(-1.2, -1.2, 1.2, 1.2, 0.01);
  const Result result = extractZUp(scan.cloud);
  const int table = planeNear(result, 0.75, 0.005), box = planeNear(result, 1.1, 0.005);
  ASSERT_GE(table, 0) << describe(result);
  ASSERT_GE(box, 0) << describe(result);
  const HorizontalPlane& plane = result.planes[table];
  int holes = 0;
  for (const auto& ring : plane.outline) holes += ringArea(ring) < 0 ? 1 : 0;
  EXPECT_EQ(holes, 1);
  EXPECT_FALSE(outlineContains(plane, 0.0, 0.0));  // where the box stands
  EXPECT_TRUE(outlineContains(plane, 0.6, 0.6));
  EXPECT_TRUE(outlineContains(result.planes[box], 0.0, 0.0));
  // Outline area: the table's 4 m² minus the box's 0.16 m², within the grid's resolution.
  EXPECT_NEAR(outlineArea(plane), 4.0 - 0.16, 0.1 * plane.area);
}

}  // namespace test
}  // namespace hope
