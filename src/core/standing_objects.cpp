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

namespace hope {

void validate(const ObjectParams& params) {
  if (!(params.max_height > 0 && params.max_height <= 100)) {
    std::ostringstream msg;
    msg << "object max_height = " << params.max_height << " is out of range (0, 100] m";
    throw std::invalid_argument(msg.str());
  }
  if (params.min_points < 1 || params.min_points > 100000000) {
    throw std::invalid_argument("object min_points = " + std::to_string(params.min_points) +
                                " is out of range [1, 1e8]");
  }
}

namespace {

// Where a plane can carry things: its occupied xy cells with their holes filled (objects
// occlude the surface they stand on) and one cell around them (an object overhanging the
// edge, the mixed pixels at its foot), as a mask over the plane's bounding box.
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
    x0_ = static_cast<long>(std::floor((plane.bbox[0] - local_origin.x()) / cell)) - 2;
    y0_ = static_cast<long>(std::floor((plane.bbox[1] - local_origin.y()) / cell)) - 2;
    width_ = static_cast<long>(std::floor((plane.bbox[2] - local_origin.x()) / cell)) - x0_ + 3;
    height_ = static_cast<long>(std::floor((plane.bbox[3] - local_origin.y()) / cell)) - y0_ + 3;
    mask_.assign(static_cast<std::size_t>(width_ * height_), 0);
  }
  void markOccupied(float x, float y) {
    const long ix = static_cast<long>(std::floor(x / cell_)) - x0_;
    const long iy = static_cast<long>(std::floor(y / cell_)) - y0_;
    if (ix > 0 && iy > 0 && ix < width_ - 1 && iy < height_ - 1) mask_[iy * width_ + ix] = 1;
  }
  // After every occupied cell was marked: fill the holes, grow by one cell.
  void finish() {
    // Cells reachable from the border without crossing an occupied cell are outside; every
    // other cell is the plane or a hole in it.
    std::vector<std::uint8_t> outside(mask_.size(), 0);
    std::vector<long> stack;
    auto push = [&](long x, long y) {
      if (x < 0 || y < 0 || x >= width_ || y >= height_) return;
      const long k = y * width_ + x;
      if (outside[k] || mask_[k]) return;
      outside[k] = 1;
      stack.push_back(k);
    };
    for (long x = 0; x < width_; ++x) push(x, 0), push(x, height_ - 1);
    for (long y = 0; y < height_; ++y) push(0, y), push(width_ - 1, y);
    while (!stack.empty()) {
      const long k = stack.back();
      stack.pop_back();
      const long x = k % width_, y = k / width_;
      push(x - 1, y), push(x + 1, y), push(x, y - 1), push(x, y + 1);
    }
    std::vector<std::uint8_t> filled(mask_.size(), 0);
    for (long y = 0; y < height_; ++y) {
      for (long x = 0; x < width_; ++x) {
        bool near_inside = false;
        for (long dy = -1; dy <= 1 && !near_inside; ++dy) {
          for (long dx = -1; dx <= 1 && !near_inside; ++dx) {
            const long nx = x + dx, ny = y + dy;
            near_inside =
                nx >= 0 && ny >= 0 && nx < width_ && ny < height_ && !outside[ny * width_ + nx];
          }
        }
        filled[y * width_ + x] = near_inside ? 1 : 0;
      }
    }
    mask_.swap(filled);
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
  bool contains(float x, float y) const {
    if (tight_ &&
        (x < tight_box_[0] || y < tight_box_[1] || x > tight_box_[2] || y > tight_box_[3])) {
      return false;
    }
    const long ix = static_cast<long>(std::floor(x / cell_)) - x0_;
    const long iy = static_cast<long>(std::floor(y / cell_)) - y0_;
    return ix >= 0 && iy >= 0 && ix < width_ && iy < height_ && mask_[iy * width_ + ix];
  }

 private:
  double cell_;
  long x0_ = 0, y0_ = 0, width_ = 0, height_ = 0;
  std::vector<std::uint8_t> mask_;
  bool tight_ = false;
  std::array<float, 4> tight_box_{};
};

// A point's cell on the object grid, with the plane it stands on, as one key: 20 bits for x
// and y and 16 for z (±5 km and ±300 m at 1 cm) and 8 for the plane.
constexpr int kMaxSupportPlanes = 255;
// How far past a plane's edge an object standing on it may reach (a plate or a box jutting
// out), metres.
constexpr double kOverhang = 0.15;
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

// A taller object pushed against a lower one rises beside the lower one's top, and what of it
// stands over that top's box (the strip along the edge they share) was given to the top. Such
// a part, on a raised plane, whose xy box touches that of an object on a lower plane rising
// higher than the raised plane, is that object's: it is joined to it, and the objects are
// numbered afresh (in the order of their first point). A cup on a book is not joined to the
// book's sides, which rise no higher than the book.
void rejoinRisingBesideTops(const AlignedPoints& points, const std::vector<HorizontalPlane>& planes,
                            const std::vector<std::uint8_t>& raised,
                            const Eigen::Vector3d& local_origin, double margin,
                            std::vector<std::int32_t>& object_of_point,
                            std::vector<int>& object_plane) {
  const std::size_t n = object_plane.size();
  bool any_raised = false;
  for (int p : object_plane) any_raised = any_raised || raised[p];
  if (!any_raised) return;
  std::vector<Eigen::AlignedBox3f> box(n);
  for (std::size_t i = 0; i < object_of_point.size(); ++i) {
    if (object_of_point[i] >= 0) box[object_of_point[i]].extend(points[i]);
  }
  std::vector<std::int32_t> into(n);
  std::iota(into.begin(), into.end(), 0);
  bool joined = false;
  for (std::size_t r = 0; r < n; ++r) {
    if (!raised[object_plane[r]]) continue;
    const double top_height = planes[object_plane[r]].height - local_origin.z();
    for (std::size_t l = 0; l < n; ++l) {
      if (l == r || raised[object_plane[l]] ||
          planes[object_plane[l]].height >= planes[object_plane[r]].height ||
          box[l].max().z() <= top_height + margin) {
        continue;
      }
      const Eigen::Vector2f gap = (box[r].min().head<2>() - box[l].max().head<2>())
                                      .cwiseMax(box[l].min().head<2>() - box[r].max().head<2>());
      if (gap.maxCoeff() <= margin) {
        into[r] = static_cast<std::int32_t>(l);
        joined = true;
        break;
      }
    }
  }
  if (!joined) return;
  std::vector<std::int32_t> renumbered(n, -1);
  std::vector<int> plane_of;
  for (std::int32_t& o : object_of_point) {
    if (o < 0) continue;
    const std::int32_t target = into[o];
    if (renumbered[target] < 0) {
      renumbered[target] = static_cast<std::int32_t>(plane_of.size());
      plane_of.push_back(object_plane[target]);
    }
    o = renumbered[target];
  }
  object_plane = std::move(plane_of);
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
  // Planes that can carry things, highest first: a point belongs to the highest one below it.
  std::vector<int> supports;
  for (std::size_t p = 0; p < planes.size() && supports.size() < kMaxSupportPlanes; ++p) {
    if (planes[p].facing != Facing::kDown) supports.push_back(static_cast<int>(p));
  }
  std::sort(supports.begin(), supports.end(),
            [&](int a, int b) { return planes[a].height > planes[b].height; });
  std::vector<SupportArea> areas;
  std::vector<int> support_of_plane(planes.size(), -1);
  for (std::size_t s = 0; s < supports.size(); ++s) {
    areas.emplace_back(planes[supports[s]], local_origin, params.r_xy);
    support_of_plane[supports[s]] = static_cast<int>(s);
  }
  for (std::size_t i = 0; i < points.size(); ++i) {
    const int p = point_labels[i];
    if (p >= 0 && support_of_plane[p] >= 0) {
      const Eigen::Vector3f q = points[i];
      areas[support_of_plane[p]].markOccupied(q.x(), q.y());
    }
  }
  for (SupportArea& area : areas) area.finish();

  // Above the plane by more than half a vertical cell: the plane's own points (its noise, a
  // sheet of paper) stay below that; below max_height.
  const double margin = params.r_z / 2;
  // A plane that itself stands on a lower one (a box's top, a book, a chair's seat on the
  // floor) is also the top of an object there: its points are object points too, and it still
  // carries what stands on it.
  // A raised plane of fewer than 8 cells carries nothing: on a can or a bottle the voxel
  // centroids of each slab form a level ring, a "plane" inside the object, which would cut it
  // in two; a book or a box top that carries a cup is larger.
  const double least_carrying_area = 8 * params.r_xy * params.r_xy;
  std::vector<std::uint8_t> raised(planes.size(), 0), carrying(supports.size(), 1);
  for (std::size_t s = 0; s < supports.size(); ++s) {
    const HorizontalPlane& top = planes[supports[s]];
    const Eigen::Vector3d c = top.centroid - local_origin;
    for (std::size_t lower = s + 1; lower < supports.size(); ++lower) {
      const double above = top.height - planes[supports[lower]].height;
      if (above <= margin) continue;
      if (above > object_params.max_height) break;
      if (areas[lower].contains(static_cast<float>(c.x()), static_cast<float>(c.y()))) {
        raised[supports[s]] = 1;
        carrying[s] = top.area >= least_carrying_area ? 1 : 0;
        break;
      }
    }
  }
  // What rises beside an object's top (a taller box pushed against a lower one) is not on it:
  // an object's top carries only over its own points' box (the r_xy cells of its mask would
  // claim up to a cell of the neighbour). Something overhanging it still joins it as "beside".
  for (std::size_t s = 0; s < supports.size(); ++s) {
    if (raised[supports[s]]) areas[s].tightenTo(planes[supports[s]], local_origin, margin);
  }

  // Objects are joined where their points touch, on cells of r_z / 4 (5 mm: two Kinect samples
  // at 1.5 m, so objects a centimetre apart stay apart) or twice the spacing of the plane's own
  // samples where the cloud is sparser (farther away, a LiDAR), so that an object is not
  // shattered into its samples.
  std::vector<double> local_height(supports.size()), cell(supports.size());
  for (std::size_t s = 0; s < supports.size(); ++s) {
    const HorizontalPlane& plane = planes[supports[s]];
    local_height[s] = plane.height - local_origin.z();
    const double spacing =
        plane.num_points > 0 ? std::sqrt(plane.area / static_cast<double>(plane.num_points)) : 0.0;
    cell[s] = std::max(params.r_z / 4, 2 * spacing);
  }
  // Each object point's cell, then the distinct cells in key order, where the neighbours are
  // found by sweeps (no hash table: sorting 10^5 keys is cheaper than as many insertions).
  std::vector<std::pair<std::uint64_t, std::uint32_t>> keyed;  // (cell key, point)
  // Points over a plane's area seed its objects; points beside it at object height (the part
  // of a box that overhangs the edge) join an object only through the cells they touch.
  std::vector<std::uint8_t> seeds(points.size(), 0);
  for (std::size_t i = 0; i < points.size(); ++i) {
    if (point_labels[i] >= 0 && !raised[point_labels[i]]) continue;
    const Eigen::Vector3f q = points[i];
    if (!q.allFinite()) continue;
    int beside = -1;  // the highest plane the point is beside, at object height
    for (std::size_t s = 0; s < supports.size(); ++s) {
      if (!carrying[s]) continue;
      const double above = q.z() - local_height[s];
      if (above <= margin) continue;                // below this plane: try the lower ones
      if (above > object_params.max_height) break;  // too high above every lower plane too
      if (areas[s].contains(q.x(), q.y())) {
        beside = -1;
        std::uint64_t key;
        if (cellKey(q, cell[s], static_cast<int>(s), key)) {
          keyed.emplace_back(key, static_cast<std::uint32_t>(i));
          seeds[i] = 1;
        }
        break;
      }
      // Beside this plane (an overhang reaches kOverhang past its edge at most): a lower plane
      // may still carry it.
      if (beside < 0 && areas[s].near(q.x(), q.y(), kOverhang)) beside = static_cast<int>(s);
    }
    std::uint64_t key;
    if (beside >= 0 && cellKey(q, cell[beside], beside, key)) {
      keyed.emplace_back(key, static_cast<std::uint32_t>(i));
    }
  }
  sortByKey(keyed);
  std::vector<std::uint64_t> cell_keys;
  std::vector<std::uint32_t> point_cell(points.size(), std::numeric_limits<std::uint32_t>::max());
  for (const auto& entry : keyed) {
    if (cell_keys.empty() || cell_keys.back() != entry.first) cell_keys.push_back(entry.first);
    point_cell[entry.second] = static_cast<std::uint32_t>(cell_keys.size() - 1);
  }

  // Cells that touch (26-neighbourhood) on the same plane are one object. Each pair is looked at
  // once, from the cell with the smaller key: for each of the 13 offsets to a larger key, the
  // neighbours' keys rise with the cells', so one forward sweep per offset finds them all.
  UnionFind components(cell_keys.size());
  for (int dx = 0; dx <= 1; ++dx) {
    for (int dy = -1; dy <= 1; ++dy) {
      for (int dz = -1; dz <= 1; ++dz) {
        if (dx == 0 && (dy < 0 || (dy == 0 && dz <= 0))) continue;  // the other half, or self
        std::size_t other = 0;
        for (std::uint32_t c = 0; c < cell_keys.size(); ++c) {
          const std::uint64_t wanted = neighbourKey(cell_keys[c], dx, dy, dz);
          while (other < cell_keys.size() && cell_keys[other] < wanted) ++other;
          if (other == cell_keys.size()) break;
          if (cell_keys[other] == wanted) components.join(c, static_cast<std::uint32_t>(other));
        }
      }
    }
  }
  // Points per component, then objects in the order of their first point.
  std::vector<std::size_t> component_points(cell_keys.size(), 0);
  std::vector<std::uint8_t> component_seeded(cell_keys.size(), 0);
  for (std::size_t i = 0; i < points.size(); ++i) {
    if (point_cell[i] != std::numeric_limits<std::uint32_t>::max()) {
      const std::uint32_t root = components.find(point_cell[i]);
      ++component_points[root];
      component_seeded[root] |= seeds[i];
    }
  }
  std::vector<std::int32_t> object_of_component(cell_keys.size(), -1);
  std::vector<int> object_plane;  // the plane index each object stands on
  for (std::size_t i = 0; i < points.size(); ++i) {
    if (point_cell[i] == std::numeric_limits<std::uint32_t>::max()) continue;
    const std::uint32_t root = components.find(point_cell[i]);
    if (component_points[root] < object_params.min_points || !component_seeded[root]) continue;
    if (object_of_component[root] < 0) {
      object_of_component[root] = static_cast<std::int32_t>(object_plane.size());
      object_plane.push_back(supports[cell_keys[root] & 0xff]);
    }
    result.point_objects[i] = object_of_component[root];
  }
  // Objects that touch come apart at the concave creases between them, which only a known
  // viewpoint tells from convex edges (a fold seen from the other side bends the other way).
  if (viewpoint && !object_plane.empty()) {
    CreaseParams crease;
    // Patches of r_z / 2 (1 cm: ~30 Kinect samples at 1 m). Where the cloud is sparser (far
    // away, a LiDAR) they hold too few points for a normal and split nothing.
    crease.patch = params.r_z / 2;
    // A part split off must be a real face or more (~5 × 5 cm at 1 m), not a crease's sliver.
    crease.min_part_points = 20 * object_params.min_points;
    crease.min_points = object_params.min_points;
    std::vector<int> parent;
    splitAtConcaveCreases(points, *viewpoint, crease, result.point_objects, parent);
    for (int& p : parent) p = object_plane[p];
    object_plane = std::move(parent);
  }
  rejoinRisingBesideTops(points, planes, raised, local_origin, margin, result.point_objects,
                         object_plane);
  result.objects.resize(object_plane.size());
  std::vector<std::vector<Eigen::Vector2d>> footprint_points(object_plane.size());
  std::vector<double> top(object_plane.size(), -std::numeric_limits<double>::infinity());
  for (std::size_t o = 0; o < object_plane.size(); ++o) {
    StandingObject& object = result.objects[o];
    object.index = static_cast<int>(o);
    object.plane_index = object_plane[o];
    object.plane_id = planes[object.plane_index].id;
  }
  for (std::size_t i = 0; i < points.size(); ++i) {
    const std::int32_t o = result.point_objects[i];
    if (o < 0) continue;
    const Eigen::Vector3f q = points[i];
    StandingObject& object = result.objects[o];
    ++object.num_points;
    object.centroid += q.cast<double>();
    footprint_points[o].emplace_back(q.x(), q.y());
    top[o] = std::max(top[o], static_cast<double>(q.z()));
  }
  for (StandingObject& object : result.objects) {
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
  return result;
}

}  // namespace hope
