// The fit behind up from the scene (up_estimation.h), step 3 of its file comment: the cells of a
// cubic grid whose normals lie within a tolerance of a direction are joined into connected
// patches at one height, and the direction becomes the one that makes all patches flattest at
// once; repeated with a narrowing tolerance. Private to the core library.
#pragma once

#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "hope/grid_filter.h"

namespace hope {
namespace detail {

class LevelFit {
 public:
  struct Result {
    bool supported = false;  // false: no patch to fit
    Eigen::Vector3d up = Eigen::Vector3d::UnitZ();
    double support_area = 0;      // m², the patches' footprint at cell size
    double angle_spread_deg = 0;  // RMS angle of their cells' normals from up
    int level_surfaces = 0;       // patches of kSurfaceCells or more
    int level_heights = 0;        // their distinct heights
    // The lowest level surface's height along up, in the grid's frame: with the sensor at the
    // origin, how far below it the floor would be.
    double lowest_height = 0;
    // The level patches `up` rests on (none left out as flat but not level): each one's mean
    // cell centroid and its cells' covariance about it, in the grid's frame.
    struct Patch {
      Eigen::Vector3d mean;
      Eigen::Matrix3d covariance;
    };
    std::vector<Patch> evidence;
  };

  // The cells (centroids, normals, 26-neighbourhood) of `grid`, read once for every fit.
  void reset(const VoxelGrid& grid, const std::vector<Eigen::Vector3f>& normals);

  // From `start`, `rounds` rounds (the tolerance narrowing from `first_tolerance_deg` to 5°),
  // the last one measuring the support. A fit that wanders more than first_tolerance_deg + 10°
  // from `start` is unsupported.
  Result fit(const Eigen::Vector3d& start, double first_tolerance_deg, int rounds) const;

  static constexpr int kRounds = 4;
  // The last round's tolerance, degrees: it keeps ramps of more than ~5° out.
  static constexpr double kLastToleranceDeg = 5.0;

 private:
  struct Patch;
  bool notLevel(const Patch& patch, const Eigen::Vector3d& up) const;
  std::vector<Eigen::Vector3d> centroid_;
  std::vector<Eigen::Vector3d> normal_;  // NaN for a cell without one
  std::vector<std::uint32_t> neighbour_begin_, neighbours_;
  double cell_ = 0;
};

}  // namespace detail
}  // namespace hope
