// Up from the scene: the sensor's up direction estimated from the cloud itself, an orientation
// source for sensors without an IMU or tf (the paper's §2.2 takes the orientation "by
// pre-calibration or an IMU"), and the refinement of a given orientation by the scene.
//
// Level structure (a floor, table tops, a ground, a ceiling) is what makes up observable: its
// surfaces share one normal, and that normal is up. The estimate
//  1. reads a sample of the cloud (every k-th row and column of an image, every k-th point of
//     an unorganized cloud; at most LevellingParams::max_points), voxelizes it on a cubic grid
//     in the sensor's own frame (the grid filter with r_z = r_xy, since no direction is special
//     yet) and takes each cell's normal as the pipeline does (normal_estimation.h);
//  2. finds the directions that many normals share (a histogram on the sphere, peaks only where
//     the prior admits up: see UpPrior);
//  3. refines each such direction: the cells whose normal lies within a few degrees of it are
//     joined into connected patches at one height, and up becomes the direction that makes all
//     patches flattest at once (the least-variance direction of the patches' pooled scatter:
//     parallel surfaces at different heights all count, each with its own offset); repeated with
//     a narrowing tolerance;
//  4. keeps the direction with the most supporting level area (weighted by the prior's
//     preference for a camera that is not looking straight down), or refuses.
// A refinement (refine()) runs step 3 from the given orientation's up and accepts the result
// within a bound.
//
// Refusal. A scene with no level patch of LevellingParams::min_support_area gives no evidence
// (a wall seen at an angle, a lone sphere, an empty cloud): LevellingError. So does a camera
// that sees a single surface head-on and nothing else level: a wall in front of a level camera
// and a floor under a camera looking straight down are the same picture. So does a camera's
// scene whose only level structure would put its floor deeper than
// LevellingParams::max_floor_depth below it: a level camera facing a flight of stairs sees
// risers receding over metres and a far wall, which a camera looking straight down would take
// for levels. So does a reading whose level cells are not level at their own scale (most of
// the clearly flat ones tilting from it): at 10 cm cells a flight of stairs has a slope whose
// cells' normals agree, while its treads' own points tilt 20-40° from it. And so does a
// reading of less than LevellingParams::min_fallback_area left after a better-scored one was
// turned down: too little to choose between them.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "hope/gravity_alignment.h"
#include "hope/grid_filter.h"
#include "hope/orientation.h"
#include "hope/params.h"
#include "hope/plane.h"
#include "hope/points_view.h"

namespace hope {

namespace detail {
class LevelFit;
}

struct LevellingParams {
  // Edge of the levelling grid's cubic cells, metres (forExtraction: twice the extraction's
  // r_xy); coarsened where the sample is too sparse for it (see UpEstimator::buildGrid).
  double cell = 0.1;
  // At most this many points are read.
  std::size_t max_points = 20000;
  // refine(): the largest correction of the given orientation accepted, degrees.
  double max_correction_deg = 5.0;
  // Less level area than this (m², footprint at cell size) is no evidence.
  double min_support_area = 0.05;
  // A camera's floor (the lowest level surface it sees) lies at most this far below it, metres:
  // a camera held at a person's eye height (1.8 m) seeing one storey (2.7 m) further down a
  // flight of stairs. An up that would put the floor deeper is no evidence (a level camera
  // facing a staircase sees risers receding over metres, which a camera looking straight down
  // would take for levels). Raise it for a camera on a mast or a drone. Cameras only.
  double max_floor_depth = 4.5;
  // A reading taken after a better-scored one was turned down (its slope not level at the
  // cells' own scale, its floor out of reach, or its refit unsupported) must rest on at least
  // this much level area
  // (m²: a small table's top); less is too little to outweigh what was turned down, and the
  // scene is ambiguous (a staircase seen from below or head-on: a sliver of risers or tread
  // edges at any pitch).
  double min_fallback_area = 0.2;
  // refine(): the sensor's range noise, which bounds the tilt a level surface can tell (see
  // UpEstimator::refine). Unset: a depth camera's for the camera prior, a LiDAR's otherwise.
  std::optional<RangeNoise> noise;
  UpPrior prior = UpPrior::kAuto;

  // The levelling that goes with an extraction: cells of 2·r_xy. Level surfaces are wide, and
  // cells twice the extraction's are a quarter as many to fit (on the TUM frame the estimate
  // took 1.65 ms with 5 cm cells and 0.69 ms with 10 cm, at the accuracy of docs/evaluation.md
  // §8).
  static LevellingParams forExtraction(const Params& params);
};

// Throws std::invalid_argument naming the parameter and its accepted range.
void validate(const LevellingParams& params);

class UpEstimator {
 public:
  // Throws std::invalid_argument for out-of-range parameters.
  explicit UpEstimator(const LevellingParams& params = LevellingParams());
  ~UpEstimator();
  UpEstimator(UpEstimator&&) noexcept;
  UpEstimator& operator=(UpEstimator&&) noexcept;
  const LevellingParams& params() const { return params_; }

  // Up with no prior orientation. Throws LevellingError when the scene shows no level
  // structure, std::invalid_argument for a cloud that cannot be a scene in metres (as the
  // extractor does). Reuses its buffers: one estimator must not run two clouds at once.
  UpEstimate estimate(const PointsView& cloud);

  // The given orientation corrected so that the scene's level surfaces come out level, by at
  // most params().max_correction_deg, and only by more than the surfaces can tell: a surface
  // L across (in the direction of the correction) at range d, whose ends are each uncertain by
  // the sensor's noise σ(d), would show a tilt of up to atan(2σ(d) / L) if it were level; the
  // surfaces together tell 1 / sqrt(Σ 1 / that²). A correction within it is not evidence (a
  // 0.28 m stair tread 2.5 m from a Kinect-class camera cannot tell 3.9° in depth; a 3 m floor
  // at that range tells 0.4°), and the given orientation is kept. Never throws for lack of
  // evidence: the given orientation is then kept (applied = false, note says why).
  UpEstimate refine(const PointsView& cloud, const Orientation& given);

 private:
  void sample(const PointsView& cloud, UpPrior prior);
  void buildGrid(double cell);
  std::vector<Eigen::Vector3d> histogramPeaks() const;
  bool admissible(const Eigen::Vector3d& up) const;
  // A camera's pitch (down positive) for `up`, degrees.
  double pitchDeg(const Eigen::Vector3d& up) const;
  void describePrior(const Eigen::Vector3d& up, UpEstimate& e) const;

  LevellingParams params_;
  std::vector<Eigen::Vector3f> sample_;
  UpPrior prior_ = UpPrior::kZUp;
  // Camera axes in the cloud's frame (kCamera): right, image down, forward.
  Eigen::Vector3d right_ = Eigen::Vector3d::UnitX(), down_ = Eigen::Vector3d::UnitY(),
                  forward_ = Eigen::Vector3d::UnitZ();
  bool sensor_at_origin_ = true;
  VoxelGrid grid_;
  std::vector<Eigen::Vector3f> normals_;  // per voxel, facing the sensor when it is known
  // Per voxel, the normal of its own points where they are clearly flat (NaN elsewhere): the
  // surface at the cell's own scale, which a normal from the neighbouring cells smooths over.
  // ownNormals() sums each voxel's points (once per grid, on the first ownAgreement());
  // ownNormal(v) fits and keeps v's normal when asked.
  std::vector<int> own_count_;
  std::vector<Eigen::Vector3d> own_sum_;
  std::vector<Eigen::Matrix3d> own_outer_;
  std::vector<Eigen::Vector3f> own_normals_;
  bool own_sums_ready_ = false;
  void ownNormals();
  const Eigen::Vector3f& ownNormal(std::size_t v);
  // Of the cells whose normal lies within the fit's last tolerance of `up` and whose own
  // normal is known: how many, and the share whose own normal lies within kOwnAgreementDeg.
  std::pair<int, double> ownAgreement(const Eigen::Vector3d& up);
  // The fit's view of the grid (src/core/level_fit.h), behind a pointer: private to the core.
  std::unique_ptr<detail::LevelFit> fit_;
};

// `given` turned about the sensor (its position and yaw kept) so that `up_in_sensor`, a unit
// vector in the cloud's frame, becomes the reference frame's +z.
Orientation levelledTo(const Orientation& given, const Eigen::Vector3d& up_in_sensor);

// Up over a stream of frames (the nodelet): each frame's direction blended into a running one,
// so that one view's noise does not rock the reference frame, while a direction more than
// `reset_deg` from the running one (a hand-held sensor that turned) starts it afresh.
class UpSmoother {
 public:
  // `weight`: the share of each new frame, in (0, 1]; 1 keeps no history.
  explicit UpSmoother(double weight = 0.3, double reset_deg = 10.0);
  // Adds one frame's unit direction; returns the running one.
  const Eigen::Vector3d& add(const Eigen::Vector3d& up) { return add(up, weight_); }
  // The same with this frame's own share, in (0, 1] (frames further apart in time weigh more).
  const Eigen::Vector3d& add(const Eigen::Vector3d& up, double weight);
  bool empty() const { return frames_ == 0; }
  const Eigen::Vector3d& value() const { return value_; }
  // Frames since the running direction started (afresh).
  int frames() const { return frames_; }
  void reset() { frames_ = 0; }

 private:
  double weight_, cos_reset_;
  Eigen::Vector3d value_ = Eigen::Vector3d::UnitZ();
  int frames_ = 0;
};

// What the cloud looks like when no orientation was given: warnings for the CLI and Python
// when it does not look z-up (a camera's optical frame, or no level surface among `planes`, found
// under the assumption), and when an unorganized z-up cloud has no viewpoint (scan-gap bridging
// off).
std::vector<std::string> unorientedCloudWarnings(const PointsView& cloud,
                                                 const std::vector<HorizontalPlane>& planes,
                                                 bool viewpoint_known);

}  // namespace hope
