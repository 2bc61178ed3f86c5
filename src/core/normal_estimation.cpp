#include "hope/normal_estimation.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <utility>

#include <Eigen/Eigenvalues>

#include "parallel.h"
#include "simd.h"

namespace hope {

namespace {

// Neighbours spread along a line fix only one direction: their "normal" is any vector across
// the line. Require the middle eigenvalue to carry at least this share of the largest one.
constexpr float kMinPlanarity = 0.05f;

}  // namespace

NormalNeighbourhood::NormalNeighbourhood(const VoxelGrid& grid, double radius_factor)
    : grid_(grid), max_dz_(static_cast<float>(2.0 * grid.rZ())) {
  // Column offsets (in cells) whose centres lie within radius_factor·r_xy.
  const int reach = static_cast<int>(std::floor(radius_factor));
  for (int dy = -reach; dy <= reach; ++dy) {
    for (int dx = -reach; dx <= reach; ++dx) {
      if (dx * dx + dy * dy <= radius_factor * radius_factor) offsets_.emplace_back(dx, dy);
    }
  }
  reach_z_ = static_cast<int>(std::ceil(max_dz_ / grid.rZ())) + 1;
}

namespace {

// The sums of one neighbourhood, in scalars: through the Moments struct the compiler stored all
// twelve after each neighbour. Each entry takes the same products in the same order as d·dᵀ
// would.
struct MomentSums {
  float sx = 0, sy = 0, sz = 0, sxx = 0, sxy = 0, sxz = 0, syy = 0, syz = 0, szz = 0;
  int count = 0;

  void add(float ex, float ey, float ez) {
    sx += ex, sy += ey, sz += ez;
    sxx += ex * ex, sxy += ex * ey, sxz += ex * ez;
    syy += ey * ey, syz += ey * ez, szz += ez * ez;
    ++count;
  }
  NormalNeighbourhood::Moments moments() const {
    NormalNeighbourhood::Moments m;
    m.sum = Eigen::Vector3f(sx, sy, sz);
    m.outer << sxx, sxy, sxz, sxy, syy, syz, sxz, syz, szz;
    m.count = count;
    return m;
  }
};

// The sums of the neighbours of the voxel whose centroid is `centre`, each taken relative to it
// and only when within max_dz in height: what moments() sums, for columnMoments' loop.
class NeighbourSums {
 public:
  NeighbourSums(const Eigen::Vector3f& centre, float max_dz);
  void add(const Eigen::Vector3f& q);
  NormalNeighbourhood::Moments moments() const;

 private:
#if HOPE_SSE2
  // In SSE2 lanes: s1_ = (Σex, Σey, Σez), s2_ = Σ e·ex = (Σex·ex, Σey·ex, Σez·ex), s3_ = Σ e·ey
  // and s4_ = Σ e·ez, of which MomentSums' sums are lanes (the products are the same numbers,
  // multiplication being commutative). The height test is a lane mask instead of a branch (a
  // voxel's neighbours pass and fail it in no predictable order): a neighbour that fails it adds
  // zeros, which leave every sum as it is (a sum of products from +0 is never -0), so the sums
  // are MomentSums' bit for bit.
  static __m128 lanes(const Eigen::Vector3f& q) {  // (x, y, z, 0)
    double xy;  // x and y as one 8-byte load (through memcpy: q is only 4-byte aligned)
    std::memcpy(&xy, q.data(), sizeof(xy));
    return _mm_movelh_ps(_mm_castpd_ps(_mm_set_sd(xy)), _mm_load_ss(q.data() + 2));
  }
  __m128 centre_, max_dz_;
  __m128 s1_ = _mm_setzero_ps(), s2_ = s1_, s3_ = s1_, s4_ = s1_;
  int count_ = 0;
#else
  Eigen::Vector3f centre_;
  float max_dz_;
  MomentSums sums_;
#endif
};

#if HOPE_SSE2
NeighbourSums::NeighbourSums(const Eigen::Vector3f& centre, float max_dz)
    : centre_(lanes(centre)), max_dz_(_mm_set1_ps(max_dz)) {}

void NeighbourSums::add(const Eigen::Vector3f& q) {
  const __m128 e = _mm_sub_ps(lanes(q), centre_);
  // In unless |ez| > max_dz, as the scalar test reads (not-greater: a NaN is in).
  const __m128 magnitude = _mm_castsi128_ps(_mm_set1_epi32(0x7fffffff));
  const __m128 in =
      _mm_cmpngt_ps(_mm_and_ps(_mm_shuffle_ps(e, e, _MM_SHUFFLE(2, 2, 2, 2)), magnitude), max_dz_);
  const __m128 d = _mm_and_ps(e, in);
  s1_ = _mm_add_ps(s1_, d);
  s2_ = _mm_add_ps(s2_, _mm_mul_ps(d, _mm_shuffle_ps(d, d, _MM_SHUFFLE(0, 0, 0, 0))));
  s3_ = _mm_add_ps(s3_, _mm_mul_ps(d, _mm_shuffle_ps(d, d, _MM_SHUFFLE(1, 1, 1, 1))));
  s4_ = _mm_add_ps(s4_, _mm_mul_ps(d, _mm_shuffle_ps(d, d, _MM_SHUFFLE(2, 2, 2, 2))));
  count_ += _mm_movemask_ps(in) & 1;
}

NormalNeighbourhood::Moments NeighbourSums::moments() const {
  alignas(16) float l1[4], l2[4], l3[4], l4[4];
  _mm_store_ps(l1, s1_), _mm_store_ps(l2, s2_), _mm_store_ps(l3, s3_), _mm_store_ps(l4, s4_);
  MomentSums sums;
  sums.sx = l1[0], sums.sy = l1[1], sums.sz = l1[2];
  sums.sxx = l2[0], sums.sxy = l2[1], sums.sxz = l2[2];
  sums.syy = l3[1], sums.syz = l3[2], sums.szz = l4[2];
  sums.count = count_;
  return sums.moments();
}
#else
NeighbourSums::NeighbourSums(const Eigen::Vector3f& centre, float max_dz)
    : centre_(centre), max_dz_(max_dz) {}

void NeighbourSums::add(const Eigen::Vector3f& q) {
  const float ex = q.x() - centre_.x(), ey = q.y() - centre_.y(), ez = q.z() - centre_.z();
  if (std::fabs(ez) > max_dz_) return;
  sums_.add(ex, ey, ez);
}

NormalNeighbourhood::Moments NeighbourSums::moments() const { return sums_.moments(); }
#endif

}  // namespace

NormalNeighbourhood::Moments NormalNeighbourhood::moments(std::size_t v) const {
  const Eigen::Vector3f p = grid_.centroid(v);
  const int cx = grid_.cellX(v), cy = grid_.cellY(v), cz = grid_.cellZ(v);
  // Offsets from p keep the sums small, so single precision stays accurate far from 0.
  MomentSums sums;
  const float max_dz = max_dz_;
  for (const auto& [dx, dy] : offsets_) {
    const auto range = grid_.columnVoxels(cx + dx, cy + dy);
    for (std::uint32_t u = grid_.firstAtOrAbove(range, cz - reach_z_); u < range.second; ++u) {
      if (grid_.cellZ(u) > cz + reach_z_) break;  // a column's voxels are sorted by z cell
      const Eigen::Vector3f& q = grid_.centroid(u);
      const float ex = q.x() - p.x(), ey = q.y() - p.y(), ez = q.z() - p.z();
      if (std::fabs(ez) > max_dz) continue;
      sums.add(ex, ey, ez);
    }
  }
  return sums.moments();
}

void NormalNeighbourhood::columnMoments(
    std::uint32_t first, std::uint32_t last, Moments* out,
    std::vector<std::pair<std::uint32_t, std::uint32_t>>& windows) const {
  if (first >= last) return;
  const int cx = grid_.cellX(first), cy = grid_.cellY(first);
  // windows[j]: the first voxel of neighbour column j not yet known to lie below the reach of
  // the current voxel, and the column's end.
  windows.resize(offsets_.size());
  for (std::size_t j = 0; j < offsets_.size(); ++j) {
    windows[j] = grid_.columnVoxels(cx + offsets_[j].first, cy + offsets_[j].second);
  }
  const float max_dz = max_dz_;
  const int reach_z = reach_z_;
  for (std::uint32_t v = first; v < last; ++v) {
    const int cz = grid_.cellZ(v);
    NeighbourSums sums(grid_.centroid(v), max_dz);
    for (auto& [begin, end] : windows) {
      // The voxels are taken in z order, so what lies below this voxel's reach lies below the
      // next one's too.
      while (begin < end && grid_.cellZ(begin) < cz - reach_z) ++begin;
      for (std::uint32_t u = begin; u < end; ++u) {
        if (grid_.cellZ(u) > cz + reach_z) break;
        sums.add(grid_.centroid(u));
      }
    }
    out[v - first] = sums.moments();
  }
}

Eigen::Matrix3f NormalNeighbourhood::Moments::covariance() const {
  const Eigen::Vector3f mean = sum / static_cast<float>(count);
  return outer / static_cast<float>(count) - mean * mean.transpose();
}

namespace detail {

namespace {
constexpr int kMaxNewtonSteps = 64;
}  // namespace

// The smallest eigenvalue λ0: Newton's method from 0, which lies at or below it (a covariance
// is positive semi-definite). Left of its smallest root a cubic with three real roots rises and
// is concave, so every step lands between the last point and the root: it climbs to λ0 and
// never passes it. c0 = λ0·λ1·λ2 below 0 is rounding in a singular matrix (neighbours on a
// line, or exactly flat): λ0 is 0 to within that rounding.
double smallestRoot(const CharacteristicCubic& cubic) {
  const double c2 = cubic.c2, c1 = cubic.c1, c0 = cubic.c0;
  double lambda0 = 0;
  for (int iteration = 0; iteration < kMaxNewtonSteps && c0 > 0; ++iteration) {
    const double f = ((lambda0 - c2) * lambda0 + c1) * lambda0 - c0;
    const double slope = (3 * lambda0 - 2 * c2) * lambda0 + c1;
    if (!(slope > 0)) break;
    const double step = -f / slope;
    // Convergence is quadratic: a step of 1e-12 leaves λ0 exact to double precision, far
    // below what turns a float normal.
    if (!(step > 1e-12 * c2)) break;
    lambda0 += step;
  }
  return lambda0;
}

// Two voxels at a time: each voxel's chain of divisions overlaps the other's, and the loop's
// exit is mispredicted once for two voxels instead of once for each.
void smallestRoots(const CharacteristicCubic& a, const CharacteristicCubic& b, double& root_a,
                   double& root_b) {
#if HOPE_SSE2
  const __m128d c2 = _mm_setr_pd(a.c2, b.c2), c1 = _mm_setr_pd(a.c1, b.c1);
  const __m128d c0 = _mm_setr_pd(a.c0, b.c0);
  const __m128d zero = _mm_setzero_pd(), three = _mm_set1_pd(3), two = _mm_set1_pd(2);
  const __m128d sign = _mm_set1_pd(-0.0), tolerance = _mm_mul_pd(_mm_set1_pd(1e-12), c2);
  __m128d lambda0 = zero;
  __m128d running = _mm_cmpgt_pd(c0, zero);
  for (int iteration = 0; iteration < kMaxNewtonSteps && _mm_movemask_pd(running) != 0;
       ++iteration) {
    const __m128d f = _mm_sub_pd(
        _mm_mul_pd(_mm_add_pd(_mm_mul_pd(_mm_sub_pd(lambda0, c2), lambda0), c1), lambda0), c0);
    const __m128d slope = _mm_add_pd(
        _mm_mul_pd(_mm_sub_pd(_mm_mul_pd(three, lambda0), _mm_mul_pd(two, c2)), lambda0), c1);
    running = _mm_and_pd(running, _mm_cmpgt_pd(slope, zero));
    const __m128d step = _mm_div_pd(_mm_xor_pd(f, sign), slope);  // -f / slope
    running = _mm_and_pd(running, _mm_cmpgt_pd(step, tolerance));
    lambda0 = _mm_add_pd(lambda0, _mm_and_pd(running, step));  // + 0 where stopped
  }
  alignas(16) double roots[2];
  _mm_store_pd(roots, lambda0);
  root_a = roots[0];
  root_b = roots[1];
#else
  root_a = smallestRoot(a);
  root_b = smallestRoot(b);
#endif
}

}  // namespace detail

namespace {

// planeNormal in three steps (the cubic, its smallest root, the normal), so that estimateNormals
// can take the middle one two voxels at a time. False when the covariance fixes no plane, before
// any solving.
bool characteristicCubic(const Eigen::Matrix3f& covariance, detail::CharacteristicCubic& cubic) {
  double scale = 0;
  for (int i = 0; i < 9; ++i) scale = std::max(scale, std::fabs(double{covariance(i)}));
  if (!(scale > 0) || !std::isfinite(scale)) return false;
  const double inverse = 1.0 / scale;
  const double a00 = covariance(0, 0) * inverse, a01 = covariance(0, 1) * inverse;
  const double a02 = covariance(0, 2) * inverse, a11 = covariance(1, 1) * inverse;
  const double a12 = covariance(1, 2) * inverse, a22 = covariance(2, 2) * inverse;
  const double c2 = a00 + a11 + a22;
  const double c1 = a00 * a11 + a00 * a22 + a11 * a22 - a01 * a01 - a02 * a02 - a12 * a12;
  const double c0 =
      a00 * (a11 * a22 - a12 * a12) - a01 * (a01 * a22 - a12 * a02) + a02 * (a01 * a12 - a11 * a02);
  cubic = {a00, a01, a02, a11, a12, a22, c2, c1, c0};
  // Most voxels of a sparse scan see their neighbours on one scan line. With
  // λ0 <= λ1 <= λ2: λ2 >= c2 / 3 and λ1·λ2 <= c1, so λ1 / λ2 <= 9·c1 / c2²; below the
  // planarity share that settles it without solving (where Newton's method would crawl
  // towards the double root λ0 ≈ λ1 ≈ 0).
  return 9 * c1 > kMinPlanarity * c2 * c2;
}

// The normal from the cubic and its smallest root λ0.
bool normalFromRoot(const Eigen::Matrix3f& covariance, const detail::CharacteristicCubic& cubic,
                    double lambda0, Eigen::Vector3f& normal) {
  // λ1 and λ2 from their sum and product (the roots of the cubic divided by λ − λ0); the
  // smaller one as product / larger, free of cancellation.
  const double sum = cubic.c2 - lambda0;
  const double product = std::max(0.0, cubic.c1 - lambda0 * sum);
  const double lambda2 = 0.5 * sum + std::sqrt(std::max(0.0, 0.25 * sum * sum - product));
  const double lambda1 = lambda2 > 0 ? product / lambda2 : 0.0;
  if (!(lambda1 > kMinPlanarity * lambda2)) return false;  // a line, a point or a blob's rim
  // The eigenvector of λ0 is orthogonal to every row of A − λ0·I: the largest cross product of
  // two rows. It is ill-defined only where λ0 nearly equals λ1 (a round blob), which the
  // general solver settles.
  const Eigen::Vector3d r0(cubic.a00 - lambda0, cubic.a01, cubic.a02),
      r1(cubic.a01, cubic.a11 - lambda0, cubic.a12), r2(cubic.a02, cubic.a12, cubic.a22 - lambda0);
  Eigen::Vector3d best = r0.cross(r1);
  for (const Eigen::Vector3d& candidate : {r0.cross(r2), r1.cross(r2)}) {
    if (candidate.squaredNorm() > best.squaredNorm()) best = candidate;
  }
  if (!(best.squaredNorm() > 1e-8 * lambda2 * lambda2 * lambda2 * lambda2)) {
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3f> solver;
    solver.computeDirect(covariance);
    const Eigen::Vector3f& eigenvalues = solver.eigenvalues();  // ascending
    if (!(eigenvalues(1) > kMinPlanarity * eigenvalues(2))) return false;
    normal = solver.eigenvectors().col(0);
    return normal.allFinite() && normal.squaredNorm() >= 0.5f;
  }
  normal = (best / best.norm()).cast<float>();
  return true;
}

}  // namespace

bool planeNormal(const Eigen::Matrix3f& covariance, Eigen::Vector3f& normal) {
  detail::CharacteristicCubic cubic;
  if (!characteristicCubic(covariance, cubic)) return false;
  return normalFromRoot(covariance, cubic, detail::smallestRoot(cubic), normal);
}

void estimateNormals(const VoxelGrid& grid, double radius_factor,
                     std::vector<Eigen::Vector3f>& normals, int threads) {
  const std::size_t num_voxels = grid.numVoxels();
  const float nan = std::numeric_limits<float>::quiet_NaN();
  normals.assign(num_voxels, Eigen::Vector3f(nan, nan, nan));
  const NormalNeighbourhood neighbourhood(grid, radius_factor);
  // Column by column: each share takes the columns that begin in its range of voxels. Every
  // voxel's normal depends on its neighbourhood alone, so the split changes nothing.
  parallel::forShares(
      num_voxels, parallel::resolve(threads), 2048,
      [&](int /*share*/, std::size_t begin, std::size_t end) {
        std::vector<NormalNeighbourhood::Moments> column_moments;
        std::vector<std::pair<std::uint32_t, std::uint32_t>> windows;
        struct Solving {
          std::uint32_t index;
          Eigen::Matrix3f covariance;
          detail::CharacteristicCubic cubic;
          double lambda0;
        };
        std::vector<Solving> solving;
        std::size_t v = begin;
        // A column that began in the previous share is that share's.
        while (v > 0 && v < end && grid.column(v) == grid.column(v - 1)) ++v;
        while (v < end) {
          const auto column = grid.columnVoxels(grid.cellX(v), grid.cellY(v));
          column_moments.resize(column.second - column.first);
          neighbourhood.columnMoments(column.first, column.second, column_moments.data(), windows);
          // planeNormal of each voxel, its Newton steps two voxels at a time.
          solving.clear();
          for (std::uint32_t u = column.first; u < column.second; ++u) {
            const NormalNeighbourhood::Moments& m = column_moments[u - column.first];
            if (m.count < 3) continue;
            Solving voxel{u, m.covariance(), {}, 0.0};
            if (characteristicCubic(voxel.covariance, voxel.cubic)) solving.push_back(voxel);
          }
          std::size_t k = 0;
          for (; k + 1 < solving.size(); k += 2) {
            detail::smallestRoots(solving[k].cubic, solving[k + 1].cubic, solving[k].lambda0,
                                  solving[k + 1].lambda0);
          }
          if (k < solving.size()) solving[k].lambda0 = detail::smallestRoot(solving[k].cubic);
          for (const Solving& voxel : solving) {
            Eigen::Vector3f n;
            if (!normalFromRoot(voxel.covariance, voxel.cubic, voxel.lambda0, n)) continue;
            n.normalize();
            normals[voxel.index] = n.z() < 0 ? Eigen::Vector3f(-n) : n;
          }
          v = column.second;
        }
      });
}

}  // namespace hope
