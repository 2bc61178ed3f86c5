#include "hope/scene_odometry.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Eigenvalues>

namespace hope {

namespace {

constexpr std::uint64_t kEmpty = std::numeric_limits<std::uint64_t>::max();
// A voxel's key: 21 bits for each of x, y and z, biased to be positive (±1 M voxels: ±31 km at
// 3 cm). Coordinates are kept two voxels inside the range, so that a neighbour's key (one step
// either way) never borrows from the next field.
constexpr std::int64_t kBias = std::int64_t{1} << 20;
constexpr int kFieldBits = 21;
// Points visited a frame, at most (a 640 × 480 image every second row and column): more do not
// move a 3 cm voxel's centroid measurably, and the time grows with them.
constexpr std::size_t kMaxPoints = 80000;
// A voxel's points, fewer than this, give no centroid worth aligning.
constexpr int kMinSamplePoints = 3;
// A voxel's points are flat when their smallest spread is a tenth of the next or less, from at
// least this many points: an edge or a corner tells no single normal.
constexpr int kMinNormalPoints = 6;
constexpr double kFlatness = 0.1;
// Correspondences within 1.5 voxels of a centroid: the neighbourhood searched.
constexpr double kReach = 1.5;
// Residuals beyond 0.3 voxels weigh less (Huber): a surface seen in one frame and not the
// other, or a moved thing, pulls the motion less.
constexpr double kHuber = 0.3;
// The share of the correspondences that must lie on surfaces that are not horizontal for the
// shift along them and the turn to be measured: a tenth of the demo room's, half of
// kitchen_dev's and studyroom_dev's at the least; a floor alone in view has under 1 %.
constexpr double kMinSteepShare = 0.05;
// Fewer correspondences than this at a level: the frames share too little to align.
constexpr int kMinPairs = 30;
// Starting turns tried when neither the last motion nor none reaches min_overlap: a hand-held
// camera turns up to ~15° between frames a third of a second apart.
constexpr std::array<double, 4> kYawSeedsDeg = {-20.0, -10.0, 10.0, 20.0};

std::int64_t decode(std::uint64_t key, int field) {
  return static_cast<std::int64_t>((key >> (field * kFieldBits)) & ((1u << kFieldBits) - 1)) -
         kBias;
}

std::uint64_t encode(std::int64_t x, std::int64_t y, std::int64_t z) {
  return (static_cast<std::uint64_t>(x + kBias) << (2 * kFieldBits)) |
         (static_cast<std::uint64_t>(y + kBias) << kFieldBits) |
         static_cast<std::uint64_t>(z + kBias);
}

bool keyOf(const Eigen::Vector3d& p, double size, std::uint64_t& key) {
  const Eigen::Vector3d c = (p / size).array().floor();
  if (!c.allFinite() || !(c.cwiseAbs().maxCoeff() < static_cast<double>(kBias - 2))) return false;
  key = encode(static_cast<std::int64_t>(c.x()), static_cast<std::int64_t>(c.y()),
               static_cast<std::int64_t>(c.z()));
  return true;
}

// ⌊v / 2⌋: the coordinate of the voxel twice as large that holds voxel v.
std::int64_t halvedDown(std::int64_t v) { return v >= 0 ? v / 2 : -((1 - v) / 2); }

std::uint64_t neighbour(std::uint64_t key, int dx, int dy, int dz) {
  return encode(decode(key, 2) + dx, decode(key, 1) + dy, decode(key, 0) + dz);
}

// Fibonacci hashing: the product's top bits, as many as the table has slots (mask + 1, a power
// of two), are spread whichever of x, y, z differ.
std::size_t slotOf(std::uint64_t key, std::size_t mask) {
  const int bits = __builtin_popcountll(mask);
  return static_cast<std::size_t>((key * 0x9E3779B97F4A7C15ULL) >> (64 - bits));
}

// Sums of a voxel's points: count, Σp, Σp pᵀ (upper triangle).
struct Moments {
  int count = 0;
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  std::array<double, 6> outer{};
  void add(const Eigen::Vector3d& p) {
    ++count;
    sum += p;
    outer[0] += p.x() * p.x();
    outer[1] += p.x() * p.y();
    outer[2] += p.x() * p.z();
    outer[3] += p.y() * p.y();
    outer[4] += p.y() * p.z();
    outer[5] += p.z() * p.z();
  }
  void add(const Moments& m) {
    count += m.count;
    sum += m.sum;
    for (std::size_t k = 0; k < outer.size(); ++k) outer[k] += m.outer[k];
  }
};

// Voxels being filled: a key table (open addressing) and each voxel's moments.
struct VoxelSums {
  std::vector<std::uint64_t> keys;
  std::vector<std::int32_t> index;
  std::vector<std::uint64_t> key_of;
  std::vector<Moments> moments;
  std::size_t mask = 0;

  explicit VoxelSums(std::size_t expected) {
    std::size_t slots = 64;
    while (slots < 2 * expected) slots *= 2;
    keys.assign(slots, kEmpty);
    index.assign(slots, -1);
    mask = slots - 1;
  }
  // The voxel's index, added when new.
  std::int32_t at(std::uint64_t key) {
    std::size_t s = slotOf(key, mask);
    while (keys[s] != kEmpty && keys[s] != key) s = (s + 1) & mask;
    if (keys[s] == kEmpty) {
      if (2 * (moments.size() + 1) > keys.size()) {
        grow();
        return at(key);
      }
      keys[s] = key;
      index[s] = static_cast<std::int32_t>(moments.size());
      key_of.push_back(key);
      moments.emplace_back();
    }
    return index[s];
  }
  void grow() {
    const std::size_t slots = 2 * keys.size();
    keys.assign(slots, kEmpty);
    index.assign(slots, -1);
    mask = slots - 1;
    for (std::size_t v = 0; v < key_of.size(); ++v) {
      std::size_t s = slotOf(key_of[v], mask);
      while (keys[s] != kEmpty) s = (s + 1) & mask;
      keys[s] = key_of[v];
      index[s] = static_cast<std::int32_t>(v);
    }
  }
};

// The plane through a voxel's points: the normal of their smallest spread, where that spread is
// a tenth of the next or less (an edge or a corner tells no single normal).
bool flatNormal(const Moments& m, Eigen::Vector3d& normal) {
  if (m.count < kMinNormalPoints) return false;
  const Eigen::Vector3d mean = m.sum / m.count;
  Eigen::Matrix3d covariance;
  const auto& o = m.outer;
  covariance << o[0], o[1], o[2], o[1], o[3], o[4], o[2], o[4], o[5];
  covariance = covariance / m.count - mean * mean.transpose();
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver;
  solver.computeDirect(covariance);
  const Eigen::Vector3d spread = solver.eigenvalues();  // ascending
  if (!(spread(0) <= kFlatness * spread(1))) return false;
  normal = solver.eigenvectors().col(0);
  return true;
}

// The finished level: each voxel's centroid and, where flat, the normal of the voxel twice its
// size that holds it (`parent`: its index in `coarser`): a voxel of a few points tells no
// normal, the eight around it do.
// The level's key table is taken from `sums` (its moments stay, for the samples).
SceneOdometry::Voxels finish(VoxelSums& sums, double size, const VoxelSums& coarser,
                             const std::vector<std::int32_t>& parent) {
  SceneOdometry::Voxels out;
  out.size = size;
  out.table_keys = std::move(sums.keys);
  out.table_index = std::move(sums.index);
  const std::size_t n = sums.moments.size();
  out.centroid.resize(n);
  out.normal.assign(n, Eigen::Vector3d::UnitZ());
  out.flat.assign(n, 0);
  std::vector<std::int8_t> parent_flat(coarser.moments.size(), -1);  // -1: not yet known
  std::vector<Eigen::Vector3d> parent_normal(parent_flat.size());
  for (std::size_t v = 0; v < n; ++v) {
    const Moments& own = sums.moments[v];
    out.centroid[v] = own.sum / own.count;
    if (own.count < kMinSamplePoints) continue;  // a stray point's voxel aligns nothing
    const std::size_t up = static_cast<std::size_t>(parent[v]);
    if (parent_flat[up] < 0) parent_flat[up] = flatNormal(coarser.moments[up], parent_normal[up]);
    if (parent_flat[up] > 0) {
      out.normal[v] = parent_normal[up];
      out.flat[v] = 1;
    }
  }
  return out;
}

Eigen::Matrix3d turn(double yaw) {
  return Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).matrix();
}

// The flat voxel of `model` holding `q`, else the flat one nearest it among the voxels around
// within kReach voxels, or -1; `distance` from q to its centroid.
std::int32_t nearestFlat(const SceneOdometry::Voxels& model, const Eigen::Vector3d& q,
                         double& distance) {
  std::uint64_t key;
  if (!keyOf(q, model.size, key)) return -1;
  const double reach = kReach * model.size;
  // The voxel holding q, when flat: its plane is q's surface (point-to-plane needs no nearer
  // centroid), and after the coarser levels it is the answer most of the time.
  const std::int32_t own = model.find(key);
  if (own >= 0 && model.flat[static_cast<std::size_t>(own)]) {
    distance = (q - model.centroid[static_cast<std::size_t>(own)]).norm();
    return own;
  }
  std::int32_t best = -1;
  double best_d = HUGE_VAL;
  for (int dx = -1; dx <= 1; ++dx) {
    for (int dy = -1; dy <= 1; ++dy) {
      for (int dz = -1; dz <= 1; ++dz) {
        if (dx == 0 && dy == 0 && dz == 0) continue;
        const std::int32_t v = model.find(neighbour(key, dx, dy, dz));
        if (v < 0 || !model.flat[static_cast<std::size_t>(v)]) continue;
        const double d = (q - model.centroid[static_cast<std::size_t>(v)]).norm();
        if (d < best_d) {
          best_d = d;
          best = v;
        }
      }
    }
  }
  if (best_d > reach) return -1;
  distance = best_d;
  return best;
}

// Every k-th sample voxel (those of kMinSamplePoints or more), at most `most`.
std::vector<std::size_t> samplesOf(const VoxelSums& sums, std::size_t most) {
  std::vector<std::size_t> all;
  for (std::size_t v = 0; v < sums.moments.size(); ++v) {
    if (sums.moments[v].count >= kMinSamplePoints) all.push_back(v);
  }
  if (all.size() <= most) return all;
  std::vector<std::size_t> picked;
  picked.reserve(most);
  for (std::size_t k = 0; k < most; ++k) picked.push_back(all[k * all.size() / most]);
  return picked;
}

}  // namespace

std::int32_t SceneOdometry::Voxels::find(std::uint64_t key) const {
  if (table_keys.empty()) return -1;
  const std::size_t mask = table_keys.size() - 1;
  std::size_t s = slotOf(key, mask);
  while (table_keys[s] != kEmpty) {
    if (table_keys[s] == key) return table_index[s];
    s = (s + 1) & mask;
  }
  return -1;
}

void validate(const OdometryParams& p) {
  auto require = [](bool ok, const std::string& what) {
    if (!ok) throw std::invalid_argument("scene odometry: " + what);
  };
  require(p.cell >= 1e-3 && p.cell <= 10,
          "cell = " + std::to_string(p.cell) + " m is out of range [0.001, 10] (metres?)");
  require(p.levels >= 1 && p.levels <= 8,
          "levels = " + std::to_string(p.levels) + " is out of range [1, 8]");
  require(p.iterations >= 1 && p.iterations <= 100,
          "iterations = " + std::to_string(p.iterations) + " is out of range [1, 100]");
  require(p.max_samples >= 100 && p.max_samples <= 1000000,
          "max_samples = " + std::to_string(p.max_samples) + " is out of range [100, 1000000]");
  if (p.noise) validate(*p.noise, "scene odometry noise");
  require(p.level_tilt_deg >= 0 && p.level_tilt_deg <= 45,
          "level_tilt_deg = " + std::to_string(p.level_tilt_deg) + " is out of range [0, 45]");
  require(p.min_overlap >= 0 && p.min_overlap <= 1,
          "min_overlap = " + std::to_string(p.min_overlap) + " is out of range [0, 1]");
}

SceneOdometry::SceneOdometry(const OdometryParams& params) : params_(params) { validate(params_); }

void SceneOdometry::reset() {
  last_.clear();
  world_from_last_.setIdentity();
  last_motion_ = Motion();
}

OdometryStep SceneOdometry::update(const PointsView& cloud,
                                   const Eigen::Isometry3d& sensor_to_frame) {
  // The frame's points in the gravity-aligned frame, in voxels of every level.
  const Eigen::Vector3d sensor = sensor_to_frame.translation();
  const RangeNoise noise =
      params_.noise.value_or(cloud.imageLike() ? RangeNoise::depthCamera() : RangeNoise::lidar());
  std::vector<VoxelSums> sums;
  sums.emplace_back(std::min<std::size_t>(cloud.count, kMaxPoints) / 4 + 16);
  const auto add = [&](std::size_t i) {
    const Eigen::Vector3d p = sensor_to_frame * Eigen::Vector3d(cloud.x(i), cloud.y(i), cloud.z(i));
    if (!p.allFinite()) return;
    if (noise.at((p - sensor).norm()) > params_.cell) return;
    std::uint64_t key;
    if (keyOf(p, params_.cell, key))
      sums[0].moments[static_cast<std::size_t>(sums[0].at(key))].add(p);
  };
  if (cloud.organized()) {
    // Every step-th row and column, so that an image is sampled evenly in both directions.
    const std::size_t step = static_cast<std::size_t>(
        std::ceil(std::sqrt(static_cast<double>(cloud.count) / kMaxPoints)));
    for (std::size_t r = 0; r < cloud.height; r += step) {
      for (std::size_t c = 0; c < cloud.width; c += step) add(r * cloud.width + c);
    }
  } else {
    const std::size_t step = std::max<std::size_t>(1, (cloud.count + kMaxPoints - 1) / kMaxPoints);
    for (std::size_t i = 0; i < cloud.count; i += step) add(i);
  }
  // Each level's voxels twice the size of the one before, and one more for the coarsest
  // level's normals; parents[l][v]: the voxel of level l + 1 holding voxel v of level l.
  std::vector<std::vector<std::int32_t>> parents;
  for (int level = 1; level <= params_.levels; ++level) {
    const VoxelSums& finer = sums.back();
    VoxelSums coarser(finer.moments.size() / 4 + 16);
    std::vector<std::int32_t> parent(finer.moments.size());
    for (std::size_t v = 0; v < finer.moments.size(); ++v) {
      const std::uint64_t k = finer.key_of[v];
      parent[v] = coarser.at(
          encode(halvedDown(decode(k, 2)), halvedDown(decode(k, 1)), halvedDown(decode(k, 0))));
      coarser.moments[static_cast<std::size_t>(parent[v])].add(finer.moments[v]);
    }
    sums.push_back(std::move(coarser));
    parents.push_back(std::move(parent));
  }
  std::vector<Voxels> levels;
  for (std::size_t level = 0; level < static_cast<std::size_t>(params_.levels); ++level) {
    levels.push_back(finish(sums[level], params_.cell * static_cast<double>(1 << level),
                            sums[level + 1], parents[level]));
  }

  OdometryStep step;
  if (last_.empty()) {
    // The first frame (or the first after a reset) is the world.
    world_from_last_.setIdentity();
    last_motion_ = Motion();
    step.world_from_frame = world_from_last_;
    step.started = true;
    last_ = std::move(levels);
    return step;
  }
  // Samples of the moving frame at each level, then the motions tried from the best start.
  std::vector<std::vector<Eigen::Vector3d>> moving(levels.size());
  for (std::size_t level = 0; level < levels.size(); ++level) {
    for (std::size_t v : samplesOf(sums[level], params_.max_samples)) {
      moving[level].push_back(levels[level].centroid[v]);
    }
  }
  Motion best;
  double best_overlap = -1.0;
  const auto tryFrom = [&](const Motion& start) {
    Motion motion = start;
    double overlap = 0.0;
    if (align(moving, motion, overlap) && overlap > best_overlap) {
      best_overlap = overlap;
      best = motion;
    }
  };
  tryFrom(last_motion_);
  tryFrom(Motion());
  if (best_overlap < params_.min_overlap) {
    for (double deg : kYawSeedsDeg) {
      Motion start;
      start.yaw = deg * M_PI / 180.0;
      tryFrom(start);
    }
  }
  if (best_overlap < 0) {
    // Nothing aligned at all (too few voxels): the sensor is taken to move on as it did.
    best = last_motion_;
    best_overlap = 0.0;
  }
  step.overlap = best_overlap;
  step.tracked = best_overlap >= params_.min_overlap;
  Eigen::Isometry3d last_from_frame = Eigen::Isometry3d::Identity();
  last_from_frame.linear() = turn(best.yaw);
  last_from_frame.translation() = best.shift;
  world_from_last_ = world_from_last_ * last_from_frame;
  step.world_from_frame = world_from_last_;
  last_motion_ = best;
  last_ = std::move(levels);
  return step;
}

// Point-to-plane Gauss–Newton from `motion` (which takes the moving frame's points into the
// last frame's), coarse to fine; `overlap` as OdometryParams::min_overlap says. A turn δ and a
// shift δt are applied on the left: q ← Rz(δ) q + δt, so that ∂q/∂δ = (−q_y, q_x, 0).
bool SceneOdometry::align(const std::vector<std::vector<Eigen::Vector3d>>& moving, Motion& motion,
                          double& overlap) const {
  const double level_cos = std::cos(params_.level_tilt_deg * M_PI / 180.0);
  for (std::size_t level = moving.size(); level-- > 0;) {
    const Voxels& model = last_[level];
    const std::vector<Eigen::Vector3d>& samples = moving[level];
    // The turn is weighed in metres, as the shifts are: by the samples' mean distance from the
    // vertical through the origin (the turn moves them that far per radian).
    double radius_sq = 0.0;
    for (const Eigen::Vector3d& p : samples) radius_sq += p.head<2>().squaredNorm();
    const double radius =
        std::max(model.size, std::sqrt(radius_sq / std::max<std::size_t>(1, samples.size())));
    for (int iteration = 0; iteration < params_.iterations; ++iteration) {
      const Eigen::Matrix3d rotation = turn(motion.yaw);
      Eigen::Matrix4d h = Eigen::Matrix4d::Zero();
      Eigen::Vector4d g = Eigen::Vector4d::Zero();
      int pairs = 0, steep = 0;
      for (const Eigen::Vector3d& p : samples) {
        const Eigen::Vector3d q = rotation * p + motion.shift;
        double distance;
        const std::int32_t v = nearestFlat(model, q, distance);
        if (v < 0) continue;
        const Eigen::Vector3d& n = model.normal[static_cast<std::size_t>(v)];
        const double r = n.dot(q - model.centroid[static_cast<std::size_t>(v)]);
        // A horizontal surface (Eq 3's test) tells the height alone: its normal's tilt is
        // noise, and would pull the motion along it.
        const bool level = std::fabs(n.z()) >= level_cos;
        steep += level ? 0 : 1;
        const Eigen::Vector4d j =
            level ? Eigen::Vector4d(0, 0, 0, n.z())
                  : Eigen::Vector4d((n.y() * q.x() - n.x() * q.y()) / radius, n.x(), n.y(), n.z());
        const double w = 1.0 / std::max(1.0, std::fabs(r) / (kHuber * model.size));
        h.noalias() += w * j * j.transpose();
        g.noalias() += w * r * j;
        ++pairs;
      }
      if (pairs < kMinPairs) return false;
      // The shift along and the turn come from the surfaces that are not horizontal; with too
      // few of them in view (a floor alone, its far samples' noise aside) the height alone is
      // measured, and the rest stays where it started (Zhang, Kaess and Singh, ICRA 2016, on
      // directions a scene does not constrain).
      Eigen::Vector4d delta = Eigen::Vector4d::Zero();
      if (steep >= std::max(kMinPairs, static_cast<int>(kMinSteepShare * pairs))) {
        delta = -h.ldlt().solve(g);
      } else if (h(3, 3) > 0) {
        delta(3) = -g(3) / h(3, 3);
      }
      if (!delta.allFinite()) return false;
      delta(0) /= radius;
      motion.yaw += delta(0);
      motion.shift = turn(delta(0)) * motion.shift + delta.tail<3>();
      if (std::fabs(delta(0)) < 2e-4 && delta.tail<3>().norm() < 2e-4) break;
    }
  }
  const Voxels& finest = last_.front();
  const Eigen::Matrix3d rotation = turn(motion.yaw);
  int near = 0;
  for (const Eigen::Vector3d& p : moving.front()) {
    const Eigen::Vector3d q = rotation * p + motion.shift;
    double distance;
    const std::int32_t v = nearestFlat(finest, q, distance);
    if (v < 0) continue;
    // On the surface, as the alignment measures it (point to plane): along it, the centroids
    // of sparse samples (a 160-pixel image's) lie up to a voxel apart however well aligned.
    const std::size_t u = static_cast<std::size_t>(v);
    if (std::fabs(finest.normal[u].dot(q - finest.centroid[u])) < 0.5 * finest.size) ++near;
  }
  overlap = moving.front().empty()
                ? 0.0
                : static_cast<double>(near) / static_cast<double>(moving.front().size());
  return true;
}

}  // namespace hope
