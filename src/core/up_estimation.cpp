#include "hope/up_estimation.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <optional>
#include <sstream>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>

#include "hope/normal_estimation.h"
#include "level_fit.h"

namespace hope {

namespace {

constexpr double kDegree = M_PI / 180.0;

// The camera prior's bounds (UpPrior::kCamera), and the z-up prior's cone.
constexpr double kMaxPitchUpDeg = 15.0;
constexpr double kMaxRollDeg = 35.0;
constexpr double kZUpConeDeg = 45.0;

// Normals within √2 cells: a cell's column and its 8 neighbours, whatever the surface's
// orientation in the sensor frame (the 4-neighbourhood of the extraction's grid suits a
// z-up grid only).
constexpr double kNormalRadiusFactor = 1.5;
constexpr int kMaxCoarsenings = 3;

// Histogram on the sphere: bins of 3° in latitude and longitude about a pole that no admissible
// up is near, peaks summed over 5 × 5 bins (±7.5°), and peaks at least 15° apart.
constexpr int kBinDeg = 3;
constexpr int kLatBins = 180 / kBinDeg, kLonBins = 360 / kBinDeg;
constexpr int kPeakHalfWidth = 2;
constexpr double kPeakSeparationDeg = 15.0;
constexpr int kMaxPeaks = 5;
constexpr int kMinPeakCells = 6;

// The fit's first tolerance must cover a bin's half diagonal and the spread of a noisy sensor's
// normals (the last, 5°, is level_fit.cpp's).
constexpr double kFirstToleranceDeg = 12.0;
// Candidates are screened with one round of the fit; the best few get every round.
constexpr int kFinalists = 2;

// A cell's own normal: from at least this many of its points, where the least variance of them
// is at most kOwnFlatness of the middle one (clearly flat: across a 10 cm cell, an RMS
// thickness under about 6.5 mm) and the middle one at least kOwnWidth of the largest (a patch,
// not a line: the points of one image row lie in one plane through the camera).
constexpr int kOwnNormalPoints = 5;
constexpr double kOwnFlatness = 0.05;
constexpr double kOwnWidth = 0.1;
// How far a support cell's own normal may lie from up. A flight of stairs seen at 10 cm cells
// has a slope whose cells' normals (from their neighbours, across the steps) agree: its
// treads' own normals lie 20-40° from that slope.
constexpr double kOwnAgreementDeg = 15.0;
// Fewer support cells with an own normal than this tell nothing (far or noisy surfaces have
// none: they are not counted against up); of more, at least this share must agree with up. On
// real level surfaces half or more do (the finalists on kitchen_dev, studyroom_dev and mosd_dev:
// 0.50 and up), on a flight's slope almost none (the synthetic flights: 0.00-0.11).
constexpr int kMinOwnCells = 10;
constexpr double kMinOwnAgreement = 0.3;

// A camera pitched more than this sees surfaces that face it head-on; with a single one of them
// the scene cannot tell a floor seen from above from a wall seen from a level camera.
constexpr double kHeadOnPitchDeg = 70.0;

double elapsedMs(std::chrono::steady_clock::time_point since) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - since)
      .count();
}

bool finite(const Eigen::Vector3f& p) { return std::isfinite(p.x() + p.y() + p.z()); }

Eigen::Vector3f pointOf(const PointsView& cloud, std::size_t i) {
  return Eigen::Vector3f(cloud.x(i), cloud.y(i), cloud.z(i));
}

// A point in front of a camera's optical frame: at z > 0 and within ~63° of the z axis. An
// unorganized cloud that a camera saw has (nearly) all its points so; a map or a LiDAR scan
// surrounds its origin or lies to one side of it.
bool inCameraFrustum(const Eigen::Vector3f& p) {
  return p.z() > 0 && std::fabs(p.x()) <= 2 * p.z() && std::fabs(p.y()) <= 2 * p.z();
}
constexpr double kInFrontShare = 0.99;

std::string formatted(const char* format, double a, double b = 0, double c = 0) {
  char text[160];
  std::snprintf(text, sizeof(text), format, a, b, c);
  return text;
}

}  // namespace

const char* toString(UpPrior prior) {
  switch (prior) {
    case UpPrior::kAuto:
      return "auto";
    case UpPrior::kCamera:
      return "camera";
    case UpPrior::kZUp:
      return "z-up";
  }
  return "?";
}

LevellingParams LevellingParams::forExtraction(const Params& params) {
  LevellingParams levelling;
  // Within the levelling grid's own range: an extraction at 0.1 mm is levelled on 1 mm cells.
  levelling.cell = std::clamp(2.0 * params.r_xy, 0.001, 10.0);
  return levelling;
}

void validate(const LevellingParams& params) {
  auto fail = [](const std::string& what) { throw std::invalid_argument(what); };
  // A value as a person writes it: 1e+308, not 309 digits.
  auto text = [](double value) {
    std::ostringstream out;
    out << value;
    return out.str();
  };
  if (!(params.cell >= 0.001 && params.cell <= 10.0)) {
    fail("levelling cell must be in [0.001, 10] m (got " + text(params.cell) + ")");
  }
  if (params.max_points < 1000 || params.max_points > 100000000) {
    fail("levelling max_points must be in [1000, 1e8] (got " + std::to_string(params.max_points) +
         ")");
  }
  if (!(params.max_correction_deg > 0 && params.max_correction_deg <= 30)) {
    fail("levelling max_correction must be in (0, 30] degrees (got " +
         text(params.max_correction_deg) + ")");
  }
  if (!(params.max_floor_depth > 0 && params.max_floor_depth <= 1e4)) {
    fail("levelling max_floor_depth must be in (0, 1e4] m (got " + text(params.max_floor_depth) +
         ")");
  }
  if (!(params.min_fallback_area >= 0 && params.min_fallback_area <= 1e6)) {
    fail("levelling min_fallback_area must be in [0, 1e6] m² (got " +
         text(params.min_fallback_area) + ")");
  }
  if (!(params.min_support_area >= 0 && params.min_support_area <= 1e6)) {
    fail("levelling min_support_area must be in [0, 1e6] m² (got " + text(params.min_support_area) +
         ")");
  }
  if (params.noise) validate(*params.noise, "levelling noise");
}

std::string UpEstimate::describe() const {
  std::ostringstream out;
  out << formatted("up (%.4f %.4f %.4f) in the sensor frame", up_in_sensor.x(), up_in_sensor.y(),
                   up_in_sensor.z());
  if (prior == UpPrior::kCamera)
    out << formatted(", camera pitch %.1f° roll %.1f°", pitch_deg, roll_deg);
  out << formatted(", level area %.2f m², normals within %.1f° RMS", support_area, angle_spread_deg)
      << ", " << level_surfaces << " level surface(s) at " << level_heights << " height(s)";
  if (refinement) {
    out << formatted("; %.2f° from the given up (the surfaces tell %.2f°)", correction_deg,
                     resolution_deg)
        << (applied ? ", corrected" : ", not corrected: " + note);
  }
  return out.str();
}

UpEstimator::UpEstimator(const LevellingParams& params)
    : params_(params), fit_(std::make_unique<detail::LevelFit>()) {
  validate(params_);
}
UpEstimator::~UpEstimator() = default;
UpEstimator::UpEstimator(UpEstimator&&) noexcept = default;
UpEstimator& UpEstimator::operator=(UpEstimator&&) noexcept = default;

// The axes of a pinhole camera from an organized cloud: every point p seen at pixel (c, r) lies
// on the ray A·(c, r, 1), A = [right/fx, down/fy, forward − …] in the cloud's own frame, so
// p × A·(c, r, 1) = 0 is linear in A's nine entries; their least-squares solution (the smallest
// eigenvector of the stacked constraints) gives right and down as A's first two columns, in
// whatever frame the cloud is published. False when the points fix no such camera.
class PinholeAxes {
 public:
  void add(const Eigen::Vector3f& point, double u, double v) {
    const Eigen::Vector3d p = point.cast<double>().normalized();
    const double pixel[3] = {u, v, 1.0};
    // B = [p]× U, U (3 × 9) with U(i, 3i + j) = pixel[j].
    Eigen::Matrix<double, 3, 9> b = Eigen::Matrix<double, 3, 9>::Zero();
    Eigen::Matrix3d cross;
    cross << 0, -p.z(), p.y(), p.z(), 0, -p.x(), -p.y(), p.x(), 0;
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j) b.col(3 * i + j) = cross.col(i) * pixel[j];
    }
    normal_ += b.transpose() * b;
    mean_ray_ += p;
    ++count_;
  }
  bool solve(Eigen::Vector3d& right, Eigen::Vector3d& down, Eigen::Vector3d& forward) const {
    if (count_ < 100) return false;
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, 9, 9>> solver(normal_);
    const Eigen::Matrix<double, 9, 1> a = solver.eigenvectors().col(0);
    Eigen::Matrix3d camera;
    camera << a(0), a(1), a(2), a(3), a(4), a(5), a(6), a(7), a(8);
    // A·(0.5, 0.5, 1), the image centre's ray (pixels are scaled to [0, 1)), points at the scene.
    const double sign = (camera * Eigen::Vector3d(0.5, 0.5, 1.0)).dot(mean_ray_) >= 0 ? 1 : -1;
    right = sign * camera.col(0);
    down = sign * camera.col(1);
    if (!(right.norm() > 1e-9 && down.norm() > 1e-9)) return false;
    right.normalize();
    down = (down - down.dot(right) * right);
    if (!(down.norm() > 1e-9)) return false;
    down.normalize();
    forward = right.cross(down);  // optical: x × y = z
    return forward.dot(mean_ray_) > 0;
  }

 private:
  Eigen::Matrix<double, 9, 9> normal_ = Eigen::Matrix<double, 9, 9>::Zero();
  Eigen::Vector3d mean_ray_ = Eigen::Vector3d::Zero();
  std::size_t count_ = 0;
};

// Reads every k-th row and column of an image (every k-th point otherwise) and, for the prior,
// finds out whether the cloud is a camera's and along which axes.
void UpEstimator::sample(const PointsView& cloud, UpPrior prior) {
  sample_.clear();
  const bool image_like = cloud.imageLike();
  PinholeAxes axes;
  if (image_like) {
    const double ratio = double(cloud.count) / double(params_.max_points);
    const std::size_t step = std::max<std::size_t>(1, std::size_t(std::ceil(std::sqrt(ratio))));
    // The camera's axes from about 500 of the sampled points: plenty for nine unknowns.
    const std::size_t fit_every = std::max<std::size_t>(1, (cloud.count / (step * step)) / 500);
    std::size_t sampled = 0;
    for (std::size_t row = 0; row < cloud.height; row += step) {
      for (std::size_t col = 0; col < cloud.width; col += step) {
        const Eigen::Vector3f p = pointOf(cloud, row * cloud.width + col);
        if (!finite(p)) continue;
        sample_.push_back(p);
        if (sampled++ % fit_every == 0 && p.norm() > 0) {
          axes.add(p, double(col) / cloud.width, double(row) / cloud.height);
        }
      }
    }
  } else {
    const std::size_t step =
        std::max<std::size_t>(1, (cloud.count + params_.max_points - 1) / params_.max_points);
    for (std::size_t i = 0; i < cloud.count; i += step) {
      const Eigen::Vector3f p = pointOf(cloud, i);
      if (finite(p)) sample_.push_back(p);
    }
  }

  prior_ = prior;
  right_ = Eigen::Vector3d::UnitX(), down_ = Eigen::Vector3d::UnitY();
  forward_ = Eigen::Vector3d::UnitZ();
  if (prior_ == UpPrior::kAuto) {
    if (image_like) {
      prior_ = UpPrior::kCamera;
    } else {
      const auto in_front = std::count_if(sample_.begin(), sample_.end(), inCameraFrustum);
      prior_ = !sample_.empty() && double(in_front) >= kInFrontShare * double(sample_.size())
                   ? UpPrior::kCamera
                   : UpPrior::kZUp;
    }
  }
  if (prior_ == UpPrior::kCamera && image_like) {
    Eigen::Vector3d right, down, forward;
    if (axes.solve(right, down, forward)) right_ = right, down_ = down, forward_ = forward;
  }
  sensor_at_origin_ = prior_ == UpPrior::kCamera;
}

// The cubic grid of the sample and its normals. The cell is doubled (at most kMaxCoarsenings
// times) while the sample puts under 4 points in a cell, or while fewer than half the cells get
// a normal: normals from cells of one or two points are noise, and a spinning LiDAR's rings lie
// metres apart on distant ground, where a cell sees one ring, a line, which fixes no plane.
void UpEstimator::buildGrid(double cell) {
  for (int attempt = 0;; ++attempt) {
    grid_.build(sample_, cell, cell);
    const bool dense = double(sample_.size()) >= 4.0 * double(grid_.numVoxels());
    if (dense || attempt == kMaxCoarsenings) estimateNormals(grid_, kNormalRadiusFactor, normals_);
    if (attempt == kMaxCoarsenings || grid_.numVoxels() == 0) break;
    if (dense) {
      const auto with_normal = std::count_if(normals_.begin(), normals_.end(),
                                             [](const Eigen::Vector3f& n) { return finite(n); });
      if (2 * std::size_t(with_normal) >= grid_.numVoxels()) break;
    }
    cell *= 2;
  }
  if (sensor_at_origin_) {
    // Facing the sensor: a floor's normal then points up and a ceiling's down.
    for (std::size_t v = 0; v < normals_.size(); ++v) {
      if (normals_[v].dot(grid_.centroid(v)) > 0) normals_[v] = -normals_[v];
    }
  }
  fit_->reset(grid_, normals_);
  own_sums_ready_ = false;  // summed when a finalist first asks (estimate(), not refine())
}

void UpEstimator::ownNormals() {
  // The points' sums per voxel now; a voxel's normal only when a finalist's support asks.
  const std::size_t n = grid_.numVoxels();
  own_count_.assign(n, 0);
  own_sum_.assign(n, Eigen::Vector3d::Zero());
  own_outer_.assign(n, Eigen::Matrix3d::Zero());
  const VoxelGrid::PointVoxels voxel_of = grid_.pointVoxels();
  for (std::size_t i = 0; i < sample_.size() && i < voxel_of.size(); ++i) {
    const std::int32_t v = voxel_of[i];
    if (v < 0) continue;
    const Eigen::Vector3d p = sample_[i].cast<double>();
    ++own_count_[v], own_sum_[v] += p, own_outer_[v] += p * p.transpose();
  }
  own_normals_.assign(n, Eigen::Vector3f::Zero());  // zero: not computed yet
}

const Eigen::Vector3f& UpEstimator::ownNormal(std::size_t v) {
  Eigen::Vector3f& normal = own_normals_[v];
  if (normal.isZero()) {
    normal = Eigen::Vector3f::Constant(NAN);
    const int count = own_count_[v];
    if (count >= kOwnNormalPoints) {
      const Eigen::Matrix3d scatter = own_outer_[v] - own_sum_[v] * own_sum_[v].transpose() / count;
      const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(scatter);
      const Eigen::Vector3d& lambda = solver.eigenvalues();
      if (lambda(0) <= kOwnFlatness * lambda(1) && lambda(1) >= kOwnWidth * lambda(2)) {
        normal = solver.eigenvectors().col(0).cast<float>();
      }
    }
  }
  return normal;
}

std::pair<int, double> UpEstimator::ownAgreement(const Eigen::Vector3d& up) {
  if (!own_sums_ready_) ownNormals();
  own_sums_ready_ = true;
  // The support: the cells the fit's last round takes.
  const float support = static_cast<float>(std::cos(detail::LevelFit::kLastToleranceDeg * kDegree));
  const float agree = static_cast<float>(std::cos(kOwnAgreementDeg * kDegree));
  const Eigen::Vector3f u = up.cast<float>();
  int cells = 0, agreeing = 0;
  for (std::size_t v = 0; v < normals_.size(); ++v) {
    if (!(std::fabs(normals_[v].dot(u)) >= support)) continue;
    const Eigen::Vector3f& own = ownNormal(v);
    if (!finite(own)) continue;
    ++cells;
    agreeing += std::fabs(own.dot(u)) >= agree;
  }
  return {cells, cells ? double(agreeing) / cells : 1.0};
}

bool UpEstimator::admissible(const Eigen::Vector3d& up) const {
  if (prior_ == UpPrior::kZUp) return up.z() >= std::cos(kZUpConeDeg * kDegree);
  const double along_right = up.dot(right_), along_down = up.dot(down_);
  const double along_forward = up.dot(forward_);
  // Pitch: up leans towards −forward as the camera looks down; at most 15° the other way.
  if (along_forward > std::sin(kMaxPitchUpDeg * kDegree)) return false;
  // Roll: the horizontal part of up (its right and −down components) within 35° of −down.
  // Near straight down that part is short and roll means little: 5° of slack.
  const double slack = std::sin(5.0 * kDegree);
  const double horizontal = std::hypot(along_right, along_down);
  if (along_down > slack) return false;
  return std::fabs(along_right) <= std::sin(kMaxRollDeg * kDegree) * horizontal + slack;
}

double UpEstimator::pitchDeg(const Eigen::Vector3d& up) const {
  return std::asin(std::clamp(-up.dot(forward_), -1.0, 1.0)) / kDegree;
}

void UpEstimator::describePrior(const Eigen::Vector3d& up, UpEstimate& e) const {
  e.prior = prior_;
  if (prior_ != UpPrior::kCamera) return;
  e.pitch_deg = pitchDeg(up);
  // Positive with the image's right side down (ROS: about the forward axis).
  e.roll_deg = std::atan2(-up.dot(right_), -up.dot(down_)) / kDegree;
}

// Peaks of the normals' directions where up is admissible, strongest first.
std::vector<Eigen::Vector3d> UpEstimator::histogramPeaks() const {
  // Latitude about a pole no admissible up is near (the camera's right axis, or x for z-up),
  // longitude from e0 towards e90.
  Eigen::Vector3d pole, e0, e90;
  if (prior_ == UpPrior::kCamera) {
    pole = right_, e0 = -down_, e90 = -forward_;
  } else {
    pole = Eigen::Vector3d::UnitX(), e0 = Eigen::Vector3d::UnitZ(), e90 = Eigen::Vector3d::UnitY();
  }
  auto directionOf = [&](double lat, double lon) {
    return Eigen::Vector3d(std::sin(lat) * pole +
                           std::cos(lat) * (std::cos(lon) * e0 + std::sin(lon) * e90));
  };
  std::vector<int> bins(kLatBins * kLonBins, 0);
  for (const Eigen::Vector3f& nf : normals_) {
    if (!finite(nf)) continue;
    const Eigen::Vector3d n = nf.cast<double>();
    const double lat = std::asin(std::clamp(n.dot(pole), -1.0, 1.0));
    const double lon = std::atan2(n.dot(e90), n.dot(e0));
    const int i = std::clamp(int((lat / kDegree + 90) / kBinDeg), 0, kLatBins - 1);
    const int j = std::clamp(int((lon / kDegree + 180) / kBinDeg), 0, kLonBins - 1);
    ++bins[i * kLonBins + j];
  }
  struct Peak {
    int cells;
    Eigen::Vector3d direction;
  };
  std::vector<Peak> peaks;
  for (int i = 0; i < kLatBins; ++i) {
    for (int j = 0; j < kLonBins; ++j) {
      if (bins[i * kLonBins + j] == 0) continue;
      const double lat = ((i + 0.5) * kBinDeg - 90) * kDegree;
      const double lon = ((j + 0.5) * kBinDeg - 180) * kDegree;
      const Eigen::Vector3d direction = directionOf(lat, lon);
      if (!admissible(direction)) continue;
      int cells = 0;
      for (int di = -kPeakHalfWidth; di <= kPeakHalfWidth; ++di) {
        const int ii = i + di;
        if (ii < 0 || ii >= kLatBins) continue;
        for (int dj = -kPeakHalfWidth; dj <= kPeakHalfWidth; ++dj) {
          cells += bins[ii * kLonBins + (j + dj + kLonBins) % kLonBins];
        }
      }
      if (cells >= kMinPeakCells) peaks.push_back({cells, direction});
    }
  }
  std::sort(peaks.begin(), peaks.end(),
            [](const Peak& a, const Peak& b) { return a.cells > b.cells; });
  std::vector<Eigen::Vector3d> chosen;
  const double separation = std::cos(kPeakSeparationDeg * kDegree);
  for (const Peak& peak : peaks) {
    if (int(chosen.size()) == kMaxPeaks) break;
    const bool near_chosen = std::any_of(chosen.begin(), chosen.end(), [&](const auto& c) {
      return c.dot(peak.direction) > separation;
    });
    if (!near_chosen) chosen.push_back(peak.direction);
  }
  return chosen;
}

UpEstimate UpEstimator::estimate(const PointsView& cloud) {
  const auto start = std::chrono::steady_clock::now();
  sample(cloud, params_.prior);
  const std::string options =
      "level it another way: give the sensor's orientation (a gravity vector, a quaternion, "
      "roll/pitch/yaw or a pose; hope_extract --gravity/--quaternion/--rpy/--pose, "
      "--level with one of them refines it)";
  if (sample_.size() < 3) {
    throw LevellingError("cannot find up from the scene: the cloud has " +
                         std::to_string(sample_.size()) + " finite point(s); " + options);
  }
  buildGrid(params_.cell);

  using Fit = detail::LevelFit::Result;
  std::vector<Fit> candidates;
  bool head_on_only = false;
  std::optional<Fit> too_deep;       // the best candidate that put the floor out of reach
  std::optional<Fit> sloped;         // the best finalist not level at its cells' own scale
  std::optional<Fit> weak_fallback;  // a finalist too small to outweigh those turned down
  // A camera's floor lies at most max_floor_depth below it: an up under which the lowest level
  // surface lies deeper is what a camera looking straight down a staircase's risers, or at a
  // far wall, would take for levels (a level camera facing a flight of stairs sees risers
  // receding over metres), not a scene a robot or a hand holds a camera over.
  auto within_reach = [&](const Fit& c) {
    return prior_ != UpPrior::kCamera || c.level_surfaces == 0 ||
           -c.lowest_height <= params_.max_floor_depth;
  };
  for (const Eigen::Vector3d& peak : histogramPeaks()) {
    const Fit c = fit_->fit(peak, kFirstToleranceDeg, 1);
    if (!c.supported || c.support_area < params_.min_support_area || !admissible(c.up)) continue;
    if (!within_reach(c)) {
      if (!too_deep || c.support_area > too_deep->support_area) too_deep = c;
      continue;
    }
    // One surface facing a camera head-on, nothing else level at another height: a wall in
    // front of a level camera and a floor under a camera looking straight down look the same,
    // so it is no evidence either way.
    if (prior_ == UpPrior::kCamera && pitchDeg(c.up) > kHeadOnPitchDeg && c.level_heights <= 1) {
      head_on_only = true;
      continue;
    }
    const bool duplicate = std::any_of(candidates.begin(), candidates.end(), [&](const Fit& o) {
      return o.up.dot(c.up) > std::cos(3 * kDegree);
    });
    if (!duplicate) candidates.push_back(c);
  }
  // A camera looking steeply down is rare beside one looking ahead, and what it takes for level
  // (surfaces facing it head-on) is what a level camera takes for walls: such candidates count
  // for less, down to a quarter of their area straight down.
  auto score = [&](const Fit& c) {
    if (prior_ != UpPrior::kCamera) return c.support_area;
    const double pitch = pitchDeg(c.up);
    const double weight = pitch <= 60 ? 1.0 : 1.0 - 0.75 * std::min(1.0, (pitch - 60) / 30);
    return c.support_area * weight;
  };
  std::sort(candidates.begin(), candidates.end(),
            [&](const Fit& a, const Fit& b) { return score(a) > score(b); });
  // Every round for the best screened candidates, the first that holds wins.
  std::optional<Fit> chosen;
  for (std::size_t k = 0; k < candidates.size() && k < kFinalists && !chosen; ++k) {
    const Fit c = fit_->fit(candidates[k].up, kFirstToleranceDeg, detail::LevelFit::kRounds);
    if (!c.supported || c.support_area < params_.min_support_area || !admissible(c.up)) continue;
    if (!within_reach(c)) {
      if (!too_deep || c.support_area > too_deep->support_area) too_deep = c;
      continue;
    }
    // Level at the cells' own scale too: the treads of a flight of stairs, not its slope.
    const auto [own_cells, own_share] = ownAgreement(c.up);
    if (own_cells >= kMinOwnCells && own_share < kMinOwnAgreement) {
      if (!sloped || c.support_area > sloped->support_area) sloped = c;
      continue;
    }
    if (k > 0 && c.support_area < params_.min_fallback_area) {
      if (!weak_fallback || c.support_area > weak_fallback->support_area) weak_fallback = c;
      continue;
    }
    chosen = c;
  }
  if (!chosen && weak_fallback) {
    throw LevellingError(
        "cannot find up from the scene: the level reading that holds (camera pitched " +
        formatted("%.0f°) rests on %.2f m² of level area, ", pitchDeg(weak_fallback->up),
                  weak_fallback->support_area) +
        formatted("less than the %.2f m² (LevellingParams::min_fallback_area) ",
                  params_.min_fallback_area) +
        "that would outweigh the better-scored readings turned down before it (a staircase "
        "seen from below or head-on); " +
        options);
  }
  if (!chosen && sloped) {
    throw LevellingError(
        "cannot find up from the scene: its level reading (camera pitched " +
        formatted("%.0f°) is not level at the cells' own scale: ", pitchDeg(sloped->up)) +
        "the surfaces it rests on tilt from it, as the treads of a flight of stairs tilt from "
        "the flight's slope; " +
        options);
  }
  if (!chosen && too_deep) {
    throw LevellingError(
        "cannot find up from the scene: the only level structure it shows would put the floor " +
        formatted("%.1f m below the camera (pitched %.0f°), ", -too_deep->lowest_height,
                  pitchDeg(too_deep->up)) +
        formatted("deeper than the %.1f m a camera on a robot or in a hand stands above it ",
                  params_.max_floor_depth) +
        "(LevellingParams::max_floor_depth): risers or a far wall, not levels; " + options);
  }
  if (!chosen && head_on_only) {
    throw LevellingError(
        "cannot find up from the scene: it shows one surface facing the camera and nothing "
        "else level (a wall in front of a level camera and a floor under a camera looking "
        "straight down look the same); " +
        options);
  }
  if (!chosen) {
    std::ostringstream msg;
    msg << "cannot find up from the scene: no level surface of "
        << formatted("%.2f", params_.min_support_area) << " m² or more where up can be ("
        << (prior_ == UpPrior::kCamera
                ? "a camera, between 15° above level and straight down, rolled up to 35°"
                : "within 45° of the cloud's z axis")
        << "; a wall, a single object or an empty scene gives no evidence); " << options;
    throw LevellingError(msg.str());
  }
  const Fit& best = *chosen;

  UpEstimate e;
  describePrior(best.up, e);
  e.up_in_sensor = best.up;
  e.orientation = Orientation::fromGravity(best.up.x(), best.up.y(), best.up.z());
  e.support_area = best.support_area;
  e.angle_spread_deg = best.angle_spread_deg;
  e.level_surfaces = best.level_surfaces;
  e.level_heights = best.level_heights;
  e.time_ms = elapsedMs(start);
  return e;
}

namespace {

// The tilt, degrees, that fit's level patches can tell in the direction from its up to
// `given_up`, with the sensor's range noise (see UpEstimator::refine()).
double resolutionDeg(const detail::LevelFit::Result& fit, const Eigen::Vector3d& given_up,
                     const RangeNoise& noise) {
  // The direction the correction tilts in: across the level plane, towards the given up.
  const Eigen::Vector3d& up = fit.up;
  Eigen::Vector3d across = given_up - given_up.dot(up) * up;
  if (across.norm() < 1e-9) across = up.unitOrthogonal();
  across.normalize();
  // A patch L across with its ends each σ off could fake a tilt of 2σ / L; with L the length of
  // a uniform strip of the same variance, sqrt(12 var), 1 / tilt² = 3 var / σ². The patches'
  // errors are independent: their 1 / tilt² add.
  double information = 0;
  for (const detail::LevelFit::Result::Patch& patch : fit.evidence) {
    const double sigma = std::max(noise.at(patch.mean.norm()), 1e-6);
    information += 3.0 * across.dot(patch.covariance * across) / (sigma * sigma);
  }
  if (information <= 0) return 90.0;
  return std::atan(1.0 / std::sqrt(information)) / kDegree;
}

}  // namespace

UpEstimate UpEstimator::refine(const PointsView& cloud, const Orientation& given) {
  const auto start = std::chrono::steady_clock::now();
  const Eigen::Vector3d given_up = upInSensor(given.sensorToReference());
  sample(cloud, params_.prior);

  UpEstimate e;
  e.refinement = true;
  e.applied = false;
  e.orientation = given;
  e.up_in_sensor = given_up;
  detail::LevelFit::Result c;
  if (sample_.size() >= 3) {
    buildGrid(params_.cell);
    c = fit_->fit(given_up, params_.max_correction_deg + 5.0, detail::LevelFit::kRounds);
  }
  e.support_area = c.support_area;
  e.angle_spread_deg = c.angle_spread_deg;
  e.level_surfaces = c.level_surfaces;
  e.level_heights = c.level_heights;
  if (!c.supported || c.support_area < params_.min_support_area) {
    e.note = "no level surface of " + formatted("%.2f", params_.min_support_area) +
             " m² or more within " + formatted("%.1f", params_.max_correction_deg) +
             "° of the given up";
  } else {
    e.correction_deg = std::acos(std::clamp(c.up.dot(given_up), -1.0, 1.0)) / kDegree;
    e.resolution_deg =
        resolutionDeg(c, given_up,
                      params_.noise.value_or(prior_ == UpPrior::kCamera ? RangeNoise::depthCamera()
                                                                        : RangeNoise::lidar()));
    if (e.correction_deg > params_.max_correction_deg) {
      e.note = "the level surfaces are " + formatted("%.2f", e.correction_deg) +
               "° from the given up, more than the bound of " +
               formatted("%.1f", params_.max_correction_deg) + "°";
    } else if (e.correction_deg <= e.resolution_deg) {
      e.note = "the level surfaces are " + formatted("%.2f", e.correction_deg) +
               "° from the given up, within the " + formatted("%.2f", e.resolution_deg) +
               "° that their extent and the sensor's noise at their range can tell";
    } else {
      e.orientation = levelledTo(given, c.up);
      e.up_in_sensor = c.up;
      e.applied = true;
    }
  }
  describePrior(e.up_in_sensor, e);
  e.time_ms = elapsedMs(start);
  return e;
}

Orientation levelledTo(const Orientation& given, const Eigen::Vector3d& up_in_sensor) {
  // Turned about the sensor, so that its position (and the heights' origin) stays.
  const Eigen::Isometry3d& transform = given.sensorToReference();
  const Eigen::Quaterniond correction = Eigen::Quaterniond::FromTwoVectors(
      transform.linear() * up_in_sensor.normalized(), Eigen::Vector3d::UnitZ());
  Eigen::Isometry3d corrected = transform;
  corrected.linear() = correction.toRotationMatrix() * transform.linear();
  const Orientation levelled = Orientation::fromTransform(corrected);
  if (!given.viewpoint()) return levelled.withoutViewpoint();
  const Eigen::Vector3d& t = transform.translation();
  return levelled.withViewpoint(correction * (*given.viewpoint() - t) + t);
}

UpSmoother::UpSmoother(double weight, double reset_deg)
    : weight_(std::clamp(weight, 1e-3, 1.0)), cos_reset_(std::cos(reset_deg * kDegree)) {}

const Eigen::Vector3d& UpSmoother::add(const Eigen::Vector3d& up, double weight) {
  weight = std::clamp(weight, 1e-3, 1.0);
  const Eigen::Vector3d unit = up.normalized();
  if (frames_ == 0 || value_.dot(unit) < cos_reset_) {
    value_ = unit;
    frames_ = 1;
    return value_;
  }
  value_ = ((1 - weight) * value_ + weight * unit).normalized();
  ++frames_;
  return value_;
}

std::vector<std::string> unorientedCloudWarnings(const PointsView& cloud,
                                                 const std::vector<HorizontalPlane>& planes,
                                                 bool viewpoint_known) {
  std::vector<std::string> warnings;
  const bool image_like = cloud.imageLike();
  const std::size_t step = std::max<std::size_t>(1, cloud.count / 20000);
  std::size_t finite_points = 0, in_front = 0;
  Eigen::AlignedBox3f box;
  for (std::size_t i = 0; i < cloud.count; i += step) {
    const Eigen::Vector3f p = pointOf(cloud, i);
    if (!finite(p)) continue;
    ++finite_points;
    box.extend(p);
    if (inCameraFrustum(p)) ++in_front;
  }
  if (finite_points == 0) return warnings;
  const bool camera_like = double(in_front) >= kInFrontShare * double(finite_points);
  if (camera_like) {
    warnings.push_back(
        std::string("no orientation given and the cloud looks like a camera's optical frame "
                    "(every point in front of it along +z") +
        (image_like ? ", an image's layout" : "") +
        "), yet hope takes its z axis as up: the planes found are slices of whatever faces the "
        "camera. Level it from the scene (hope_extract --level, Python level=True) or give the "
        "sensor's orientation (--gravity, --quaternion, --rpy, --pose)");
    return warnings;
  }
  double planes_area = 0;
  for (const HorizontalPlane& plane : planes) planes_area += plane.area;
  if (planes_area < 0.05) {
    warnings.push_back(
        "no orientation given and no level surface found with the cloud's z axis as up: is the "
        "cloud z-up? Level it from the scene (hope_extract --level, Python level=True) or give "
        "the sensor's orientation (--gravity, --quaternion, --rpy, --pose)");
  }
  // A scan around its sensor: the origin inside the points' box, in xy.
  const bool around_origin =
      box.min().x() < 0 && box.max().x() > 0 && box.min().y() < 0 && box.max().y() > 0;
  if (!viewpoint_known && !image_like && around_origin) {
    warnings.push_back(
        "no viewpoint: scan-gap bridging is off (it follows the sensor's rays), so a spinning "
        "LiDAR's ground beyond ~10 m comes out in pieces; for a scan in its sensor's own frame "
        "give --viewpoint \"0 0 0\" (Python viewpoint=(0, 0, 0))");
  }
  return warnings;
}

}  // namespace hope
