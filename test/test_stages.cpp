// Each stage on its own, with hand-checkable inputs.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <map>
#include <random>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>

#include "helpers.h"
#include "hope/grid_filter.h"
#include "hope/horizontal_candidates.h"
#include "hope/normal_estimation.h"
#include "hope/pca_refinement.h"
#include "hope/plane_description.h"
#include "hope/scan_gap_bridging.h"
#include "hope/z_clustering.h"
#include "reference_grid.h"

namespace hope {
namespace test {

namespace {

std::vector<Eigen::Vector3f> points(std::initializer_list<Eigen::Vector3f> list) { return list; }

std::vector<Eigen::Vector3f> sheet(double x0, double y0, double x1, double y1, double z) {
  LabeledCloud c;
  addSheet(c, x0, y0, x1, y1, z, 0.01, 0);
  std::vector<Eigen::Vector3f> out;
  for (const auto& p : c.cloud) out.emplace_back(p.x, p.y, p.z);
  return out;
}

}  // namespace

TEST(GridFilter, GroupsPointsByAnisotropicVoxelAndRemembersEachPointsVoxel) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const auto pts = points({{0.01f, 0.01f, 0.001f},
                           {0.03f, 0.02f, 0.005f},  // same voxel (0.05 × 0.05 × 0.02)
                           {0.01f, 0.01f, 0.031f},  // one z cell up
                           {0.07f, 0.01f, 0.001f},  // next column in x
                           {nan, 0.f, 0.f}});
  VoxelGrid grid;
  grid.build(pts, 0.05, 0.02);
  ASSERT_EQ(grid.numVoxels(), 3u);
  const std::vector<std::int32_t> voxel_of = grid.pointVoxel();
  EXPECT_EQ(voxel_of[0], voxel_of[1]);
  EXPECT_NE(voxel_of[0], voxel_of[2]);
  EXPECT_NE(voxel_of[0], voxel_of[3]);
  EXPECT_EQ(voxel_of[4], -1);
  const auto v = static_cast<std::size_t>(voxel_of[0]);
  EXPECT_EQ(grid.numPointsIn(v), 2u);
  EXPECT_NEAR(grid.centroid(v).x(), 0.02f, 1e-6);
  EXPECT_NEAR(grid.centroid(v).z(), 0.003f, 1e-6);
  // Column (0, 0) holds two voxels ordered by z cell.
  const auto range = grid.columnVoxels(0, 0);
  ASSERT_EQ(range.second - range.first, 2u);
  EXPECT_LT(grid.cellZ(range.first), grid.cellZ(range.first + 1));
  EXPECT_EQ(grid.columnVoxels(-1, 0).second, grid.columnVoxels(-1, 0).first);
}

TEST(GridFilter, SparseWideCloudsTakeTheHashPathWithTheSameResult) {
  // Two clusters 3 km apart at 5 cm: 60 000 columns in x, far more cells than points.
  auto pts = sheet(0, 0, 0.3, 0.3, 0.0);
  auto far = sheet(3000, 0, 3000.3, 0.3, 0.0);
  pts.insert(pts.end(), far.begin(), far.end());
  VoxelGrid grid;
  grid.build(pts, 0.05, 0.02);
  VoxelGrid one_part;  // one sheet alone, on the dense path
  one_part.build(sheet(0, 0, 0.3, 0.3, 0.0), 0.05, 0.02);
  EXPECT_EQ(grid.numVoxels(), 2 * one_part.numVoxels());
  for (std::size_t v = 0; v < grid.numVoxels(); ++v) {
    const auto range = grid.columnVoxels(grid.cellX(v), grid.cellY(v));
    EXPECT_LE(range.first, v);
    EXPECT_GT(range.second, v);
  }
}

// A width x height "image" of a wavy surface with NaN holes, in row order, and the hints the
// alignment brings (the box and count of its finite points).
GridHints wavyImage(int width, int height, std::vector<Eigen::Vector3f>& image) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  GridHints hints;
  Eigen::AlignedBox3f box;
  for (int row = 0; row < height; ++row) {
    for (int col = 0; col < width; ++col) {
      if ((row * 7 + col * 3) % 23 == 0) {
        image.emplace_back(nan, nan, nan);
        continue;
      }
      const Eigen::Vector3f p(0.004f * col, 0.005f * row, 0.03f * std::sin(0.05f * (col + row)));
      image.push_back(p);
      box.extend(p);
      ++hints.finite_points;
    }
  }
  hints.finite_box = box;
  return hints;
}

TEST(GridFilter, EqualsThePlainReferenceOnShuffledNoisyAndSparseClouds) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> uniform(0.f, 1.f);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  // 60 000 points in a 3 x 3 x 1 m box in random order (tens of thousands of voxels: the hash
  // table grows several times), one in ten NaN.
  std::vector<Eigen::Vector3f> scattered;
  for (int i = 0; i < 60000; ++i) {
    if (i % 10 == 3) {
      scattered.emplace_back(nan, 0.f, 0.f);
    } else {
      scattered.emplace_back(3 * uniform(rng) - 1.5f, 3 * uniform(rng), uniform(rng) + 0.4f);
    }
  }
  // A scan-ordered sheet (neighbours share voxels) with a far cluster: the sparse column path.
  auto far_apart = sheet(0, 0, 0.6, 0.6, 0.1);
  const auto far = sheet(2500, 10, 2500.3, 10.3, 0.2);
  far_apart.insert(far_apart.end(), far.begin(), far.end());
  VoxelGrid grid;  // one grid for every cloud: buffers reused from a larger frame, too
  for (const auto* pts : {&scattered, &far_apart, &scattered}) {
    grid.build(*pts, 0.05, 0.02);
    expectSameAsReference(grid, *pts, 0.05, 0.02);
    grid.build(*pts, 0.3, 0.1);
    expectSameAsReference(grid, *pts, 0.3, 0.1);
  }
  // The hints the alignment brings (the box and count of the finite points) change nothing:
  // a 200 x 150 "image" of a wavy surface, with NaN holes, read with them.
  std::vector<Eigen::Vector3f> image;
  const GridHints hints = wavyImage(200, 150, image);
  grid.build(image, 0.009, 0.002, hints);
  expectSameAsReference(grid, image, 0.009, 0.002);
  grid.build(image, 0.05, 0.02, hints);
  expectSameAsReference(grid, image, 0.05, 0.02);
}

// With threads the point pass runs in shares on tables of their own, merged in share order,
// and the sums are taken per voxel owner: the result must still be the plain reference, bit
// for bit, for shares that split image rows and voxels' runs anywhere.
TEST(GridFilter, ThreadedPassEqualsThePlainReference) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> uniform(0.f, 1.f);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  // 300 000 scattered points (one in ten NaN) and a 640 x 480 wavy "image" with NaN holes.
  std::vector<Eigen::Vector3f> scattered;
  for (int i = 0; i < 300000; ++i) {
    if (i % 10 == 3) {
      scattered.emplace_back(nan, 0.f, 0.f);
    } else {
      scattered.emplace_back(4 * uniform(rng), 4 * uniform(rng), uniform(rng));
    }
  }
  std::vector<Eigen::Vector3f> image;
  const GridHints image_hints = wavyImage(640, 480, image);
  VoxelGrid grid;
  for (int threads : {2, 3}) {
    GridHints plain;
    plain.threads = threads;
    grid.build(scattered, 0.05, 0.02, plain);
    expectSameAsReference(grid, scattered, 0.05, 0.02);
    GridHints organized = image_hints;
    organized.threads = threads;
    grid.build(image, 0.009, 0.002, organized);
    expectSameAsReference(grid, image, 0.009, 0.002);
    grid.build(image, 0.05, 0.02, organized);
    expectSameAsReference(grid, image, 0.05, 0.02);
  }
  // The sparse column path over several chunks (a point 2.5 km away makes the grid too wide
  // for a dense column table): a voxel's entries from different chunks joined in chunk order.
  std::vector<Eigen::Vector3f> with_far_point = scattered;
  with_far_point.emplace_back(2500.f, 1.f, 0.5f);
  for (int threads : {1, 2}) {
    GridHints plain;
    plain.threads = threads;
    grid.build(with_far_point, 0.05, 0.02, plain);
    expectSameAsReference(grid, with_far_point, 0.05, 0.02);
  }
}

// The point pass joins a point to the current run when its unclamped cells are those of the
// point before, and tests finiteness only when they change. Two cases that shortcut could get
// wrong, each checked against the plain reference: points on the box's far side whose quotient
// lands exactly on the cell count (unclamped cell 187, clamped to 186, the cell of their
// neighbours: the cells change, the voxel does not), and single infinite coordinates (a z-up
// cloud is read in place, so infinities reach the grid) in the middle of runs.
TEST(GridFilter, FarSideOfTheBoxAndInfinitiesEqualThePlainReference) {
  // x spans [0, 1.5] and r_xy = 1.5 / 187: 1.5 / r_xy rounds below 187, so the grid has 187
  // columns, while 1.5 · (1 / r_xy), the point pass's product, is exactly 187.
  const double r_xy = 1.5 / 187;
  ASSERT_LT(std::floor(1.5 / r_xy) + 1, 188.0);
  ASSERT_EQ(static_cast<int>(1.5 * (1.0 / r_xy)), 187);
  const float inf = std::numeric_limits<float>::infinity();
  std::vector<Eigen::Vector3f> pts = {{0.f, 0.f, 0.f}};
  for (int i = 0; i < 40; ++i) {
    const float y = 0.001f * static_cast<float>(i % 4);
    // Alternating between unclamped cells 187 and 186 of one voxel, and on to the next row.
    pts.emplace_back(1.5f, y, 0.005f);
    pts.emplace_back(1.4995f, y, 0.005f);
    if (i % 5 == 2) pts.emplace_back(inf, y, 0.005f);
    if (i % 7 == 3) pts.emplace_back(1.5f, -inf, 0.005f);
    if (i % 9 == 4) pts.emplace_back(1.4995f, y, inf);
    pts.emplace_back(1.5f, y, 0.005f);
  }
  VoxelGrid grid;
  grid.build(pts, r_xy, 0.02);
  expectSameAsReference(grid, pts, r_xy, 0.02);
  // The far column holds the points of both unclamped cells: 40 · 3 per row of y cells.
  std::size_t in_last_column = 0;
  for (std::size_t v = 0; v < grid.numVoxels(); ++v) {
    if (grid.cellX(v) == 186) in_last_column += grid.numPointsIn(v);
  }
  EXPECT_EQ(in_last_column, 120u);
}

TEST(GridFilter, ACloudSpanningMoreCellsThanSupportedIsAClearError) {
  const auto pts = points({{0, 0, 0}, {1e6f, 0, 0}});
  VoxelGrid grid;
  grid.build(sheet(0, 0, 0.5, 0.5, 0.0), 0.05, 0.02);  // a grid before: its tables stay behind
  try {
    grid.build(pts, 0.05, 0.02);
    FAIL() << "accepted a 1000 km cloud at 5 cm";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("along x"), std::string::npos) << e.what();
  }
  // Left empty, not half the previous grid: no voxel, every point without one.
  EXPECT_EQ(grid.numVoxels(), 0u);
  const VoxelGrid::PointVoxels voxels = grid.pointVoxels();
  ASSERT_EQ(voxels.size(), pts.size());
  for (std::size_t i = 0; i < voxels.size(); ++i) EXPECT_EQ(voxels[i], -1);
}

// rowVoxels(cx0, cx1, cy) must be the columns' own ranges joined, for every row and every run
// of three columns, the grid's borders and beyond included: on a sheet with holes beside a
// tall pillar (a column of 60 voxels). A sparse grid has no rows.
TEST(GridFilter, RowVoxelsAreTheRowsColumnsJoined) {
  std::vector<Eigen::Vector3f> pts;
  for (const Eigen::Vector3f& p : sheet(0, 0, 0.5, 0.4, 0.0)) {
    if (std::fmod(p.x() * p.y() * 977.0f, 1.0f) < 0.3f) pts.push_back(p);  // random holes
  }
  for (int k = 0; k < 240; ++k) pts.emplace_back(0.53f, 0.21f, 0.005f * k);
  VoxelGrid grid;
  grid.build(pts, 0.05, 0.02);
  ASSERT_TRUE(grid.denseColumns());
  int max_x = 0, max_y = 0;
  for (std::size_t v = 0; v < grid.numVoxels(); ++v) {
    max_x = std::max(max_x, grid.cellX(v));
    max_y = std::max(max_y, grid.cellY(v));
  }
  std::size_t non_empty = 0;
  for (int cy = -2; cy <= max_y + 2; ++cy) {
    for (int cx = -2; cx <= max_x + 2; ++cx) {
      std::uint32_t first = 0, end = 0, total = 0;
      for (int dx = -1; dx <= 1; ++dx) {
        const auto column = grid.columnVoxels(cx + dx, cy);
        if (column.first == column.second) continue;
        if (total == 0) first = column.first;
        EXPECT_EQ(column.first, total == 0 ? first : end) << cx << ", " << cy;  // contiguous
        end = column.second;
        total += column.second - column.first;
      }
      const auto row = grid.rowVoxels(cx - 1, cx + 1, cy);
      EXPECT_EQ(row.second - row.first, total) << cx << ", " << cy;
      if (total > 0) {
        EXPECT_EQ(row.first, first) << cx << ", " << cy;
        EXPECT_EQ(row.second, end) << cx << ", " << cy;
        ++non_empty;
      }
    }
  }
  EXPECT_GT(non_empty, 50u);
  pts.emplace_back(3000.f, 3000.f, 0.f);  // 3 km away at 5 cm: the sparse column table
  grid.build(pts, 0.05, 0.02);
  ASSERT_FALSE(grid.denseColumns());
  const auto row = grid.rowVoxels(0, 2, 0);
  EXPECT_EQ(row.first, row.second);
}

TEST(Normals, FlatSheetGivesVerticalNormalsAndSlopesGiveTheirTilt) {
  VoxelGrid grid;
  grid.build(sheet(0, 0, 1, 1, 0.3), 0.05, 0.02);
  std::vector<Eigen::Vector3f> normals;
  estimateNormals(grid, 1.01, normals);
  for (const auto& n : normals) {
    ASSERT_TRUE(n.allFinite());
    EXPECT_NEAR(n.z(), 1.0f, 1e-5);
  }
  // 0.3 rad slope about y.
  std::vector<Eigen::Vector3f> slope;
  for (const auto& p : sheet(0, 0, 1, 1, 0))
    slope.emplace_back(p.x(), p.y(), std::tan(0.3f) * p.x());
  grid.build(slope, 0.05, 0.02);
  estimateNormals(grid, 1.01, normals);
  int finite = 0;
  for (const auto& n : normals) {
    if (!n.allFinite()) continue;
    ++finite;
    EXPECT_NEAR(std::acos(n.z()), 0.3, 0.02);
  }
  EXPECT_GT(finite, static_cast<int>(normals.size() * 9 / 10));
}

// estimateNormals works column by column (columnMoments); moments() is the plain per-voxel
// definition. They must agree bit for bit, on short columns and on tall ones (a wall, more
// voxels than VoxelGrid::kShortColumn), for the paper's 4-neighbours and wider radii.
TEST(Normals, ColumnByColumnEqualsVoxelByVoxel) {
  std::mt19937 rng(7);
  std::normal_distribution<float> noise(0.f, 0.004f);
  std::vector<Eigen::Vector3f> pts;
  for (int i = 0; i < 40; ++i) {
    for (int j = 0; j < 40; ++j) {
      const float x = 0.013f * i, y = 0.013f * j;
      pts.emplace_back(x, y, noise(rng));                                                   // floor
      if (i > 10 && i < 30 && j > 5 && j < 25) pts.emplace_back(x, y, 0.72f + noise(rng));  // table
      pts.emplace_back(x, y, 0.05f + 0.25f * x + noise(rng));                               // ramp
    }
  }
  for (int k = 0; k < 120; ++k) {  // a wall: tall columns
    for (int j = 0; j < 40; ++j) pts.emplace_back(0.6f + noise(rng), 0.013f * j, 0.012f * k);
  }
  VoxelGrid grid;
  grid.build(pts, 0.05, 0.02);
  std::size_t tall_columns = 0;
  for (std::size_t v = 0; v < grid.numVoxels();) {
    const auto column = grid.columnVoxels(grid.cellX(v), grid.cellY(v));
    tall_columns += column.second - column.first > VoxelGrid::kShortColumn ? 1 : 0;
    v = column.second;
  }
  ASSERT_GT(tall_columns, 5u);
  for (const double radius_factor : {1.01, 1.5, 2.5}) {
    const NormalNeighbourhood neighbourhood(grid, radius_factor);
    std::vector<NormalNeighbourhood::Moments> column_moments;
    std::vector<std::pair<std::uint32_t, std::uint32_t>> windows;
    std::size_t compared = 0, partial = 0;
    for (std::size_t v = 0; v < grid.numVoxels();) {
      const auto column = grid.columnVoxels(grid.cellX(v), grid.cellY(v));
      column_moments.assign(column.second - column.first, {});
      neighbourhood.columnMoments(column.first, column.second, column_moments.data(), windows);
      for (std::uint32_t u = column.first; u < column.second; ++u) {
        const NormalNeighbourhood::Moments expected = neighbourhood.moments(u);
        const NormalNeighbourhood::Moments& got = column_moments[u - column.first];
        ASSERT_EQ(got.count, expected.count) << "voxel " << u << ", radius " << radius_factor;
        for (int i = 0; i < 3; ++i) ASSERT_EQ(got.sum(i), expected.sum(i)) << "voxel " << u;
        for (int i = 0; i < 9; ++i) ASSERT_EQ(got.outer(i), expected.outer(i)) << "voxel " << u;
        ++compared;
        // A wall voxel sees only part of its column: the window must slide, not stay put.
        if (column.second - column.first > VoxelGrid::kShortColumn && expected.count > 0) ++partial;
      }
      v = column.second;
    }
    EXPECT_EQ(compared, grid.numVoxels());
    EXPECT_GT(partial, 100u);
    // The normals estimateNormals writes are those of each voxel's own moments.
    std::vector<Eigen::Vector3f> normals;
    estimateNormals(grid, radius_factor, normals);
    std::size_t with_normal = 0;
    for (std::size_t v = 0; v < grid.numVoxels(); ++v) {
      const NormalNeighbourhood::Moments m = neighbourhood.moments(v);
      Eigen::Vector3f n;
      if (m.count < 3 || !planeNormal(m.covariance(), n)) {
        EXPECT_FALSE(normals[v].allFinite()) << "voxel " << v;
        continue;
      }
      n.normalize();
      if (n.z() < 0) n = -n;
      ASSERT_EQ(normals[v], n) << "voxel " << v << ", radius " << radius_factor;
      ++with_normal;
    }
    EXPECT_GT(with_normal, grid.numVoxels() / 2);
  }
}

// Newton's method on two voxels at once gives each the smallest root it gets alone, bit for
// bit: pairs that stop after different numbers of steps, flat and round neighbourhoods, a
// singular one (c0 <= 0, no step at all).
TEST(Normals, NewtonStepsOnTwoVoxelsAtOnceGiveEachItsOwnRoot) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  struct Known {
    detail::CharacteristicCubic cubic;
    double lambda0;  // the smallest eigenvalue it was made from
  };
  auto cubicOf = [](double l0, double l1, double l2) {
    detail::CharacteristicCubic c{};
    c.c2 = l0 + l1 + l2;
    c.c1 = l0 * l1 + l0 * l2 + l1 * l2;
    c.c0 = l0 * l1 * l2;
    return Known{c, std::max(l0, 0.0)};
  };
  std::vector<Known> cubics = {cubicOf(0, 0.5, 1), cubicOf(-1e-18, 0.3, 1), cubicOf(0.3, 0.31, 1)};
  for (int i = 0; i < 2000; ++i) {
    const double l1 = 0.05 + 0.95 * unit(rng);
    cubics.push_back(cubicOf(std::pow(10.0, -12 * unit(rng)) * l1, l1, 1.0));
  }
  std::size_t steps_differ = 0;
  for (std::size_t i = 0; i < cubics.size(); ++i) {
    const Known& a = cubics[i];
    const Known& b = cubics[(i * 7919 + 13) % cubics.size()];
    double root_a = -1, root_b = -1;
    detail::smallestRoots(a.cubic, b.cubic, root_a, root_b);
    const double alone_a = detail::smallestRoot(a.cubic), alone_b = detail::smallestRoot(b.cubic);
    ASSERT_EQ(std::memcmp(&root_a, &alone_a, sizeof(double)), 0) << i << ": " << root_a;
    ASSERT_EQ(std::memcmp(&root_b, &alone_b, sizeof(double)), 0) << i << ": " << root_b;
    // Steps below 1e-12·c2 are not taken: λ0 is known to that, absolutely.
    ASSERT_NEAR(alone_a, a.lambda0, 2e-12 * a.cubic.c2 + 1e-9 * a.lambda0) << i;
    // Flat against round: one lane stops steps before the other.
    if (std::fabs(std::log10(a.lambda0 + 1e-30) - std::log10(b.lambda0 + 1e-30)) > 3) {
      ++steps_differ;
    }
  }
  EXPECT_GT(steps_differ, 500u);  // many pairs of a flat and a rounder neighbourhood
}

TEST(Normals, IsolatedVoxelsAndLinesHaveNoNormal) {
  VoxelGrid grid;
  std::vector<Eigen::Vector3f> line;
  for (int i = 0; i < 20; ++i) line.emplace_back(0.05f * i + 0.02f, 0.02f, 0.0f);
  line.emplace_back(5.0f, 5.0f, 0.0f);
  grid.build(line, 0.05, 0.02);
  std::vector<Eigen::Vector3f> normals;
  estimateNormals(grid, 1.01, normals);
  for (const auto& n : normals) EXPECT_FALSE(n.allFinite());
}

namespace {

// The covariance of `points` as estimateNormals forms it: moments relative to the first point,
// in float.
Eigen::Matrix3f covarianceOf(const std::vector<Eigen::Vector3f>& points) {
  Eigen::Vector3f sum = Eigen::Vector3f::Zero();
  Eigen::Matrix3f outer = Eigen::Matrix3f::Zero();
  for (const Eigen::Vector3f& p : points) {
    const Eigen::Vector3f d = p - points.front();
    sum += d;
    outer += d * d.transpose();
  }
  const Eigen::Vector3f mean = sum / static_cast<float>(points.size());
  return outer / static_cast<float>(points.size()) - mean * mean.transpose();
}

}  // namespace

TEST(Normals, ClosedFormSolverAgreesWithAnIterativeSolverInDouble) {
  // Point sets of every shape a neighbourhood takes (flat patches, lines, blobs, slabs between),
  // rotated at random and far from the origin; the reference is Eigen's iterative (QR) solver
  // on the same covariance in double.
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> unit(-1.0, 1.0), exponent(-4.0, 0.0);
  int compared_normals = 0, planar = 0, not_planar = 0;
  for (int trial = 0; trial < 20000; ++trial) {
    const Eigen::Vector3d spread(std::pow(10.0, exponent(rng)), std::pow(10.0, exponent(rng)),
                                 std::pow(10.0, exponent(rng)));
    const Eigen::Matrix3d rotation =
        Eigen::Quaterniond(Eigen::Vector4d(unit(rng), unit(rng), unit(rng), unit(rng)).normalized())
            .toRotationMatrix();
    const Eigen::Vector3d offset(100 * unit(rng), 100 * unit(rng), 10 * unit(rng));
    std::vector<Eigen::Vector3f> pts;
    const int count = 3 + trial % 25;
    for (int k = 0; k < count; ++k) {
      const Eigen::Vector3d local(spread.x() * unit(rng), spread.y() * unit(rng),
                                  spread.z() * unit(rng));
      pts.push_back((rotation * local + offset).cast<float>());
    }
    const Eigen::Matrix3f covariance = covarianceOf(pts);
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> reference(covariance.cast<double>());
    const Eigen::Vector3d eigenvalues = reference.eigenvalues();  // ascending
    const double share = eigenvalues(1) / eigenvalues(2);
    Eigen::Vector3f normal;
    const bool found = planeNormal(covariance, normal);
    if (std::fabs(share - 0.05) < 1e-3) continue;  // at the planarity limit either verdict holds
    ASSERT_EQ(found, share > 0.05)
        << "trial " << trial << ", eigenvalues " << eigenvalues.transpose();
    (found ? planar : not_planar) += 1;
    // The normal is well defined where the smallest eigenvalue stands apart from the middle one.
    if (!found || eigenvalues(0) > 0.5 * eigenvalues(1)) continue;
    ASSERT_NEAR(normal.norm(), 1.0f, 1e-5f);
    const double angle = std::acos(
        std::min(1.0, std::fabs(normal.cast<double>().dot(reference.eigenvectors().col(0)))));
    EXPECT_LT(angle, 1e-3) << "trial " << trial << ", eigenvalues " << eigenvalues.transpose();
    ++compared_normals;
  }
  EXPECT_GT(compared_normals, 2000);
  EXPECT_GT(planar, 3000);
  EXPECT_GT(not_planar, 3000);
}

TEST(Normals, ClosedFormSolverOnExactAndDegenerateNeighbourhoods) {
  Eigen::Vector3f normal;
  // Exactly flat, tilted: the covariance is singular (c0 is 0 or rounds below it).
  const Eigen::Vector3d n = Eigen::Vector3d(0.2, -0.1, 1.0).normalized();
  const Eigen::Vector3d u = n.unitOrthogonal(), w = n.cross(u);
  std::vector<Eigen::Vector3f> flat;
  for (int i = 0; i < 5; ++i) {
    for (int j = 0; j < 5; ++j) flat.push_back((0.05 * i * u + 0.05 * j * w).cast<float>());
  }
  ASSERT_TRUE(planeNormal(covarianceOf(flat), normal));
  EXPECT_NEAR(std::fabs(normal.cast<double>().dot(n)), 1.0, 1e-6);
  // On a line, at one point, all zero or NaN: no plane.
  std::vector<Eigen::Vector3f> line;
  for (int i = 0; i < 6; ++i) line.push_back((0.05 * i * u).cast<float>());
  EXPECT_FALSE(planeNormal(covarianceOf(line), normal));
  EXPECT_FALSE(planeNormal(
      covarianceOf({Eigen::Vector3f(1, 2, 3), Eigen::Vector3f(1, 2, 3), Eigen::Vector3f(1, 2, 3)}),
      normal));
  EXPECT_FALSE(planeNormal(Eigen::Matrix3f::Zero(), normal));
  Eigen::Matrix3f nan = Eigen::Matrix3f::Identity();
  nan(1, 1) = std::numeric_limits<float>::quiet_NaN();
  EXPECT_FALSE(planeNormal(nan, normal));
  // A round blob: every direction is a least-variance one; any unit vector will do.
  ASSERT_TRUE(planeNormal(Eigen::Matrix3f::Identity(), normal));
  EXPECT_NEAR(normal.norm(), 1.0f, 1e-5f);
}

namespace {

// Rings of a LiDAR at the origin: arcs of radius r (every 2 cm along the arc, ±0.5 rad of
// azimuth) at height z(r).
template <class Height>
std::vector<Eigen::Vector3f> rings(std::initializer_list<double> radii, Height z) {
  std::vector<Eigen::Vector3f> out;
  for (double r : radii) {
    for (double a = -0.5; a <= 0.5; a += 0.02 / r) {
      out.emplace_back(static_cast<float>(r * std::cos(a)), static_cast<float>(r * std::sin(a)),
                       static_cast<float>(z(r)));
    }
  }
  return out;
}

struct Bridged {
  VoxelGrid grid;
  std::vector<Eigen::Vector3f> normals;
  std::vector<VoxelLink> links;
  std::size_t count = 0;
};

Bridged bridge(const std::vector<Eigen::Vector3f>& pts, const Params& params) {
  Bridged b;
  b.grid.build(pts, params.r_xy, params.r_z);
  estimateNormals(b.grid, params.normal_radius_factor, b.normals);
  b.count = bridgeScanGaps(b.grid, Eigen::Vector3d::Zero(), params, b.normals, b.links);
  return b;
}

}  // namespace

TEST(ScanGapBridging, RingsOfTheGroundBecomeOneLevelCluster) {
  Params params;
  params.r_xy = 0.1;
  params.r_z = 0.05;
  // Three ground rings 0.6 m apart (6 cells): each ring alone is a line without a normal.
  const Bridged b = bridge(rings({5.0, 5.6, 6.2}, [](double) { return -1.5; }), params);
  std::vector<Eigen::Vector3f> plain;
  estimateNormals(b.grid, params.normal_radius_factor, plain);
  std::size_t plain_finite = 0, bridged_level = 0;
  for (std::size_t v = 0; v < b.grid.numVoxels(); ++v) {
    plain_finite += plain[v].allFinite() ? 1 : 0;
    bridged_level += b.normals[v].allFinite() && b.normals[v].z() > 0.99f ? 1 : 0;
  }
  EXPECT_EQ(plain_finite, 0u);
  EXPECT_EQ(b.count, b.grid.numVoxels());
  EXPECT_EQ(bridged_level, b.grid.numVoxels());
  std::vector<std::uint8_t> candidates;
  selectHorizontalCandidates(b.normals, params.gamma(), candidates);
  EXPECT_EQ(zClustering(b.grid, candidates, params.r_z, 3).size(), 3u);  // without the links
  const auto clusters = zClustering(b.grid, candidates, params.r_z, 3, b.links);
  ASSERT_EQ(clusters.size(), 1u);
  EXPECT_EQ(clusters[0].size(), b.grid.numVoxels());
}

TEST(ScanGapBridging, AStepAboveRzASlopeAndAWallAreNotBridged) {
  Params params;
  params.r_xy = 0.1;
  params.r_z = 0.05;
  // A kerb: the outer ring 6 cm up (above r_z), with ground seen beyond neither.
  const Bridged kerb =
      bridge(rings({5.0, 5.6}, [](double r) { return r > 5.3 ? -1.44 : -1.5; }), params);
  EXPECT_TRUE(kerb.links.empty());
  // A plane sloping 40° across the rays (rising along y): each ring is a line climbing at 40°
  // and its next ring along the ray lies level with it, so the link is found, but the plane
  // through line and link is as steep as the slope, beyond Eq 3's atan(√2·γ) = 35.3°: no
  // horizontal candidate, no link kept.
  std::vector<Eigen::Vector3f> slope;
  for (double r : {5.0, 5.6}) {
    for (double a = -0.3; a <= 0.3; a += 0.02 / r) {
      const double x = r * std::cos(a), y = r * std::sin(a);
      slope.emplace_back(static_cast<float>(x), static_cast<float>(y),
                         static_cast<float>(-1.5 + std::tan(40.0 * M_PI / 180.0) * y));
    }
  }
  const Bridged sloped = bridge(slope, params);
  EXPECT_GT(sloped.count, 20u);  // the bridging did give normals
  std::vector<std::uint8_t> slope_candidates;
  EXPECT_EQ(selectHorizontalCandidates(sloped.normals, params.gamma(), slope_candidates), 0u);
  EXPECT_TRUE(sloped.links.empty());
  // A wall: rings one above the other at the same range, a column going on above and below.
  std::vector<Eigen::Vector3f> wall;
  for (double z : {-0.2, -0.1, 0.0, 0.1, 0.2}) {
    for (const Eigen::Vector3f& p : rings({8.0}, [z](double) { return z; })) wall.push_back(p);
  }
  const Bridged w = bridge(wall, params);
  std::vector<std::uint8_t> candidates;
  EXPECT_EQ(selectHorizontalCandidates(w.normals, params.gamma(), candidates), 0u);
}

TEST(HorizontalCandidates, Eq3BoundIsOneOverSqrtOnePlusTwoGammaSquared) {
  const double gamma = 0.4;
  const double bound = candidateNormalZBound(gamma);
  EXPECT_NEAR(bound, 1.0 / std::sqrt(1.32), 1e-12);
  const double just_in = std::acos(bound) - 0.01, just_out = std::acos(bound) + 0.01;
  const float nan = std::numeric_limits<float>::quiet_NaN();
  std::vector<Eigen::Vector3f> normals = {
      {0, 0, 1},
      {static_cast<float>(std::sin(just_in)), 0, static_cast<float>(std::cos(just_in))},
      {static_cast<float>(std::sin(just_out)), 0, static_cast<float>(std::cos(just_out))},
      {0, 0, -1},  // opposite orientation still counts (|n_z|)
      {nan, nan, nan}};
  std::vector<std::uint8_t> mask;
  EXPECT_EQ(selectHorizontalCandidates(normals, gamma, mask), 3u);
  EXPECT_EQ(mask, (std::vector<std::uint8_t>{1, 1, 0, 1, 0}));
}

TEST(ZClustering, JoinsAcrossColumnsOnlyBelowRzAndDropsTinyClusters) {
  auto pts = sheet(0, 0, 0.5, 0.5, 0.0);
  const auto step = sheet(0.51, 0, 1.0, 0.5, 0.025);  // 2.5 cm > r_z = 2 cm above
  pts.insert(pts.end(), step.begin(), step.end());
  pts.emplace_back(3.0f, 3.0f, 0.0f);  // a lone voxel
  VoxelGrid grid;
  grid.build(pts, 0.05, 0.02);
  std::vector<std::uint8_t> all(grid.numVoxels(), 1);
  const auto clusters = zClustering(grid, all, 0.02, 3);
  ASSERT_EQ(clusters.size(), 2u);
  EXPECT_EQ(clusters[0].size() + clusters[1].size(), grid.numVoxels() - 1);
  // With r_z = 3 cm the step is joined.
  EXPECT_EQ(zClustering(grid, all, 0.03, 3).size(), 1u);
}

// Z clustering reads short rows of columns as one range and tall ones column by column; a grid
// with a sparse column table reads every column alone. A floor with a pillar of 60 voxels
// beside it, and the same plus one point 3 km away (last in voxel order, so every other voxel
// keeps its number): the clusters must be the same, voxel for voxel, and the floor one.
TEST(ZClustering, RowAndColumnReadsGiveTheSameClusters) {
  std::vector<Eigen::Vector3f> pts = sheet(0, 0, 0.5, 0.5, 0.0);
  for (int k = 0; k < 240; ++k) pts.emplace_back(0.53f, 0.21f, 0.005f * k);
  VoxelGrid dense, sparse;
  dense.build(pts, 0.05, 0.02);
  pts.emplace_back(3000.f, 3000.f, 0.f);
  sparse.build(pts, 0.05, 0.02);
  ASSERT_TRUE(dense.denseColumns());
  ASSERT_FALSE(sparse.denseColumns());
  ASSERT_EQ(sparse.numVoxels(), dense.numVoxels() + 1);
  std::vector<std::uint8_t> all(dense.numVoxels(), 1);
  const auto by_rows = zClustering(dense, all, 0.02, 3);
  all.push_back(0);  // the far voxel
  const auto by_columns = zClustering(sparse, all, 0.02, 3);
  EXPECT_EQ(by_rows, by_columns);
  ASSERT_FALSE(by_rows.empty());
  // The floor: every voxel of z cell 0 in the first cluster.
  std::size_t floor_voxels = 0;
  for (std::uint32_t v = 0; v < dense.numVoxels(); ++v) {
    if (dense.cellZ(v) != 0) continue;
    ++floor_voxels;
    EXPECT_NE(std::find(by_rows[0].begin(), by_rows[0].end(), v), by_rows[0].end()) << v;
  }
  EXPECT_GE(floor_voxels, 100u);
}

TEST(PcaRefinement, FlatNormalsPassCurvedAndSlopedOnesFail) {
  const double gamma = 0.4;
  std::vector<std::uint32_t> members;
  std::vector<Eigen::Vector3f> normals;
  auto reset = [&] {
    members.clear();
    normals.clear();
  };
  auto add = [&](double tilt, double azimuth) {
    normals.emplace_back(std::sin(tilt) * std::cos(azimuth), std::sin(tilt) * std::sin(azimuth),
                         std::cos(tilt));
    members.push_back(static_cast<std::uint32_t>(normals.size() - 1));
  };
  // Flat with noise: small tilts in every direction.
  for (int i = 0; i < 40; ++i) add(0.03 * ((i * 7) % 5) / 4.0, i * 2.4);
  EXPECT_TRUE(refineWithPCA(normals, members, gamma).horizontal);
  // A uniform slope just above atan γ: Eq 10's first test.
  reset();
  for (int i = 0; i < 40; ++i) add(std::atan(gamma) + 0.02, 0.0);
  RefinementVerdict slope = refineWithPCA(normals, members, gamma);
  EXPECT_FALSE(slope.horizontal);
  EXPECT_GT(slope.mean_tilt, std::atan(gamma));
  // A ridge (tube top): normals tilt ±0.45 rad across one axis; mean vertical, groups apart.
  reset();
  for (int i = -20; i <= 20; ++i) add(std::fabs(i) * 0.45 / 20, i < 0 ? M_PI : 0.0);
  RefinementVerdict ridge = refineWithPCA(normals, members, gamma);
  EXPECT_LT(ridge.mean_tilt, 0.01);
  EXPECT_FALSE(ridge.horizontal);
  // Too few normals.
  reset();
  add(0, 0);
  add(0, 0);
  EXPECT_FALSE(refineWithPCA(normals, members, gamma).horizontal);
}

TEST(PlaneDescription, ConvexHullIsCounterClockwiseAndDropsInteriorPoints) {
  const auto hull = convexHull2D({{0, 0}, {1, 0}, {1, 1}, {0, 1}, {0.5, 0.5}, {0.2, 0.7}, {1, 0}});
  ASSERT_EQ(hull.size(), 4u);
  double twice_area = 0;
  for (std::size_t i = 0; i < hull.size(); ++i) {
    const auto& a = hull[i];
    const auto& b = hull[(i + 1) % hull.size()];
    twice_area += a.x() * b.y() - b.x() * a.y();
  }
  EXPECT_NEAR(twice_area, 2.0, 1e-12);  // positive: counter-clockwise
}

// The hull drops the points strictly inside the octagon of the extreme points before its sort;
// the hull must be the one a plain monotone chain over every point gives, vertex for vertex:
// on a disc, a square with points on a coarse lattice (duplicates, collinear rims), a thin
// diagonal strip and a ring.
TEST(PlaneDescription, ConvexHullEqualsAPlainMonotoneChainOverEveryPoint) {
  auto plain = [](std::vector<Eigen::Vector2d> p) {
    std::sort(p.begin(), p.end(), [](const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
      return a.x() < b.x() || (a.x() == b.x() && a.y() < b.y());
    });
    p.erase(std::unique(p.begin(), p.end()), p.end());
    auto turn = [](const Eigen::Vector2d& o, const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
      return (a.x() - o.x()) * (b.y() - o.y()) - (a.y() - o.y()) * (b.x() - o.x());
    };
    std::vector<Eigen::Vector2d> lower, upper;
    for (const auto& q : p) {
      while (lower.size() >= 2 && turn(lower[lower.size() - 2], lower.back(), q) <= 0)
        lower.pop_back();
      lower.push_back(q);
    }
    for (auto it = p.rbegin(); it != p.rend(); ++it) {
      while (upper.size() >= 2 && turn(upper[upper.size() - 2], upper.back(), *it) <= 0)
        upper.pop_back();
      upper.push_back(*it);
    }
    lower.pop_back();
    upper.pop_back();
    lower.insert(lower.end(), upper.begin(), upper.end());
    return lower;
  };
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  // Shapes: a disk (0), a grid with whole rows and columns on the rim (1), a thin diagonal
  // strip (2), a ring (3), a filled rectangle (4, whose corners are the octagon's: the
  // octagon's inner box must shrink), and a 2 x 1 mm rectangle 500 km out (5, UTM-scale
  // coordinates: the edge tests round at 1e-10 m).
  for (int shape = 0; shape < 6; ++shape) {
    for (std::size_t n : {70u, 500u, 20000u}) {
      std::vector<Eigen::Vector2d> pts;
      while (pts.size() < n) {
        double x = uniform(rng), y = uniform(rng);
        const double r = std::hypot(x, y);
        if (shape == 0 && r > 1.0) continue;
        if (shape == 1) x = std::round(x * 8) / 8, y = std::round(y * 8) / 8;
        if (shape == 2) y = x + 0.01 * y;
        if (shape == 3 && (r < 0.9 || r > 1.0)) continue;
        if (shape == 4) x *= 2;
        if (shape == 5) x = 500000.0 + 0.001 * x, y = -4000000.0 + 0.0005 * y;
        pts.emplace_back(x, y);
      }
      const std::vector<Eigen::Vector2d> expected = plain(pts);
      const std::vector<Eigen::Vector2d> hull = convexHull2D(pts);
      ASSERT_GE(expected.size(), 3u);
      ASSERT_EQ(hull.size(), expected.size()) << "shape " << shape << ", " << n << " points";
      for (std::size_t k = 0; k < expected.size(); ++k) {
        EXPECT_EQ(hull[k], expected[k])
            << "shape " << shape << ", " << n << " points, vertex " << k;
      }
    }
  }
}

// The description's hull knows each point's grid cell and drops whole cells inside the polygon
// of the points extreme in 32 directions. Its hull must be convexHull2D's, vertex for vertex:
// on a disc of cells, a ring (a hole in the middle), one row of cells, points on a coarse
// lattice (duplicates, collinear rims, points on cell borders), a plane 500 km out (UTM-scale
// coordinates), and cells whose points fill only a corner (the extreme points far inside the
// cells). Each cell's inner point is its points' mean rounded to float, as the description
// gives. With 40 points a cell the shortcut must leave the sort under a quarter of the points
// (at 500 km the rounding allowance is metres and it drops nothing, rightly).
TEST(PlaneDescription, CellHullEqualsTheHullOfEveryPoint) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const double side = 0.05;
  for (int shape = 0; shape < 6; ++shape) {
    for (int points_per_cell : {1, 3, 40}) {
      const Eigen::Vector2d offset =
          shape == 4 ? Eigen::Vector2d(500000.0, -4000000.0) : Eigen::Vector2d(-1.3, 0.7);
      CellPoints cells;
      cells.side = side;
      for (int iy = -20; iy <= 20; ++iy) {
        for (int ix = -20; ix <= 20; ++ix) {
          const double r = std::hypot(ix, iy);
          if (shape != 2 && r > 20) continue;
          if (shape == 1 && r < 14) continue;
          if (shape == 2 && iy != 0) continue;
          const Eigen::Vector2d corner = offset + side * Eigen::Vector2d(ix, iy);
          const auto cell = static_cast<std::uint32_t>(cells.cell_min.size());
          Eigen::Vector2d sum = Eigen::Vector2d::Zero();
          for (int k = 0; k < points_per_cell; ++k) {
            Eigen::Vector2d u(unit(rng), unit(rng));
            if (shape == 3) u = (u * 4).array().round() / 4;  // 0, ¼, ½, ¾, 1 of the cell
            if (shape == 5) u *= 0.2;
            cells.points.push_back(corner + side * u);
            cells.cell_of_point.push_back(cell);
            sum += cells.points.back();
          }
          cells.cell_min.push_back(corner);
          cells.cell_inner.push_back((sum / points_per_cell).cast<float>().cast<double>());
        }
      }
      const std::size_t n = cells.points.size();
      const std::vector<Eigen::Vector2d> expected = convexHull2D(cells.points);
      std::size_t sorted = 0;
      const std::vector<Eigen::Vector2d> hull = convexHullOfCellPoints(cells, &sorted);
      ASSERT_GE(expected.size(), 3u);
      ASSERT_EQ(hull.size(), expected.size()) << "shape " << shape << ", " << points_per_cell;
      for (std::size_t k = 0; k < expected.size(); ++k) {
        EXPECT_EQ(hull[k], expected[k]) << "shape " << shape << ", vertex " << k;
      }
      if (points_per_cell == 40 && shape != 4) {
        EXPECT_LT(4 * sorted, n) << "shape " << shape << ": " << sorted << " of " << n;
      }
    }
  }
}

// The description skips voxels the plane surrounds on all four diagonal sides when it looks
// for hull vertices and bbox extremes; the hull and bbox must be those of every point.
TEST(PlaneDescription, HullAndBboxEqualThoseOfEveryPoint) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  for (int shape = 0; shape < 3; ++shape) {
    // Random points of an annulus (shape 0), a thin cross (1) and a scatter of rings (2).
    std::vector<Eigen::Vector3f> pts;
    while (pts.size() < 20000) {
      const double x = 3 * uniform(rng), y = 3 * uniform(rng), r = std::hypot(x, y);
      const bool keep = shape == 0   ? (r > 1.0 && r < 2.8)
                        : shape == 1 ? (std::fabs(x) < 0.2 || std::fabs(y) < 0.15)
                                     : std::fabs(std::fmod(r, 0.7) - 0.35) < 0.03;
      if (keep) pts.emplace_back(static_cast<float>(x), static_cast<float>(y), 0.0f);
    }
    VoxelGrid grid;
    grid.build(pts, 0.1, 0.05);
    std::vector<std::uint32_t> all(grid.numVoxels());
    for (std::uint32_t v = 0; v < all.size(); ++v) all[v] = v;
    const HorizontalPlane plane = describePlane(grid, pts, all);
    std::vector<Eigen::Vector2d> flat;
    Eigen::Vector2d lo(HUGE_VAL, HUGE_VAL), hi(-HUGE_VAL, -HUGE_VAL);
    for (const Eigen::Vector3f& p : pts) {
      flat.emplace_back(p.x(), p.y());
      lo = lo.cwiseMin(flat.back());
      hi = hi.cwiseMax(flat.back());
    }
    const std::vector<Eigen::Vector2d> expected = convexHull2D(flat);
    ASSERT_EQ(plane.hull.size(), expected.size()) << "shape " << shape;
    for (std::size_t k = 0; k < expected.size(); ++k) {
      EXPECT_EQ(plane.hull[k].x(), expected[k].x()) << "shape " << shape << " vertex " << k;
      EXPECT_EQ(plane.hull[k].y(), expected[k].y()) << "shape " << shape << " vertex " << k;
    }
    EXPECT_EQ(plane.bbox[0], lo.x());
    EXPECT_EQ(plane.bbox[1], lo.y());
    EXPECT_EQ(plane.bbox[2], hi.x());
    EXPECT_EQ(plane.bbox[3], hi.y());
    EXPECT_EQ(plane.num_points, pts.size());
  }
}

}  // namespace test
}  // namespace hope
