// The floor grid (floor_grid.h) on points whose answer is known by construction: a floor with a
// box standing on it, a tilted floor followed, and frames' grids laid over each other.
#include <vector>

#include <gtest/gtest.h>

#include "hope/floor_grid.h"

namespace hope {
namespace {

constexpr double kCell = 0.1;

HorizontalPlane levelFloor(double height, Eigen::Vector3d normal = Eigen::Vector3d::UnitZ()) {
  HorizontalPlane floor;
  floor.height = height;
  floor.centroid = Eigen::Vector3d(1.0, 1.0, height);
  floor.normal = normal.normalized();
  return floor;
}

// The cell value at reference-frame (x, y), or -2 outside the grid.
int cellAt(const FloorGrid& grid, double x, double y) {
  const int cx = static_cast<int>(std::floor((x - grid.origin.x()) / grid.resolution));
  const int cy = static_cast<int>(std::floor((y - grid.origin.y()) / grid.resolution));
  if (cx < 0 || cy < 0 || cx >= grid.width || cy >= grid.height) return -2;
  return grid.cells[static_cast<std::size_t>(cy) * grid.width + cx];
}

// A 2 × 2 m floor at z = 0.5 sampled every 2 cm from (0, 0), a 0.3 m box over
// [1.0, 1.4] × [0.6, 1.0] (its top at 0.8 m), a lamp hanging at 3 m over (0.25, 0.25) and a
// hole's bottom 0.4 m under the floor at (1.75, 1.75).
std::vector<Eigen::Vector3f> roomPoints() {
  std::vector<Eigen::Vector3f> points;
  for (double x = 0.01; x < 2.0; x += 0.02) {
    for (double y = 0.01; y < 2.0; y += 0.02) {
      const bool box = x > 1.0 && x < 1.4 && y > 0.6 && y < 1.0;
      const bool hole = x > 1.7 && x < 1.8 && y > 1.7 && y < 1.8;
      const bool lamp = x > 0.2 && x < 0.3 && y > 0.2 && y < 0.3;
      points.emplace_back(x, y, box ? 0.8 : hole ? 0.1 : 0.5);
      if (lamp) points.emplace_back(x, y, 3.5);
    }
  }
  points.emplace_back(std::nanf(""), 0.f, 0.f);
  return points;
}

TEST(FloorGrid, TheBoxIsOccupiedTheFloorFreeAndTheHoleAndTheSkyUnseen) {
  const std::vector<Eigen::Vector3f> points = roomPoints();
  const FloorGrid grid = floorGrid(AlignedPoints(points), Eigen::Vector3d::Zero(), levelFloor(0.5),
                                   Eigen::Vector2d(1, 1), 0.05, 0.05, 2.0, kCell);
  EXPECT_EQ(grid.width, 20);
  EXPECT_EQ(grid.height, 20);
  EXPECT_DOUBLE_EQ(grid.floor_height, 0.5);
  int occupied = 0, free = 0;
  for (int cy = 0; cy < grid.height; ++cy) {
    for (int cx = 0; cx < grid.width; ++cx) {
      const double x = grid.origin.x() + (cx + 0.5) * kCell,
                   y = grid.origin.y() + (cy + 0.5) * kCell;
      const int cell = grid.cells[static_cast<std::size_t>(cy) * grid.width + cx];
      if (x > 1.0 && x < 1.4 && y > 0.6 && y < 1.0) {
        EXPECT_EQ(cell, FloorGrid::kOccupied) << x << " " << y;
        ++occupied;
      } else if (x > 1.7 && x < 1.8 && y > 1.7 && y < 1.8) {
        EXPECT_EQ(cell, FloorGrid::kUnseen) << "a hole below the floor is not floor";
      } else {
        EXPECT_EQ(cell, FloorGrid::kFree) << x << " " << y << ": the lamp above 2 m is no obstacle";
        ++free;
      }
    }
  }
  EXPECT_EQ(occupied, 16);
  EXPECT_EQ(free, 400 - 16 - 1);
}

TEST(FloorGrid, ATiltedFloorIsFollowedAndCellsStayOnTheResolutionsMultiples) {
  // The floor rising 8 cm a metre along x (4.6°), 8 cm above and below its centroid's height at
  // its ends: read as level, its low end would fall out of the floor's 5 cm and its high end
  // stand on it; the points 8 cm above it beyond x = 1.8 m are a thing standing there.
  std::vector<Eigen::Vector3f> points;
  for (double x = 0.01; x < 2.0; x += 0.02) {
    for (double y = 0.01; y < 2.0; y += 0.02) {
      const double floor_z = 0.08 * (x - 1.0);
      points.emplace_back(x, y, floor_z + (x > 1.8 ? 0.08 : 0.0));
    }
  }
  // The points relative to a local origin (as the extractor keeps them far from the origin).
  const Eigen::Vector3d local_origin(100.0, -50.0, 0.0);
  for (Eigen::Vector3f& p : points) p -= local_origin.cast<float>();
  HorizontalPlane floor = levelFloor(0.0, Eigen::Vector3d(-0.08, 0, 1));
  floor.centroid = Eigen::Vector3d(1.0, 1.0, 0.0);
  const FloorGrid grid = floorGrid(AlignedPoints(points), local_origin, floor,
                                   Eigen::Vector2d(1, 1), 0.05, 0.05, 2.0, kCell);
  ASSERT_EQ(grid.width, 20);
  EXPECT_NEAR(grid.origin.x(), 0.0, 1e-9);
  EXPECT_NEAR(grid.origin.y(), 0.0, 1e-9);
  for (int cx = 0; cx < grid.width; ++cx) {
    EXPECT_EQ(grid.cells[5 * grid.width + cx], cx >= 18 ? FloorGrid::kOccupied : FloorGrid::kFree)
        << "column " << cx;
  }
}

TEST(FloorGrid, NoPointNearTheFloorGivesAnEmptyGridAndFarPointsAreCropped) {
  const std::vector<Eigen::Vector3f> sky = {{0, 0, 5}, {1, 1, 6}};
  EXPECT_EQ(floorGrid(AlignedPoints(sky), Eigen::Vector3d::Zero(), levelFloor(0), {0, 0}, 0.05,
                      0.05, 2.0, kCell)
                .width,
            0);
  // A point 200 m out at 0.1 m cells: beyond kFloorGridMaxCells / 2 cells of the centre.
  const std::vector<Eigen::Vector3f> far = {{0.05f, 0.05f, 0.f}, {200.f, 0.05f, 0.f}};
  const FloorGrid grid = floorGrid(AlignedPoints(far), Eigen::Vector3d::Zero(), levelFloor(0),
                                   {0, 0}, 0.05, 0.05, 2.0, kCell);
  EXPECT_EQ(grid.width, 1);
  EXPECT_EQ(grid.height, 1);
}

FloorGrid grid(double x0, double y0, int width, int height, std::vector<std::int8_t> cells) {
  FloorGrid g;
  g.resolution = kCell;
  g.origin = {x0, y0};
  g.width = width;
  g.height = height;
  g.cells = std::move(cells);
  return g;
}

TEST(FloorGrid, LaidOverEachOtherTheLatestLookWinsAndAThingLeavesAfterThreeFreeLooks) {
  const std::int8_t U = FloorGrid::kUnseen, F = FloorGrid::kFree, O = FloorGrid::kOccupied;
  FloorMap map;
  accumulate(map, grid(0.0, 0.0, 2, 1, {F, O}), {0, 0});
  EXPECT_EQ(map.grid.cells, (std::vector<std::int8_t>{F, O}));
  // Seen one cell to the right and one up: (0.1, 0) free once (still occupied: one look could
  // be a noisy edge), (0.2, 0) unseen, (0.1, 0.1) occupied, (0.2, 0.1) free; (0, 0.1) was
  // never seen.
  accumulate(map, grid(0.1, 0.0, 2, 2, {F, U, O, F}), {0, 0});
  ASSERT_EQ(map.grid.width, 3);
  ASSERT_EQ(map.grid.height, 2);
  EXPECT_NEAR(map.grid.origin.x(), 0.0, 1e-12);
  EXPECT_EQ(map.grid.cells, (std::vector<std::int8_t>{F, O, U, U, O, F}));
  accumulate(map, grid(0.1, 0.0, 1, 1, {F}), {0, 0});
  EXPECT_EQ(cellAt(map.grid, 0.15, 0.05), O) << "two free looks";
  accumulate(map, grid(0.1, 0.0, 1, 1, {F}), {0, 0});
  EXPECT_EQ(cellAt(map.grid, 0.15, 0.05), F) << "the third: the thing left";
  // An occupied look between free ones starts the count again.
  accumulate(map, grid(0.1, 0.1, 1, 1, {F}), {0, 0});
  accumulate(map, grid(0.1, 0.1, 1, 1, {O}), {0, 0});
  accumulate(map, grid(0.1, 0.1, 1, 1, {F}), {0, 0});
  accumulate(map, grid(0.1, 0.1, 1, 1, {F}), {0, 0});
  EXPECT_EQ(cellAt(map.grid, 0.15, 0.15), O);
  EXPECT_EQ(cellAt(map.grid, 0.05, 0.05), F) << "cells not seen keep theirs";
  // A frame far away: the map is cropped to kFloorGridMaxCells around the sensor there.
  accumulate(map, grid(80.0, 0.0, 1, 1, {O}), {80.0, 0.0});
  EXPECT_EQ(cellAt(map.grid, 80.05, 0.05), O);
  EXPECT_EQ(cellAt(map.grid, 0.05, 0.05), -2) << "80 m behind the sensor, 30 m outside its window";
  EXPECT_LE(map.grid.width, kFloorGridMaxCells + 1);
  EXPECT_EQ(map.free_looks.size(), map.grid.cells.size());
  // Another resolution starts afresh.
  FloorGrid coarse = grid(0.0, 0.0, 1, 1, {F});
  coarse.resolution = 0.2;
  accumulate(map, coarse, {0, 0});
  EXPECT_EQ(map.grid.cells, (std::vector<std::int8_t>{F}));
  EXPECT_EQ(map.grid.resolution, 0.2);
}

}  // namespace
}  // namespace hope
