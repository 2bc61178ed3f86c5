#include "hope/standing_objects.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numeric>
#include <sstream>
#include <stdexcept>
#include <utility>

#include <Eigen/Geometry>

#include "cell_keys.h"
#include "hope/convex_hull.h"
#include "hope/crease_splitting.h"
#include "hope/obstacle_points.h"

namespace hope {

void validate(const ObjectParams& params) {
  if (!(params.max_height > 0 && params.max_height <= 100)) {
    std::ostringstream msg;
    msg << "object max_height = " << params.max_height << " is out of range (0, 100] m";
    throw std::invalid_argument(msg.str());
  }
  if (!(params.max_top_height > 0 && params.max_top_height <= 100)) {
    std::ostringstream msg;
    msg << "object max_top_height = " << params.max_top_height << " is out of range (0, 100] m";
    throw std::invalid_argument(msg.str());
  }
  if (params.noise) validate(*params.noise, "object noise");
  if (params.min_points < 1 || params.min_points > 100000000) {
    throw std::invalid_argument("object min_points = " + std::to_string(params.min_points) +
                                " is out of range [1, 1e8]");
  }
}

namespace {

// Where a plane can carry things: its occupied xy cells with their holes filled (objects
// occlude the surface they stand on) and one cell around them (an object overhanging the
// edge, the mixed pixels at its foot), as a mask over the plane's bounding box; and, where
// nothing is seen below the plane, the convex hull of its cells (see withinHull).
class SupportArea {
 public:
  // Cells along the longer side at most: a kilometre of merged map at r_xy is coarsened rather
  // than given a mask of 400 MB.
  static constexpr double kMaxSide = 4000;

  SupportArea(const HorizontalPlane& plane, const Eigen::Vector3d& local_origin, double cell)
      : cell_(std::max(
            cell,
            std::max(plane.bbox[2] - plane.bbox[0], plane.bbox[3] - plane.bbox[1]) / kMaxSide)) {
    // One cell of border on each side, so that the flood from the border reaches around.
    // In cells of cell_, the coarsened size every lookup (cellOf) uses.
    x0_ = static_cast<long>(std::floor((plane.bbox[0] - local_origin.x()) / cell_)) - 2;
    y0_ = static_cast<long>(std::floor((plane.bbox[1] - local_origin.y()) / cell_)) - 2;
    width_ = static_cast<long>(std::floor((plane.bbox[2] - local_origin.x()) / cell_)) - x0_ + 3;
    height_ = static_cast<long>(std::floor((plane.bbox[3] - local_origin.y()) / cell_)) - y0_ + 3;
    mask_.assign(static_cast<std::size_t>(width_ * height_), 0);
  }
  // Something was seen below the plane's height at (x, y): the plane is not there.
  void markBelow(float x, float y) {
    long ix, iy;
    if (cellOf(x, y, ix, iy)) {
      if (below_.empty()) below_.assign(mask_.size(), 0);
      below_[iy * width_ + ix] = 1;
    }
  }
  void markOccupied(float x, float y) {
    long ix, iy;  // not on the border, so that the flood from it reaches around
    if (cellOf(x, y, ix, iy) && ix > 0 && iy > 0 && ix < width_ - 1 && iy < height_ - 1) {
      mask_[iy * width_ + ix] = 1;
    }
  }
  // After every occupied cell was marked: fill the holes, grow by one cell.
  void finish() {
    // Cells reachable from the border without crossing an occupied cell are outside (marked
    // kOutside in the mask); every other cell is the plane or a hole in it. Filled run by run
    // along the rows (a scanline fill): a street scan's ground holds half a million cells, and
    // a push per cell took milliseconds. The border ring is never occupied (markOccupied), so
    // one seed on it reaches all of it.
    if (mask_.empty()) return;
    constexpr std::uint8_t kOutside = 2;
    std::uint8_t* cells = mask_.data();
    std::vector<long> seeds{0};
    while (!seeds.empty()) {
      const long k = seeds.back();
      seeds.pop_back();
      if (cells[k]) continue;
      const long row = k - k % width_;
      long left = k, right = k;
      while (left > row && !cells[left - 1]) --left;
      while (right < row + width_ - 1 && !cells[right + 1]) ++right;
      std::fill(cells + left, cells + right + 1, kOutside);
      // The free runs above and below it, each seeded once.
      for (const long step : {-width_, width_}) {
        if (row + step < 0 || row + step >= static_cast<long>(mask_.size())) continue;
        bool in_run = false;
        for (long n = left + step; n <= right + step; ++n) {
          const bool open = !cells[n];
          if (open && !in_run) seeds.push_back(n);
          in_run = open;
        }
      }
    }
    // The convex hull of the occupied cells' corners: a bay of the plane that its edge does not
    // enclose (the back of a table hidden by the things on it, out to its far edge) is still
    // under the plane.
    // Each row's first and last occupied cells hold the corners that can be on it.
    std::vector<Eigen::Vector2d> corners;
    for (long y = 0; y < height_; ++y) {
      const auto row = mask_.begin() + y * width_;
      const auto first = std::find(row, row + width_, 1);
      if (first == row + width_) continue;
      const long x_first = first - row;
      long x_last = width_ - 1;
      while (row[x_last] != 1) --x_last;
      for (const long cy : {y, y + 1}) {
        corners.emplace_back((x0_ + x_first) * cell_, (y0_ + cy) * cell_);
        corners.emplace_back((x0_ + x_last + 1) * cell_, (y0_ + cy) * cell_);
      }
    }
    hull_ = convexHull2D(std::move(corners));
    // Grown by one cell: a cell is the area's when a cell of its 3 × 3 block is not outside,
    // found along the rows, then down the columns (at the mask's edge a cell stands in for its
    // missing neighbour).
    std::vector<std::uint8_t> along_row(mask_.size());
    const long last = width_ - 1;
    for (long y = 0; y < height_; ++y) {
      const std::uint8_t* in = cells + y * width_;
      std::uint8_t* near = along_row.data() + y * width_;
      near[0] = (in[0] & in[std::min(1L, last)]) != kOutside;
      for (long x = 1; x < last; ++x) near[x] = (in[x - 1] & in[x] & in[x + 1]) != kOutside;
      near[last] = (in[std::max(last - 1, 0L)] & in[last]) != kOutside;
    }
    for (long y = 0; y < height_; ++y) {
      const std::uint8_t* middle = along_row.data() + y * width_;
      const std::uint8_t* above = y > 0 ? middle - width_ : middle;
      const std::uint8_t* below = y + 1 < height_ ? middle + width_ : middle;
      std::uint8_t* grown = cells + y * width_;
      for (long x = 0; x < width_; ++x) grown[x] = above[x] | middle[x] | below[x];
    }
  }
  // Within `reach` metres of the area's bounding box.
  bool near(float x, float y, double reach) const {
    const double lo_x = (x0_ + 1) * cell_ - reach, hi_x = (x0_ + width_ - 1) * cell_ + reach;
    const double lo_y = (y0_ + 1) * cell_ - reach, hi_y = (y0_ + height_ - 1) * cell_ + reach;
    return x >= lo_x && x <= hi_x && y >= lo_y && y <= hi_y;
  }
  // From now on only what lies within `margin` of the plane's own points' box in xy is over
  // it (see the raised planes in findStandingObjects).
  void tightenTo(const HorizontalPlane& plane, const Eigen::Vector3d& local_origin, double margin) {
    tight_ = true;
    tight_box_ = {static_cast<float>(plane.bbox[0] - local_origin.x() - margin),
                  static_cast<float>(plane.bbox[1] - local_origin.y() - margin),
                  static_cast<float>(plane.bbox[2] - local_origin.x() + margin),
                  static_cast<float>(plane.bbox[3] - local_origin.y() + margin)};
  }
  // Within the convex hull of the plane's cells (and within the tightened box, if any), where
  // nothing was seen below the plane's height: a bay its edge does not enclose, hidden by the
  // things standing in it (a chair's back in front of a desk hides the desk's edge, but its
  // seat and legs below the desk's height say the desk is not there).
  bool withinHull(float x, float y) const {
    long ix, iy;
    if (hull_.size() < 3 || !near(x, y, 0) || outsideTightBox(x, y) || !cellOf(x, y, ix, iy)) {
      return false;
    }
    // A thing's sides seen below the plane mark the rim of its footprint: the cells next to
    // them are its inside.
    for (long dy = -1; dy <= 1 && !below_.empty(); ++dy) {
      for (long dx = -1; dx <= 1; ++dx) {
        const long nx = ix + dx, ny = iy + dy;
        if (nx >= 0 && ny >= 0 && nx < width_ && ny < height_ && below_[ny * width_ + nx]) {
          return false;
        }
      }
    }
    for (std::size_t k = 0; k < hull_.size(); ++k) {
      const Eigen::Vector2d& a = hull_[k];
      const Eigen::Vector2d& b = hull_[(k + 1) % hull_.size()];
      if ((b.x() - a.x()) * (y - a.y()) - (b.y() - a.y()) * (x - a.x()) < 0) return false;
    }
    return true;
  }
  bool contains(float x, float y) const {
    long ix, iy;
    return !outsideTightBox(x, y) && cellOf(x, y, ix, iy) && mask_[iy * width_ + ix];
  }

 private:
  // The cell holding (x, y), false when it is outside the mask.
  bool cellOf(float x, float y, long& ix, long& iy) const {
    ix = static_cast<long>(std::floor(x / cell_)) - x0_;
    iy = static_cast<long>(std::floor(y / cell_)) - y0_;
    return ix >= 0 && iy >= 0 && ix < width_ && iy < height_;
  }
  bool outsideTightBox(float x, float y) const {
    return tight_ &&
           (x < tight_box_[0] || y < tight_box_[1] || x > tight_box_[2] || y > tight_box_[3]);
  }
  double cell_;
  long x0_ = 0, y0_ = 0, width_ = 0, height_ = 0;
  std::vector<std::uint8_t> mask_;
  std::vector<Eigen::Vector2d> hull_;
  std::vector<std::uint8_t> below_;  // empty: nothing below anywhere
  bool tight_ = false;
  std::array<float, 4> tight_box_{};
};

// A point's cell on the object grid, with the plane it stands on, as one key: 20 bits for x
// and y and 16 for z (±5 km and ±300 m at 1 cm) and 8 for the plane.
constexpr int kMaxSupportPlanes = 255;
// How far past a plane's edge an object standing on it may reach (a plate or a box jutting
// out), metres.
constexpr double kOverhang = 0.15;
// Cell levels of r_z / 4 · 2^level: 5 mm to 64 cm at the default r_z.
constexpr int kLevels = 8;
bool cellKey(const Eigen::Vector3f& p, double cell, int plane, std::uint64_t& key) {
  const double ix = std::floor(p.x() / cell), iy = std::floor(p.y() / cell),
               iz = std::floor(p.z() / cell);
  if (std::fabs(ix) >= (1 << 19) || std::fabs(iy) >= (1 << 19) || std::fabs(iz) >= (1 << 15)) {
    return false;
  }
  key = (static_cast<std::uint64_t>(static_cast<long>(ix) + (1 << 19)) << 44) |
        (static_cast<std::uint64_t>(static_cast<long>(iy) + (1 << 19)) << 24) |
        (static_cast<std::uint64_t>(static_cast<long>(iz) + (1 << 15)) << 8) |
        static_cast<std::uint64_t>(plane);
  return true;
}

std::uint64_t neighbourKey(std::uint64_t key, int dx, int dy, int dz) {
  // Unsigned arithmetic, which wraps by definition (a negative step is its two's complement);
  // a shifted negative int would be undefined.
  const std::uint64_t step = static_cast<std::uint64_t>(dx) * (std::uint64_t{1} << 44) +
                             static_cast<std::uint64_t>(dy) * (std::uint64_t{1} << 24) +
                             static_cast<std::uint64_t>(dz) * (std::uint64_t{1} << 8);
  return key + step;
}

// The key of the cell `level` levels coarser (each cell 2^level times as large) that holds
// the cell of `key`: each coordinate halved `level` times. Its bias (2^19 for x and y, 2^15 for
// z) is halved too, the same for every cell, so neighbours stay one step apart.
std::uint64_t coarser(std::uint64_t key, int level) {
  if (level == 0) return key;
  const std::uint64_t x = key >> 44, y = (key >> 24) & 0xfffff, z = (key >> 8) & 0xffff;
  return ((x >> level) << 44) | ((y >> level) << 24) | ((z >> level) << 8) | (key & 0xff);
}

// The smallest-area rectangle around a convex polygon has a side along one of its edges.
void smallestUprightBox(const std::vector<Eigen::Vector2d>& hull, Eigen::Vector2d& centre,
                        double& yaw, Eigen::Vector2d& size) {
  double best_area = std::numeric_limits<double>::infinity();
  const std::size_t n = hull.size();
  for (std::size_t i = 0; i < std::max<std::size_t>(n, 1); ++i) {
    Eigen::Vector2d along =
        n >= 2 ? Eigen::Vector2d(hull[(i + 1) % n] - hull[i]) : Eigen::Vector2d::UnitX();
    if (along.norm() < 1e-12) continue;
    along.normalize();
    const Eigen::Vector2d across(-along.y(), along.x());
    double lo_u = std::numeric_limits<double>::infinity(), hi_u = -lo_u, lo_v = lo_u, hi_v = -lo_u;
    for (const Eigen::Vector2d& q : hull) {
      lo_u = std::min(lo_u, q.dot(along)), hi_u = std::max(hi_u, q.dot(along));
      lo_v = std::min(lo_v, q.dot(across)), hi_v = std::max(hi_v, q.dot(across));
    }
    const double area = (hi_u - lo_u) * (hi_v - lo_v);
    if (area < best_area) {
      best_area = area;
      centre = along * (lo_u + hi_u) / 2 + across * (lo_v + hi_v) / 2;
      size = Eigen::Vector2d(hi_u - lo_u, hi_v - lo_v);
      yaw = std::atan2(along.y(), along.x());
    }
  }
  if (!std::isfinite(best_area)) {  // one point, or all at one place
    centre = n ? hull.front() : Eigen::Vector2d::Zero();
    size = Eigen::Vector2d::Zero();
    yaw = 0;
  }
  if (yaw < 0) yaw += M_PI;
  if (yaw >= M_PI) yaw -= M_PI;
}

// Each object's points moved to object target[o] (-1: to none), and the objects left
// numbered afresh in the order of their first point. Returns, for each new object, the old
// object it is.
std::vector<std::int32_t> renumberObjects(const std::vector<std::int32_t>& target,
                                          std::vector<std::int32_t>& object_of_point) {
  std::vector<std::int32_t> renumbered(target.size(), -1), origin;
  for (std::int32_t& o : object_of_point) {
    if (o < 0) continue;
    const std::int32_t to = target[o];
    if (to >= 0 && renumbered[to] < 0) {
      renumbered[to] = static_cast<std::int32_t>(origin.size());
      origin.push_back(to);
    }
    o = to >= 0 ? renumbered[to] : -1;
  }
  return origin;
}

// values[origin[k]] for each k: a per-object table after renumberObjects.
template <class T>
std::vector<T> picked(const std::vector<T>& values, const std::vector<std::int32_t>& origin) {
  std::vector<T> out;
  out.reserve(origin.size());
  for (std::int32_t o : origin) out.push_back(values[o]);
  return out;
}

// Objects that are pieces of one thing, joined before the crease split (each joined object
// keeps the larger crease patch of its pieces, and is joined across a gap when any was); the
// objects are then numbered afresh in the order of their first point.
// - A side beside a top: a taller object pushed against a lower one rises beside the lower
//   one's top, and what of it stands over that top's box (the strip along the edge they share)
//   was given to the top. Such a part, on a raised plane, whose xy box touches that of an
//   object on a lower plane rising higher than the raised plane, is that object's (the highest
//   such). A cup on a book is not joined to the book's sides, which rise no higher than it.
// - A side between two tops: a part on a raised plane that rises to another top of the thing
//   that plane is a top of, within a vertical cell (2 · margin), is that thing's side between
//   them (a stair block's riser whose middle something nearer hides). Across a gap. A cup on a
//   book reaches no other top of the book.
void joinPiecesOfOneThing(const AlignedPoints& points, const std::vector<HorizontalPlane>& planes,
                          const std::vector<std::int32_t>& point_labels,
                          const std::vector<std::uint8_t>& raised,
                          const Eigen::Vector3d& local_origin, double margin,
                          std::vector<std::int32_t>& object_of_point,
                          std::vector<int>& object_plane, std::vector<double>& object_patch,
                          std::vector<std::uint8_t>& joined_across_gap) {
  const std::size_t n = object_plane.size();
  if (n == 0 || std::find(raised.begin(), raised.end(), 1) == raised.end()) return;
  std::vector<Eigen::AlignedBox3f> box(n);
  // Per raised plane and object, how many of the plane's points the object holds; the object
  // holding most is the thing the plane is a top of.
  std::vector<std::size_t> top_points(planes.size() * n, 0);
  for (std::size_t i = 0; i < object_of_point.size(); ++i) {
    const std::int32_t p = point_labels[i], o = object_of_point[i];
    if (o < 0) continue;
    box[o].extend(points[i]);
    if (p >= 0 && raised[p]) ++top_points[static_cast<std::size_t>(p) * n + o];
  }
  std::vector<std::int32_t> thing_of_top(planes.size(), -1);
  for (std::size_t p = 0; p < planes.size(); ++p) {
    const auto first = top_points.begin() + static_cast<std::ptrdiff_t>(p * n);
    const auto most = std::max_element(first, first + static_cast<std::ptrdiff_t>(n));
    if (*most > 0) thing_of_top[p] = static_cast<std::int32_t>(most - first);
  }
  // Each object joined into another (into[o] != o) or its own thing; joins go to a thing's
  // root, and never to the object itself, so they form a forest.
  std::vector<std::int32_t> into(n);
  std::iota(into.begin(), into.end(), 0);
  const auto thingOf = [&](std::int32_t o) {
    while (o >= 0 && into[o] != o) o = into[o];
    return o;
  };
  std::vector<std::uint8_t> across(n, 0);  // joined across a hidden gap
  bool joined = false;
  const auto join = [&](std::size_t o, std::int32_t thing, bool across_gap) {
    const std::int32_t root = thingOf(thing), own = thingOf(static_cast<std::int32_t>(o));
    if (root < 0 || root == own) return;
    into[own] = root;
    across[own] = across[own] || across_gap;
    joined = true;
  };
  for (std::size_t r = 0; r < n; ++r) {
    if (!raised[object_plane[r]]) continue;
    const double top_height = planes[object_plane[r]].height - local_origin.z();
    // Of the objects it touches that rise past the top, the highest: the one it is a side of.
    float highest = static_cast<float>(top_height + margin);
    std::int32_t side_of = -1;
    for (std::size_t l = 0; l < n; ++l) {
      if (l == r || planes[object_plane[l]].height >= planes[object_plane[r]].height ||
          box[l].max().z() <= highest) {
        continue;
      }
      const Eigen::Vector2f gap = (box[r].min().head<2>() - box[l].max().head<2>())
                                      .cwiseMax(box[l].min().head<2>() - box[r].max().head<2>());
      if (gap.maxCoeff() <= margin) {
        side_of = static_cast<std::int32_t>(l);
        highest = box[l].max().z();
      }
    }
    if (side_of >= 0) join(r, side_of, false);
  }
  for (std::size_t r = 0; r < n; ++r) {
    if (!raised[object_plane[r]] || into[r] != static_cast<std::int32_t>(r)) continue;
    const std::int32_t thing = thingOf(thing_of_top[object_plane[r]]);
    if (thing < 0 || thing == static_cast<std::int32_t>(r)) continue;
    for (std::size_t q = 0; q < planes.size(); ++q) {
      if (planes[q].height > planes[object_plane[r]].height && thingOf(thing_of_top[q]) == thing &&
          std::fabs(box[r].max().z() - (planes[q].height - local_origin.z())) <= 2 * margin) {
        join(r, thing, true);
        break;
      }
    }
  }
  if (!joined) return;
  for (std::size_t o = 0; o < n; ++o) into[o] = thingOf(static_cast<std::int32_t>(o));
  std::vector<double> patch = object_patch;
  std::vector<std::uint8_t> gap = joined_across_gap;
  for (std::size_t o = 0; o < n; ++o) {
    patch[into[o]] = std::max(patch[into[o]], object_patch[o]);
    gap[into[o]] |= joined_across_gap[o] | across[o];
  }
  const std::vector<std::int32_t> origin = renumberObjects(into, object_of_point);
  object_plane = picked(object_plane, origin);
  object_patch = picked(patch, origin);
  joined_across_gap = picked(gap, origin);
}

// Whether a plane (its centroid `centre`, relative to the local origin) stands over `area`:
// its centroid is, or any corner of its `hull`.
bool standsOver(const SupportArea& area, const Eigen::Vector3d& centre,
                const std::vector<Eigen::Vector3d>& hull, const Eigen::Vector3d& local_origin) {
  if (area.contains(static_cast<float>(centre.x()), static_cast<float>(centre.y()))) return true;
  for (const Eigen::Vector3d& corner : hull) {
    const Eigen::Vector3d q = corner - local_origin;
    if (area.contains(static_cast<float>(q.x()), static_cast<float>(q.y()))) return true;
  }
  return false;
}

// Whether the eye sees at least `enough` points through the space under `hull` (a plane's
// convex hull, counter-clockwise, relative to the local origin) at `height`, at least `inset`
// inside its edges: their rays cross that height there, and they lie past it by more than
// their noise (`margin` at least), so that the top's own samples do not count. Something whose
// top the hull is, standing on a plane below `height`, would fill that space, and no ray would
// pass it.
bool seenThroughUnder(const AlignedPoints& points, const std::vector<Eigen::Vector3d>& hull,
                      const Eigen::Vector3d& local_origin, double height, double inset,
                      const Eigen::Vector3f& eye, const RangeNoise& noise, double margin,
                      std::size_t enough) {
  if (hull.size() < 3) return false;
  std::vector<Eigen::Vector2d> corner(hull.size());
  Eigen::AlignedBox2d box;
  for (std::size_t k = 0; k < hull.size(); ++k) {
    corner[k] = (hull[k] - local_origin).head<2>();
    box.extend(corner[k]);
  }
  // Within the hull's edges by `inset` (the caller has tested its box).
  const auto inside = [&](const Eigen::Vector2d& x) {
    for (std::size_t k = 0; k < corner.size(); ++k) {
      const Eigen::Vector2d edge = corner[(k + 1) % corner.size()] - corner[k];
      const Eigen::Vector2d to_x = x - corner[k];
      const double length = edge.norm();
      if (length > 0 && (edge.x() * to_x.y() - edge.y() * to_x.x()) < inset * length) return false;
    }
    return true;
  };
  const double eye_above = eye.z() - height;
  std::size_t seen = 0;
  for (std::size_t i = 0; i < points.size(); ++i) {
    const Eigen::Vector3f q = points[i];
    const double q_above = q.z() - height;
    if (!(eye_above * q_above < 0) || !q.allFinite()) continue;  // the ray does not cross it
    // The crossing x = eye + (eye_above / w) (q − eye), w = eye_above − q_above, tested
    // against the hull's box times |w| first: no division for the many rays that miss it.
    const double w = std::fabs(eye_above - q_above);
    const double sign = eye_above > 0 ? 1.0 : -1.0;
    const Eigen::Vector2d x_w = eye.head<2>().cast<double>() * w +
                                sign * eye_above * (q.head<2>() - eye.head<2>()).cast<double>();
    if ((x_w.array() < box.min().array() * w).any() ||
        (x_w.array() > box.max().array() * w).any() || !inside(x_w / w)) {
      continue;
    }
    const Eigen::Vector3f ray = q - eye;
    const double range = ray.norm();
    const double vertical = range > 0 ? 3 * noise.at(range) * std::fabs(ray.z()) / range : 0.0;
    if (std::fabs(q_above) > std::max(margin, vertical) && ++seen >= enough) return true;
  }
  return false;
}

// Objects that a split or a join left with fewer than `least` points are noise: their points
// go back to no object, and the others are numbered afresh in the order of their first point.
void dropSmallObjects(std::size_t least, std::vector<std::int32_t>& object_of_point,
                      std::vector<int>& object_plane) {
  std::vector<std::size_t> count(object_plane.size(), 0);
  for (std::int32_t o : object_of_point) {
    if (o >= 0) ++count[o];
  }
  std::vector<std::int32_t> target(object_plane.size());
  for (std::size_t o = 0; o < target.size(); ++o) {
    target[o] = count[o] < least ? -1 : static_cast<std::int32_t>(o);
  }
  object_plane = picked(object_plane, renumberObjects(target, object_of_point));
}

// The planes that can carry things, highest first (a point belongs to the highest one below
// it): where each can carry, which stand on which as a thing's top, and each one's cells.
struct Supports {
  std::vector<int> plane;     // support s's plane index
  std::vector<int> of_plane;  // plane p's support, or -1
  std::vector<SupportArea> areas;
  std::vector<std::uint8_t> raised;    // per plane: the top of a thing on a lower plane
  std::vector<std::uint8_t> carrying;  // per support: large enough to carry things
  std::vector<int> stands_on;          // the support a raised plane's on, or -1
  std::vector<int> tall_top_over;      // the support a tall thing's top stands on, or -1
  std::vector<double> local_height;    // relative to the local origin
  std::vector<double> sample_cell;     // the finest cell of the objects on it
  double finest_cell = 0.0;            // the finest of all: r_z / 4 (see findSupports)
};

// The object points: each with its support, its level, and whether it seeds objects.
// Points over a plane's area seed its objects; points beside it at object height (the part
// of a box that overhangs the edge) join an object only through the cells they touch.
struct ObjectPoint {
  std::uint32_t index;
  std::uint8_t support;
  std::uint8_t level;
  bool seed;
  std::int16_t under_top;  // the tall top it rises under past max_height, or -1
  float noise;             // the sensor's range noise σ at the point (0 without a viewpoint)
};

// A thing's foot: its points within the plane's margin or in the plane's own voxels, but
// higher above it than three σ of the sensor's noise seen vertically (the plane's own
// samples stay below that). They seed and join nothing (two things close together would
// touch through them); once the objects are found, each goes to the one object whose lowest
// points touch it (see the feet after the crease split). Only with a known sensor position,
// which σ needs.
struct FootPoint {
  std::uint32_t index;
  std::uint8_t support;
};

// The supports, their areas (what is seen below each marks where it is not), the planes that
// stand on a lower one as a thing's top, and the cells their objects are found on.
Supports findSupports(const AlignedPoints& points, const std::vector<HorizontalPlane>& planes,
                      const std::vector<std::int32_t>& point_labels,
                      const Eigen::Vector3d& local_origin, const Params& params,
                      const ObjectParams& object_params, const RangeNoise& noise,
                      const std::optional<Eigen::Vector3f>& eye, double margin) {
  Supports found;
  std::vector<int>& supports = found.plane;
  std::vector<SupportArea>& areas = found.areas;
  std::vector<int>& support_of_plane = found.of_plane;
  support_of_plane.assign(planes.size(), -1);
  // Planes that can carry things, highest first: a point belongs to the highest one below it.
  for (std::size_t p = 0; p < planes.size() && supports.size() < kMaxSupportPlanes; ++p) {
    if (planes[p].facing != Facing::kDown) supports.push_back(static_cast<int>(p));
  }
  std::sort(supports.begin(), supports.end(),
            [&](int a, int b) { return planes[a].height > planes[b].height; });
  for (std::size_t s = 0; s < supports.size(); ++s) {
    areas.emplace_back(planes[supports[s]], local_origin, params.r_xy);
    support_of_plane[supports[s]] = static_cast<int>(s);
  }
  // What is seen below a plane's height by more than r_z, other than a plane (the sides of a
  // thing standing lower down), marks where that plane is not. A lower plane seen there marks
  // nothing: with nothing on it in the bay, nothing there is taken for standing on the higher.
  std::vector<double> height_of_support(supports.size());
  for (std::size_t s = 0; s < supports.size(); ++s) {
    height_of_support[s] = planes[supports[s]].height - local_origin.z() - params.r_z;
  }
  for (std::size_t i = 0; i < points.size(); ++i) {
    const int p = point_labels[i];
    const Eigen::Vector3f q = points[i];
    if (p >= 0) {
      if (support_of_plane[p] >= 0) areas[support_of_plane[p]].markOccupied(q.x(), q.y());
      continue;
    }
    if (!q.allFinite()) continue;
    for (std::size_t s = 0; s < supports.size() && q.z() < height_of_support[s]; ++s) {
      areas[s].markBelow(q.x(), q.y());
    }
  }
  for (SupportArea& area : areas) area.finish();

  // A plane that itself stands on a lower one (a box's top, a book, a chair's seat on the
  // floor) is also the top of an object there: its points are object points too, and it still
  // carries what stands on it. One higher than max_height (a cabinet's, a table's) is a tall
  // thing's top: what stands under it up to its height belongs to the thing.
  // A raised plane of fewer than 8 cells carries nothing: on a can or a bottle the voxel
  // centroids of each slab form a level ring, a "plane" inside the object, which would cut it
  // in two; a book or a box top that carries a cup is larger.
  const double least_carrying_area = 8 * params.r_xy * params.r_xy;
  const double max_top_height = std::max(object_params.max_top_height, object_params.max_height);
  std::vector<std::uint8_t>& raised = found.raised;
  std::vector<std::uint8_t>& carrying = found.carrying;
  std::vector<int>& stands_on_support = found.stands_on;
  std::vector<int>& tall_top_over = found.tall_top_over;
  raised.assign(planes.size(), 0);
  carrying.assign(supports.size(), 1);
  stands_on_support.assign(supports.size(), -1);
  tall_top_over.assign(supports.size(), -1);
  for (std::size_t s = 0; s < supports.size(); ++s) {
    const HorizontalPlane& top = planes[supports[s]];
    const Eigen::Vector3d c = top.centroid - local_origin;
    // The highest plane below whose area holds its centroid; failing that, one of its corners
    // (a thing hides the floor under and behind it, where the floor's area has no hole to
    // fill).
    int stands_on = -1;
    for (int pass = 0; pass < 2 && stands_on < 0; ++pass) {
      for (std::size_t lower = s + 1; lower < supports.size(); ++lower) {
        const double above = top.height - planes[supports[lower]].height;
        if (above <= margin) continue;
        if (above > max_top_height) break;
        const auto& corners = pass == 0 ? std::vector<Eigen::Vector3d>() : top.hull;
        if (!standsOver(areas[lower], c, corners, local_origin)) continue;
        // By a corner alone, the top might rest there, or overhang a lower surface that runs
        // on under it (a desk top over a lower cabinet, the floor in the bay of an L-shaped
        // desk): the eye seeing through the space under its hull, halfway down, tells the
        // second. As many rays as an object's least points are the evidence; the tops that
        // rest (a stair block's upper tread, a cabinet's top) let none through.
        if (pass == 1 && eye) {
          const double inset = std::max(params.r_xy, 3 * noise.at((c.cast<float>() - *eye).norm()));
          if (seenThroughUnder(points, top.hull, local_origin, c.z() - above / 2, inset, *eye,
                               noise, margin, object_params.min_points)) {
            continue;
          }
        }
        stands_on = static_cast<int>(lower);
        break;
      }
    }
    if (stands_on < 0) continue;
    if (top.height - planes[supports[stands_on]].height > object_params.max_height) {
      if (top.area < least_carrying_area) continue;  // a ring inside something tall
      tall_top_over[s] = stands_on;
    }
    raised[supports[s]] = 1;
    stands_on_support[s] = stands_on;
    carrying[s] = top.area >= least_carrying_area ? 1 : 0;
  }
  // What rises beside an object's top (a taller box pushed against a lower one) is not on it:
  // an object's top carries only over its own points' box (its mask's cells would claim up to
  // a cell of the neighbour). Something overhanging it still joins it as "beside".
  for (std::size_t s = 0; s < supports.size(); ++s) {
    if (raised[supports[s]]) areas[s].tightenTo(planes[supports[s]], local_origin, margin);
  }
  std::vector<double>& local_height = found.local_height;
  local_height.resize(supports.size());
  for (std::size_t s = 0; s < supports.size(); ++s) {
    local_height[s] = planes[supports[s]].height - local_origin.z();
  }
  // Points touch within a distance that follows the data. The finest is a cell of r_z / 4
  // (5 mm: two Kinect samples at 1.5 m, so objects a centimetre apart stay apart). Where the
  // plane's own samples are sparser (farther away, a LiDAR), cells are twice their spacing, so
  // that an object is not shattered into its samples. And with a known viewpoint, cells are at
  // least twice the sensor's range noise at the point: neighbouring samples of one surface lie
  // about √2 σ apart along the ray (26 mm at 4 m for a Kinect), and a finer grid would cut a
  // far chair into its samples. Cells come in levels of the plane's finest cell · 2^level;
  // points of one level touch on its grid, and a coarser point reaches the finer points in its
  // cell's neighbours.
  found.finest_cell = params.r_z / 4;
  const double finest_cell = found.finest_cell;
  std::vector<double>& sample_cell = found.sample_cell;
  sample_cell.resize(supports.size());
  for (std::size_t s = 0; s < supports.size(); ++s) {
    const HorizontalPlane& plane = planes[supports[s]];
    const double spacing =
        plane.num_points > 0 ? std::sqrt(plane.area / static_cast<double>(plane.num_points)) : 0.0;
    sample_cell[s] = std::max(finest_cell, 2 * spacing);
  }
  return found;
}

// The object points over the supports (`candidates`) and the feet of things (`feet`).
void classifyPoints(const AlignedPoints& points, const std::vector<HorizontalPlane>& planes,
                    const std::vector<std::int32_t>& point_labels,
                    const Eigen::Vector3d& local_origin, const ObjectParams& object_params,
                    const RangeNoise& noise, const std::optional<Eigen::Vector3f>& eye,
                    double margin, const Supports& found, std::vector<ObjectPoint>& candidates,
                    std::vector<FootPoint>& feet) {
  const std::vector<int>& supports = found.plane;
  const std::vector<int>& support_of_plane = found.of_plane;
  const std::vector<SupportArea>& areas = found.areas;
  const std::vector<std::uint8_t>& raised = found.raised;
  const std::vector<std::uint8_t>& carrying = found.carrying;
  const std::vector<int>& stands_on_support = found.stands_on;
  const std::vector<int>& tall_top_over = found.tall_top_over;
  const std::vector<double>& local_height = found.local_height;
  const std::vector<double>& sample_cell = found.sample_cell;
  const double max_top_height = std::max(object_params.max_top_height, object_params.max_height);
  // The tall thing's top standing on support s that q is under (no higher than the top), or -1.
  const auto underTallTop = [&](std::size_t s, const Eigen::Vector3f& q) {
    for (std::size_t t = 0; t < s; ++t) {
      if (tall_top_over[t] == static_cast<int>(s) && q.z() <= local_height[t] + margin &&
          areas[t].contains(q.x(), q.y())) {
        return static_cast<int>(t);
      }
    }
    return -1;
  };

  // The level whose cells are at least `cell` on support s's grid (the nearest power of two).
  const auto levelOf = [&](std::size_t s, double cell) {
    if (!(cell > sample_cell[s])) return std::uint8_t{0};
    const long level = std::lround(std::log2(cell / sample_cell[s]));
    return static_cast<std::uint8_t>(std::clamp(level, 0L, static_cast<long>(kLevels - 1)));
  };

  // Room for every point ahead: growing them point by point copied them several times over.
  candidates.reserve(points.size());
  feet.reserve(points.size());
  // Height above support s's fitted plane (its normal through its centroid), not its mean
  // height: a plane a little tilted in the frame (an up a fraction of a degree off) lies
  // millimetres above its mean height at its far side, and feet are millimetres high.
  std::vector<HeightAbovePlane> above_fitted;
  for (int support : supports) above_fitted.emplace_back(planes[support], local_origin);
  // Height above support s's fitted surface over its own extent, held at its box's edge
  // beyond it: a plane's tilt is measured over its extent and is not followed past it (a small
  // plane's fitted normal, degrees off, would rise or sink metres away).
  std::vector<Eigen::AlignedBox2f> extent_of_support;
  for (int support : supports) {
    const auto& b = planes[support].bbox;
    extent_of_support.emplace_back(Eigen::Vector2f(static_cast<float>(b[0] - local_origin.x()),
                                                   static_cast<float>(b[1] - local_origin.y())),
                                   Eigen::Vector2f(static_cast<float>(b[2] - local_origin.x()),
                                                   static_cast<float>(b[3] - local_origin.y())));
  }
  const auto aboveFittedOverExtent = [&](std::size_t s, const Eigen::Vector3f& q) {
    const Eigen::AlignedBox2f& box = extent_of_support[s];
    const Eigen::Vector2f held = q.head<2>().cwiseMax(box.min()).cwiseMin(box.max());
    const double surface = above_fitted[s](Eigen::Vector3f(held.x(), held.y(), 0.0f));
    return static_cast<double>(q.z()) + surface;  // surface = -(its height under `held`)
  };
  // The sensor's range noise σ at q, and three σ of it seen vertically; 0 without a viewpoint.
  struct NoiseAt {
    double sigma = 0.0, vertical = 0.0;
  };
  const auto noiseAt = [&](const Eigen::Vector3f& q) {
    NoiseAt at;
    if (!eye) return at;
    const Eigen::Vector3f ray = q - *eye;
    const double range = ray.norm();
    at.sigma = noise.at(range);
    if (range > 0) at.vertical = 3 * at.sigma * std::fabs(ray.z()) / range;
    return at;
  };
  for (std::size_t i = 0; i < points.size(); ++i) {
    const Eigen::Vector3f q = points[i];
    if (!q.allFinite()) continue;
    // Above a plane by more than its noise: half a vertical cell, or three standard deviations
    // of the sensor's range noise at the point, seen vertically (a far floor's own samples
    // scatter farther above it than r_z / 2).
    const NoiseAt at = noiseAt(q);
    const double sigma = at.sigma, vertical_noise = at.vertical;
    const double noise_margin = std::max(margin, vertical_noise);
    const bool in_plane_voxels = point_labels[i] >= 0 && !raised[point_labels[i]];
    if (in_plane_voxels) {
      const int s = support_of_plane[point_labels[i]];
      if (s < 0 || !carrying[s]) continue;
      const double above = above_fitted[static_cast<std::size_t>(s)](q);
      // The plane's voxels are r_z tall, and a surface across two layers of them holds points
      // up to 2 r_z above it: higher than the plane's noise (as every other point is judged
      // below), such a point is a thing's, not the plane's (the top of a box lying flat, too
      // small to be a plane of its own). It joins the object it touches but seeds none (a
      // floor's warp far away rises as high). Lower, but above three σ, it is a foot.
      if (!(above > noise_margin)) {
        if (eye && above > 0 && above > vertical_noise) {
          feet.push_back({static_cast<std::uint32_t>(i), static_cast<std::uint8_t>(s)});
        }
        continue;
      }
    }
    int beside = -1;  // the highest plane the point is beside, at object height
    int over = -1;    // the plane whose area it stands over
    int under_top = -1;
    bool on_plane = false;  // within the noise of a plane over whose area it lies
    int foot_of = -1;       // the plane it is a foot over
    // A raised plane's own points (within its noise: higher ones stand on it) stand, whole, on
    // the plane it stands on.
    const int own = point_labels[i] >= 0 ? support_of_plane[point_labels[i]] : -1;
    if (own >= 0 && stands_on_support[own] >= 0 && q.z() - local_height[own] <= noise_margin) {
      over = stands_on_support[own];
      if (tall_top_over[own] >= 0) under_top = own;
    }
    for (std::size_t s = 0; s < supports.size() && over < 0; ++s) {
      if (!carrying[s]) continue;
      // Above the plane by the margin both over its level height and over its fitted surface
      // over its extent (aboveFittedOverExtent): with an up a degree off (an accelerometer's
      // usual error) a level floor rises in the frame by d·tan 1° away from its centroid (4 cm
      // 2.4 m off), past the margin over its mean height, and its far samples would be taken
      // for things; the tilted surface follows it. Not that surface alone: where it sinks
      // below the level height (its far side the other way) it would let noise through.
      const double above = std::min<double>(q.z() - local_height[s], aboveFittedOverExtent(s, q));
      if (above <= noise_margin) {  // below this plane: try the lower ones
        on_plane = on_plane || (point_labels[i] != supports[s] && above >= -noise_margin &&
                                areas[s].contains(q.x(), q.y()));
        if (eye && foot_of < 0 && above_fitted[s](q) > vertical_noise &&
            areas[s].contains(q.x(), q.y())) {
          foot_of = static_cast<int>(s);
        }
        continue;
      }
      if (above > object_params.max_height) {
        // Too high above every lower plane too, unless under a tall thing's top there (and
        // not the foot of something on a plane in between: on_plane).
        for (std::size_t lower = s; lower < supports.size() && over < 0 && !on_plane; ++lower) {
          if (q.z() - local_height[lower] > max_top_height) break;
          under_top = underTallTop(lower, q);
          if (under_top >= 0) over = static_cast<int>(lower);
        }
        break;
      }
      if (areas[s].contains(q.x(), q.y()) || areas[s].withinHull(q.x(), q.y())) {
        over = static_cast<int>(s);
        break;
      }
      // Beside this plane (an overhang reaches kOverhang past its edge at most): a lower plane
      // may still carry it.
      if (beside < 0 && areas[s].near(q.x(), q.y(), kOverhang)) beside = static_cast<int>(s);
    }
    const int s = over >= 0 ? over : beside;
    if (s < 0) {
      if (foot_of >= 0) {
        feet.push_back({static_cast<std::uint32_t>(i), static_cast<std::uint8_t>(foot_of)});
      }
      continue;
    }
    candidates.push_back({static_cast<std::uint32_t>(i), static_cast<std::uint8_t>(s),
                          levelOf(static_cast<std::size_t>(s), 2 * sigma),
                          over >= 0 && !in_plane_voxels, static_cast<std::int16_t>(under_top),
                          static_cast<float>(sigma)});
  }
}

// No fine cell: a candidate whose cell key would overflow.
constexpr std::uint32_t kNoCell = std::numeric_limits<std::uint32_t>::max();

// Cells that touch (26-neighbourhood) on the same plane are one object, level by level.
// First each point's cell on its plane's finest grid: every point of such a cell ends in one
// object (at its coarsest point's level the cell is joined whole), so the levels work on
// these cells, far fewer than the points, and a coarser cell's key is the finer one's with
// each coordinate halved per level. At each level the cells are sorted by key, where the
// neighbours are found by sweeps (no hash table: sorting 10^5 keys is cheaper than as many
// insertions). A cell holding a point of this level joins its points and every point of the
// cells around it; a cell of finer points alone joins nothing here (they touched at theirs).
// Candidate k's fine cell goes to cell_of[k] (kNoCell for none); the fine cells' union-find
// is returned.
UnionFind joinTouchingCells(const AlignedPoints& points, const std::vector<ObjectPoint>& candidates,
                            const std::vector<double>& sample_cell,
                            std::vector<std::uint32_t>& cell_of) {
  // (cell key, candidate or cell), kept from frame to frame (cell_keys.h)
  thread_local std::vector<std::pair<std::uint64_t, std::uint32_t>> keyed;
  keyed.clear();
  keyed.reserve(candidates.size());
  for (std::size_t k = 0; k < candidates.size(); ++k) {
    std::uint64_t key;
    const ObjectPoint& c = candidates[k];
    if (cellKey(points[c.index], sample_cell[c.support], c.support, key)) {
      keyed.emplace_back(key, static_cast<std::uint32_t>(k));
    }
  }
  sortByKey(keyed);
  std::vector<std::uint64_t> fine_keys;
  std::vector<std::uint8_t> levels_in;  // per fine cell, bit l set when it holds a point of level l
  cell_of.assign(candidates.size(), kNoCell);
  for (const auto& [key, k] : keyed) {
    if (fine_keys.empty() || fine_keys.back() != key) {
      fine_keys.push_back(key);
      levels_in.push_back(0);
    }
    levels_in.back() |= static_cast<std::uint8_t>(1u << candidates[k].level);
    cell_of[k] = static_cast<std::uint32_t>(fine_keys.size() - 1);
  }
  UnionFind components(fine_keys.size());
  std::uint8_t all_levels = 0;
  for (std::uint8_t levels : levels_in) all_levels |= levels;
  for (int level = 0; level < kLevels; ++level) {
    const unsigned bit = 1u << level;
    if (!(all_levels & bit)) continue;
    keyed.clear();
    for (std::uint32_t c = 0; c < fine_keys.size(); ++c) {
      if (levels_in[c] & ((bit << 1) - 1)) keyed.emplace_back(coarser(fine_keys[c], level), c);
    }
    if (level > 0) sortByKey(keyed);
    // The cells in key order: their first entry, and whether a point of this level is there.
    std::vector<std::uint64_t> cell_keys;
    std::vector<std::uint32_t> first;
    std::vector<std::uint8_t> active;
    for (std::uint32_t e = 0; e < keyed.size(); ++e) {
      if (cell_keys.empty() || cell_keys.back() != keyed[e].first) {
        cell_keys.push_back(keyed[e].first);
        first.push_back(e);
        active.push_back(0);
      }
      active.back() |= (levels_in[keyed[e].second] & bit) ? 1 : 0;
    }
    first.push_back(static_cast<std::uint32_t>(keyed.size()));
    // All fine cells of cell c joined to `to`.
    const auto joinCell = [&](std::uint32_t c, std::uint32_t to) {
      for (std::uint32_t e = first[c]; e < first[c + 1]; ++e) components.join(keyed[e].second, to);
    };
    for (std::uint32_t c = 0; c < cell_keys.size(); ++c) {
      if (active[c]) joinCell(c, keyed[first[c]].second);
    }
    // Each pair once, from the cell with the smaller key: for each of the 13 offsets to a
    // larger key, the neighbours' keys rise with the cells', so one forward sweep finds them.
    for (int dx = 0; dx <= 1; ++dx) {
      for (int dy = -1; dy <= 1; ++dy) {
        for (int dz = -1; dz <= 1; ++dz) {
          if (dx == 0 && (dy < 0 || (dy == 0 && dz <= 0))) continue;  // the other half, or self
          std::size_t other = 0;
          for (std::uint32_t c = 0; c < cell_keys.size(); ++c) {
            const std::uint64_t wanted = neighbourKey(cell_keys[c], dx, dy, dz);
            while (other < cell_keys.size() && cell_keys[other] < wanted) ++other;
            if (other == cell_keys.size()) break;
            if (cell_keys[other] != wanted || !(active[c] || active[other])) continue;
            const auto o = static_cast<std::uint32_t>(other);
            if (active[c] && active[o]) {
              components.join(keyed[first[c]].second, keyed[first[o]].second);
            } else if (active[c]) {
              joinCell(o, keyed[first[c]].second);
            } else {
              joinCell(c, keyed[first[o]].second);
            }
          }
        }
      }
    }
  }
  return components;
}

// Each foot point goes to the object whose lowest points (up to a vertical cell and two of
// its plane's finest cells above the plane) share its cell on its plane's finest grid, or
// failing that touch it, when exactly one object's do; then the feet next to those, and so
// on down, a vertical cell at most (a thing's lowest points may lie in the plane's voxels,
// a few cells below the lowest that was not the plane's).
void attachFeet(const AlignedPoints& points, const std::vector<FootPoint>& feet,
                std::size_t object_points, const Supports& found,
                const std::vector<int>& object_plane, const Params& params,
                std::vector<std::int32_t>& point_objects) {
  if (feet.empty() || object_plane.empty()) return;
  const std::vector<int>& support_of_plane = found.of_plane;
  const std::vector<double>& local_height = found.local_height;
  const std::vector<double>& sample_cell = found.sample_cell;
  std::vector<std::pair<std::uint64_t, std::int32_t>> lowest;  // (cell key, object)
  // Feet far from every object's lowest points (the plane's own noisy samples, most of them)
  // are passed over at once: only those in or beside an r_xy column holding some are looked at.
  std::vector<std::uint64_t> columns;
  lowest.reserve(object_points);  // at most the candidates
  columns.reserve(object_points);
  const auto columnOf = [&](const Eigen::Vector3f& q, int s) {
    std::uint64_t key = 0;
    cellKey(Eigen::Vector3f(q.x(), q.y(), 0), params.r_xy, s, key);
    return key;
  };
  for (std::size_t i = 0; i < points.size(); ++i) {
    const std::int32_t o = point_objects[i];
    if (o < 0) continue;
    const int s = support_of_plane[object_plane[o]];
    if (s < 0) continue;
    const Eigen::Vector3f q = points[i];
    std::uint64_t key;
    if (q.z() - local_height[s] <= params.r_z + 2 * sample_cell[s] &&
        cellKey(q, sample_cell[s], s, key)) {
      lowest.emplace_back(key, o);
      columns.push_back(columnOf(q, s));
    }
  }
  std::sort(lowest.begin(), lowest.end());
  lowest.erase(std::unique(lowest.begin(), lowest.end()), lowest.end());
  std::sort(columns.begin(), columns.end());
  columns.erase(std::unique(columns.begin(), columns.end()), columns.end());
  const auto nearColumn = [&](std::uint64_t column) {
    for (int dx = -1; dx <= 1; ++dx) {
      for (int dy = -1; dy <= 1; ++dy) {
        if (std::binary_search(columns.begin(), columns.end(), neighbourKey(column, dx, dy, 0))) {
          return true;
        }
      }
    }
    return false;
  };
  std::vector<std::uint64_t> foot_key(feet.size());
  std::vector<std::uint8_t> keyed_foot(feet.size(), 0);
  for (std::size_t f = 0; f < feet.size(); ++f) {
    const Eigen::Vector3f q = points[feet[f].index];
    keyed_foot[f] = nearColumn(columnOf(q, feet[f].support)) &&
                    cellKey(q, sample_cell[feet[f].support], feet[f].support, foot_key[f]);
  }
  std::vector<std::pair<std::uint64_t, std::int32_t>> attached, attached_before;
  // At most a vertical cell down, in the finest cells: feet never creep along the plane.
  const int rounds = static_cast<int>(std::ceil(params.r_z / found.finest_cell));
  bool grew = true;
  for (int round = 0; grew && round < rounds; ++round) {
    attached.clear();
    for (std::size_t f = 0; f < feet.size(); ++f) {
      if (!keyed_foot[f] || point_objects[feet[f].index] >= 0) continue;
      // The objects whose lowest points share the cell with it, failing that touch it.
      std::int32_t object = -1;
      bool one = true;
      const auto lookIn = [&](const std::vector<std::pair<std::uint64_t, std::int32_t>>& cells,
                              std::uint64_t wanted) {
        auto it =
            std::lower_bound(cells.begin(), cells.end(), std::make_pair(wanted, std::int32_t{-1}));
        for (; it != cells.end() && it->first == wanted && one; ++it) {
          one = object < 0 || object == it->second;
          object = it->second;
        }
      };
      const auto look = [&](std::uint64_t wanted) {
        lookIn(lowest, wanted);
        lookIn(attached_before, wanted);
      };
      look(foot_key[f]);
      for (int dx = -1; dx <= 1 && one && object < 0; ++dx) {
        for (int dy = -1; dy <= 1 && one; ++dy) {
          for (int dz = -1; dz <= 1 && one; ++dz) look(neighbourKey(foot_key[f], dx, dy, dz));
        }
      }
      if (one && object >= 0) attached.emplace_back(foot_key[f], object), keyed_foot[f] = 2;
    }
    // Written after the round, so that a round's outcome does not depend on the feet's order.
    for (std::size_t f = 0, a = 0; f < feet.size(); ++f) {
      if (keyed_foot[f] == 2) {
        point_objects[feet[f].index] = attached[a++].second;
        keyed_foot[f] = 3;
      }
    }
    grew = !attached.empty();
    // Kept apart from the objects' lowest cells, far more: merging into those each round
    // copied them all again.
    std::sort(attached.begin(), attached.end());
    const auto middle = static_cast<std::ptrdiff_t>(attached_before.size());
    attached_before.insert(attached_before.end(), attached.begin(), attached.end());
    std::inplace_merge(attached_before.begin(), attached_before.begin() + middle,
                       attached_before.end());
  }
}

// Each object's points, centroid, height over its plane, smallest upright box and footprint.
std::vector<StandingObject> describeObjects(const AlignedPoints& points,
                                            const std::vector<HorizontalPlane>& planes,
                                            const std::vector<std::int32_t>& point_objects,
                                            const std::vector<int>& object_plane,
                                            const Eigen::Vector3d& local_origin) {
  std::vector<StandingObject> objects;
  objects.resize(object_plane.size());
  std::vector<std::vector<Eigen::Vector2d>> footprint_points(object_plane.size());
  std::vector<double> top(object_plane.size(), -std::numeric_limits<double>::infinity());
  for (std::size_t o = 0; o < object_plane.size(); ++o) {
    StandingObject& object = objects[o];
    object.index = static_cast<int>(o);
    object.plane_index = object_plane[o];
    object.plane_id = planes[object.plane_index].id;
  }
  for (std::size_t i = 0; i < points.size(); ++i) {
    const std::int32_t o = point_objects[i];
    if (o < 0) continue;
    const Eigen::Vector3f q = points[i];
    StandingObject& object = objects[o];
    ++object.num_points;
    object.centroid += q.cast<double>();
    footprint_points[o].emplace_back(q.x(), q.y());
    top[o] = std::max(top[o], static_cast<double>(q.z()));
  }
  for (StandingObject& object : objects) {
    const std::size_t o = static_cast<std::size_t>(object.index);
    const double base = planes[object.plane_index].height;
    object.centroid = object.centroid / static_cast<double>(object.num_points) + local_origin;
    object.height = top[o] + local_origin.z() - base;
    const std::vector<Eigen::Vector2d> hull = convexHull2D(std::move(footprint_points[o]));
    Eigen::Vector2d centre = Eigen::Vector2d::Zero(), size = Eigen::Vector2d::Zero();
    smallestUprightBox(hull, centre, object.yaw, size);
    object.box_centre = Eigen::Vector3d(centre.x() + local_origin.x(),
                                        centre.y() + local_origin.y(), base + object.height / 2);
    object.box_size = Eigen::Vector3d(size.x(), size.y(), object.height);
    for (const Eigen::Vector2d& h : hull) {
      object.footprint.emplace_back(h.x() + local_origin.x(), h.y() + local_origin.y(), base);
    }
  }
  return objects;
}

}  // namespace

StandingObjects findStandingObjects(const AlignedPoints& points,
                                    const std::vector<HorizontalPlane>& planes,
                                    const std::vector<std::int32_t>& point_labels,
                                    const Eigen::Vector3d& local_origin, const Params& params,
                                    const ObjectParams& object_params,
                                    const std::optional<Eigen::Vector3d>& viewpoint) {
  validate(object_params);
  if (point_labels.size() != points.size()) {
    throw std::invalid_argument("findStandingObjects: one plane label per point is needed");
  }
  StandingObjects result;
  result.point_objects.assign(points.size(), -1);
  const RangeNoise noise = object_params.noise.value_or(RangeNoise::depthCamera());
  std::optional<Eigen::Vector3f> eye;
  if (viewpoint) eye = viewpoint->cast<float>();
  // Above the plane by more than half a vertical cell: the plane's own points (its noise, a
  // sheet of paper) stay below that; below max_height.
  const double margin = params.r_z / 2;
  const Supports found = findSupports(points, planes, point_labels, local_origin, params,
                                      object_params, noise, eye, margin);
  const std::vector<int>& supports = found.plane;
  const std::vector<int>& support_of_plane = found.of_plane;
  const std::vector<SupportArea>& areas = found.areas;
  const std::vector<std::uint8_t>& raised = found.raised;
  const std::vector<int>& tall_top_over = found.tall_top_over;
  const std::vector<double>& local_height = found.local_height;
  const std::vector<double>& sample_cell = found.sample_cell;
  thread_local std::vector<ObjectPoint> candidates;  // kept from frame to frame (cell_keys.h)
  candidates.clear();
  thread_local std::vector<FootPoint> feet;
  feet.clear();
  classifyPoints(points, planes, point_labels, local_origin, object_params, noise, eye, margin,
                 found, candidates, feet);

  thread_local std::vector<std::uint32_t> cell_of;  // kept from frame to frame (cell_keys.h)
  UnionFind components = joinTouchingCells(points, candidates, sample_cell, cell_of);

  // What rises past max_height under a tall thing's top is that thing's (a table's leg whose
  // top the table's edge hides), whether or not the points between are seen.
  // The tall top candidate k is a point of, where that top stands as a thing's top, or -1.
  const auto tallTopOf = [&](std::uint32_t k) {
    const std::int32_t label = point_labels[candidates[k].index];
    const int t = label >= 0 ? support_of_plane[label] : -1;
    return t >= 0 && tall_top_over[t] == candidates[k].support ? t : -1;
  };
  std::vector<std::uint32_t> top_cell(supports.size(), kNoCell);
  for (std::uint32_t k = 0; k < candidates.size(); ++k) {
    const int t = tallTopOf(k);
    if (t >= 0 && cell_of[k] != kNoCell) top_cell[t] = cell_of[k];
  }
  for (std::uint32_t k = 0; k < candidates.size(); ++k) {
    const int t = candidates[k].under_top;
    if (t >= 0 && cell_of[k] != kNoCell && top_cell[t] != kNoCell) {
      components.join(cell_of[k], top_cell[t]);
    }
  }

  // Per component: points, whether seeded, whether it holds a tall thing's top, its top and
  // bottom above its plane, the sensor's noise over it, whether it was joined across a gap,
  // its plane, its xy box and where its highest point is.
  struct Component {
    std::size_t points = 0;
    bool seeded = false;
    bool tall_top = false;
    double top = -std::numeric_limits<double>::infinity();
    double bottom = std::numeric_limits<double>::infinity();
    double noise = 0.0;      // sum of σ over its points
    bool under_top = false;  // has points joined to a tall top across a gap
    std::uint8_t support = 0;
    Eigen::AlignedBox2f footprint;
    Eigen::Vector3f highest = Eigen::Vector3f::Zero();
  };
  thread_local std::vector<Component> component;  // kept from frame to frame (cell_keys.h)
  component.resize(components.parent.size());     // each gathering fills it anew
  const auto gatherComponents = [&] {
    std::fill(component.begin(), component.end(), Component());
    for (std::uint32_t k = 0; k < candidates.size(); ++k) {
      const ObjectPoint& c = candidates[k];
      if (cell_of[k] == kNoCell) continue;
      Component& into = component[components.find(cell_of[k])];
      const Eigen::Vector3f q = points[c.index];
      ++into.points;
      into.seeded = into.seeded || c.seed;
      into.tall_top = into.tall_top || tallTopOf(k) >= 0;
      const double above = q.z() - local_height[c.support];
      if (above > into.top) into.highest = q;
      into.top = std::max(into.top, above);
      into.bottom = std::min(into.bottom, above);
      into.noise += c.noise;
      into.under_top = into.under_top || c.under_top >= 0;
      into.support = c.support;
      into.footprint.extend(q.head<2>());
    }
  };
  gatherComponents();
  // A slender upright (twice as tall as it is wide or more) standing under a tall thing's top
  // and seen rising until that thing hides it from the sensor is the thing's leg: a table's
  // far legs, whose upper part the table's edge hides. Whether it rises on behind the edge
  // cannot be seen; a slender upright reaching up into the hidden space under a top is taken
  // as holding it up. One whose top is seen (the sight line to a vertical cell above it passes
  // no point of the thing) is a thing of its own, under the table or not.
  if (eye) {
    // Whether a point of component `root` lies on the sight line to `target`, nearer than it:
    // within its own cell (twice its noise, or its plane's sample cell) of the line.
    const auto hiddenBy = [&](std::uint32_t root, const Eigen::Vector3f& target) {
      const Eigen::Vector3f sight = target - *eye;
      const float length = sight.norm();
      if (!(length > 0)) return false;
      const Eigen::Vector3f along = sight / length;
      for (std::uint32_t k = 0; k < candidates.size(); ++k) {
        if (cell_of[k] == kNoCell || components.find(cell_of[k]) != root) continue;
        const Eigen::Vector3f to = points[candidates[k].index] - *eye;
        const float depth = to.dot(along);
        if (!(depth > 0 && depth < length)) continue;
        const double reach =
            std::max(2.0 * candidates[k].noise, sample_cell[candidates[k].support]);
        if ((to - depth * along).norm() <= reach) return true;
      }
      return false;
    };
    bool joined_leg = false;
    for (std::uint32_t root = 0; root < component.size(); ++root) {
      const Component& c = component[root];
      if (c.points < object_params.min_points || !c.seeded || c.tall_top || c.under_top) continue;
      const double height = c.top - std::min(c.bottom, 0.0);
      if (2 * c.footprint.sizes().maxCoeff() > height) continue;
      for (std::size_t t = 0; t < supports.size(); ++t) {
        if (tall_top_over[t] != c.support || top_cell[t] == kNoCell ||
            c.highest.z() >= local_height[t] || !areas[t].contains(c.highest.x(), c.highest.y())) {
          continue;
        }
        const std::uint32_t thing = components.find(top_cell[t]);
        if (!hiddenBy(thing, c.highest + Eigen::Vector3f(0, 0, params.r_z))) continue;
        components.join(root, thing);
        joined_leg = true;
        break;
      }
    }
    // The thing keeps its leg through the crease split: its top's own points count as joined
    // across a gap (under_top), so a part that touches no other stays with it.
    if (joined_leg) gatherComponents();
  }
  // Objects in the order of their first point. What rises to max_height with no top of its
  // own was cut there: the foot of a wall, a partition, a pillar, not a thing on the plane.
  const double structure_height = object_params.max_height - params.r_z;
  std::vector<std::int32_t> object_of_component(components.parent.size(), -1);
  std::vector<int> object_plane;     // the plane index each object stands on
  std::vector<double> object_patch;  // the crease split's patch for each
  std::vector<std::uint8_t> joined_across_gap;
  for (std::uint32_t k = 0; k < candidates.size(); ++k) {
    if (cell_of[k] == kNoCell) continue;
    const std::uint32_t root = components.find(cell_of[k]);
    const Component& c = component[root];
    // And a tall top whose thing is not seen reaching down to the plane (a shelf board on a
    // wall, a table whose legs are hidden) is no thing standing there either.
    if (c.points < object_params.min_points || !c.seeded ||
        (c.top >= structure_height && !c.tall_top) ||
        (c.tall_top && c.bottom > object_params.max_height)) {
      continue;
    }
    if (object_of_component[root] < 0) {
      object_of_component[root] = static_cast<std::int32_t>(object_plane.size());
      object_plane.push_back(supports[candidates[k].support]);
      // Patches of r_z / 2 (1 cm: ~30 Kinect samples at 1 m), or as large as twice the
      // sensor's mean noise over the object (to the nearest power of two), so that a far
      // object's patches still give normals. Where the cloud is sparser (a LiDAR) they hold
      // too few points for a normal and split nothing.
      const double noise_cell = 2 * c.noise / static_cast<double>(c.points);
      const double crease_patch = params.r_z / 2;
      const long level =
          noise_cell > crease_patch ? std::lround(std::log2(noise_cell / crease_patch)) : 0L;
      object_patch.push_back(crease_patch * static_cast<double>(1L << std::min(level, 6L)));
      joined_across_gap.push_back(c.under_top ? 1 : 0);
    }
    result.point_objects[candidates[k].index] = object_of_component[root];
  }
  // Pieces of one thing join before the crease split: a taller thing's side rising beside a
  // lower one's top joins the taller thing before both come apart at the crease between them,
  // so that the side is seen whole; pieces seen apart join across what hides the middle.
  joinPiecesOfOneThing(points, planes, point_labels, raised, local_origin, margin,
                       result.point_objects, object_plane, object_patch, joined_across_gap);
  // Objects that touch come apart at the concave creases between them, which only a known
  // viewpoint tells from convex edges (a fold seen from the other side bends the other way).
  if (viewpoint && !object_plane.empty()) {
    CreaseParams crease;
    crease.patch = params.r_z / 2;
    crease.object_patch = std::move(object_patch);
    crease.joined_across_gap = std::move(joined_across_gap);
    // A part split off must be a real face or more (~5 × 5 cm at 1 m), not a crease's sliver.
    crease.min_part_points = 20 * object_params.min_points;
    crease.min_points = object_params.min_points;
    std::vector<int> parent;
    splitAtConcaveCreases(points, *viewpoint, crease, result.point_objects, parent);
    for (int& p : parent) p = object_plane[p];
    object_plane = std::move(parent);
  }
  dropSmallObjects(object_params.min_points, result.point_objects, object_plane);
  attachFeet(points, feet, candidates.size(), found, object_plane, params, result.point_objects);
  result.objects =
      describeObjects(points, planes, result.point_objects, object_plane, local_origin);
  return result;
}

}  // namespace hope
