#include "hope/convex_hull.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <utility>

namespace hope {

namespace {

// Up to this many points a hull sorts them all: a filter's extra pass would cost more.
constexpr std::size_t kSortAllUpTo = 64;

double cross(const Eigen::Vector2d& o, const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  return (a.x() - o.x()) * (b.y() - o.y()) - (a.y() - o.y()) * (b.x() - o.x());
}

// Akl–Toussaint: the points extreme in eight directions (x, y and both diagonals, both ways)
// span an octagon inside the hull, and a point strictly inside it cannot be a hull vertex.
// One pass drops those points, so that the O(n log n) sort sees only the few near the rim; the
// hull is the same, vertex for vertex. Returns the number of points kept at the front.
std::size_t dropPointsInsideExtremeOctagon(Eigen::Vector2d* points, std::size_t n) {
  // Directions at -90°, -45°, 0°, 45°, 90°, 135°, 180°, 225° (their extreme points follow one
  // another counter-clockwise around the hull), scored without multiplications: -y, x - y, x,
  // x + y, y, y - x, -x, -x - y.
  std::size_t extreme[8] = {0, 0, 0, 0, 0, 0, 0, 0};
  double best[8];
  for (int k = 0; k < 8; ++k) best[k] = -HUGE_VAL;
  for (std::size_t i = 0; i < n; ++i) {
    const double x = points[i].x(), y = points[i].y();
    const double score[8] = {-y, x - y, x, x + y, y, y - x, -x, -x - y};
    for (int k = 0; k < 8; ++k) {
      if (score[k] > best[k]) best[k] = score[k], extreme[k] = i;
    }
  }
  Eigen::Vector2d octagon[8];
  std::size_t corners = 0;
  for (int k = 0; k < 8; ++k) {
    const Eigen::Vector2d& p = points[extreme[k]];
    if (corners == 0 || p != octagon[corners - 1]) octagon[corners++] = p;
  }
  while (corners > 1 && octagon[corners - 1] == octagon[0]) --corners;
  if (corners < 3) return n;
  auto strictlyInside = [&](const Eigen::Vector2d& p, double margin) {
    for (std::size_t k = 0; k < corners; ++k) {
      if (!(cross(octagon[k], octagon[(k + 1) % corners], p) > margin)) return false;
    }
    return true;
  };
  // Most points lie well inside: a box inside the octagon settles them with four comparisons.
  // The box spanned by the innermost coordinates of the extreme points on each side touches the
  // octagon (a rectangle's corners are its vertices), so it is shrunk about its centre until
  // its corners lie inside by a margin far above the rounding of the edge tests: a point inside
  // it then passes every edge test too (the tests are linear in the point), and the points
  // kept are the same as with the edge tests alone.
  auto coordinate = [&](int k, int axis) { return points[extreme[k]](axis); };
  const double left = std::max({coordinate(5, 0), coordinate(6, 0), coordinate(7, 0)});
  const double right = std::min({coordinate(1, 0), coordinate(2, 0), coordinate(3, 0)});
  const double bottom = std::max({coordinate(7, 1), coordinate(0, 1), coordinate(1, 1)});
  const double top = std::min({coordinate(3, 1), coordinate(4, 1), coordinate(5, 1)});
  const double extent = (best[2] + best[6]) + (best[4] + best[0]);  // width + height
  const double margin = 1e-6 * extent * extent;
  double x0 = 0, x1 = 0, y0 = 0, y1 = 0;
  bool use_box = false;
  for (const double shrink : {0.98, 0.9, 0.7}) {
    if (!(left < right && bottom < top)) break;
    const double cx = 0.5 * (left + right), cy = 0.5 * (bottom + top);
    const double hx = 0.5 * shrink * (right - left), hy = 0.5 * shrink * (top - bottom);
    x0 = cx - hx, x1 = cx + hx, y0 = cy - hy, y1 = cy + hy;
    use_box = true;
    for (int corner = 0; corner < 4 && use_box; ++corner) {
      use_box = strictlyInside(Eigen::Vector2d(corner & 1 ? x1 : x0, corner & 2 ? y1 : y0), margin);
    }
    if (use_box) break;
  }
  std::size_t kept = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const Eigen::Vector2d p = points[i];
    if (use_box && p.x() > x0 && p.x() < x1 && p.y() > y0 && p.y() < y1) continue;
    if (!strictlyInside(p, 0.0)) points[kept++] = p;
  }
  return kept;
}

// Andrew's monotone chain over points[0..n): sorts them, drops duplicates and writes the hull
// (counter-clockwise from the lowest-x point, collinear points left out) to `hull`, which has
// room for 2n + 1 points. Returns the hull's size.
std::size_t monotoneChain(Eigen::Vector2d* points, std::size_t n, Eigen::Vector2d* hull) {
  auto less = [](const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
    return a.x() < b.x() || (a.x() == b.x() && a.y() < b.y());
  };
  std::sort(points, points + n, less);
  n = static_cast<std::size_t>(std::unique(points, points + n) - points);
  if (n < 3) {
    std::copy(points, points + n, hull);
    return n;
  }
  std::size_t k = 0;
  for (std::size_t i = 0; i < n; ++i) {  // lower chain
    while (k >= 2 && cross(hull[k - 2], hull[k - 1], points[i]) <= 0) --k;
    hull[k++] = points[i];
  }
  for (std::size_t i = n - 1, lower = k + 1; i-- > 0;) {  // upper chain
    while (k >= lower && cross(hull[k - 2], hull[k - 1], points[i]) <= 0) --k;
    hull[k++] = points[i];
  }
  return k - 1;  // the last point repeats the first
}

}  // namespace

std::size_t convexHullInPlace(Eigen::Vector2d* points, std::size_t n, Eigen::Vector2d* hull) {
  if (n > kSortAllUpTo) n = dropPointsInsideExtremeOctagon(points, n);
  return monotoneChain(points, n, hull);
}

std::vector<Eigen::Vector2d> convexHull2D(std::vector<Eigen::Vector2d> points) {
  std::vector<Eigen::Vector2d> hull(2 * points.size() + 1);
  hull.resize(convexHullInPlace(points.data(), points.size(), hull.data()));
  return hull;
}

std::vector<Eigen::Vector2d> convexHullOfCellPoints(CellPoints& cells, std::size_t* points_sorted) {
  std::vector<Eigen::Vector2d>& points = cells.points;
  const std::size_t n = points.size();
  if (points_sorted) *points_sorted = n;
  const std::size_t num_cells = cells.cell_min.size();
  if (n <= kSortAllUpTo || num_cells == 0 || !(cells.side > 0) || !std::isfinite(cells.side)) {
    return convexHull2D(std::move(points));
  }
  constexpr int K = kHullDirections;
  constexpr double kPi = 3.14159265358979323846;
  // Directions k·360°/K, counter-clockwise from +x; the four axes exactly.
  static const auto directions = [] {
    std::array<Eigen::Vector2d, K> d;
    for (int k = 0; k < K; ++k) {
      const double angle = 2.0 * kPi * k / K;
      d[static_cast<std::size_t>(k)] =
          k % (K / 4) == 0
              ? Eigen::Vector2d(std::round(std::cos(angle)), std::round(std::sin(angle)))
              : Eigen::Vector2d(std::cos(angle), std::sin(angle));
    }
    return d;
  }();
  // How far a point may lie outside its cell, or a cell's inner point outside the hull, by
  // rounding (the inner points may be float means): far above any rounding, far below a cell.
  double scale = 0;
  for (const Eigen::Vector2d& corner : cells.cell_min)
    scale = std::max(scale, corner.cwiseAbs().maxCoeff());
  const double slack = 1e-3 * cells.side + 1e-6 * (scale + cells.side);

  // Each direction's maximum over the points is at least its maximum over the inner points;
  // only cells reaching that far can hold the extreme point (a bit per direction per cell).
  std::array<double, K> lower;
  lower.fill(-HUGE_VAL);
  for (const Eigen::Vector2d& inner : cells.cell_inner) {
    for (int k = 0; k < K; ++k) lower[k] = std::max(lower[k], directions[k].dot(inner));
  }
  // Each cell's square grown by the slack: its centre and half side.
  const double half = 0.5 * cells.side + slack;
  std::vector<Eigen::Vector2d> centre(num_cells);
  for (std::size_t c = 0; c < num_cells; ++c) {
    centre[c] = cells.cell_min[c] + Eigen::Vector2d::Constant(0.5 * cells.side);
  }
  std::vector<std::uint32_t> reach(num_cells, 0);
  for (std::size_t c = 0; c < num_cells; ++c) {
    for (int k = 0; k < K; ++k) {
      const Eigen::Vector2d& d = directions[k];
      const double upper = d.dot(centre[c]) + half * (std::fabs(d.x()) + std::fabs(d.y()));
      if (upper >= lower[k] - slack) reach[c] |= std::uint32_t{1} << k;
    }
  }
  std::array<double, K> best;
  best.fill(-HUGE_VAL);
  std::array<std::size_t, K> extreme;
  extreme.fill(n);
  for (std::size_t i = 0; i < n; ++i) {
    for (std::uint32_t bits = reach[cells.cell_of_point[i]]; bits != 0; bits &= bits - 1) {
      const int k = __builtin_ctz(bits);
      const double score = directions[k].dot(points[i]);
      if (score > best[k]) best[k] = score, extreme[k] = i;
    }
  }
  // The extreme points, counter-clockwise: a convex polygon inside the hull (its vertices are
  // points). A point strictly inside it is no hull vertex.
  std::array<Eigen::Vector2d, K> polygon;
  std::size_t corners = 0;
  for (int k = 0; k < K; ++k) {
    if (extreme[k] == n) return convexHull2D(std::move(points));  // a cell lied: no shortcut
    const Eigen::Vector2d& p = points[extreme[k]];
    if (corners == 0 || p != polygon[corners - 1]) polygon[corners++] = p;
  }
  while (corners > 1 && polygon[corners - 1] == polygon[0]) --corners;
  if (corners < 3) return convexHull2D(std::move(points));

  // Per cell, the polygon's edges its square (grown by the slack) is not strictly inside of.
  // cross(a, b, p) is linear in p, so its minimum over a square is at the centre minus the
  // half side times |b - a|'s components; a cell inside every edge by more than the rounding of
  // the edge tests (as in dropPointsInsideExtremeOctagon) is dropped whole, and a point of
  // another cell is tested against the edges its cell crosses only.
  const double extent = (best[0] + best[K / 2]) + (best[K / 4] + best[3 * K / 4]);
  const double margin = 1e-6 * extent * extent;
  std::vector<std::uint32_t> crossed(num_cells, 0);
  for (std::size_t c = 0; c < num_cells; ++c) {
    for (std::size_t e = 0; e < corners; ++e) {
      const Eigen::Vector2d& a = polygon[e];
      const Eigen::Vector2d& b = polygon[(e + 1) % corners];
      const double lowest =
          cross(a, b, centre[c]) - half * (std::fabs(b.x() - a.x()) + std::fabs(b.y() - a.y()));
      if (!(lowest > margin)) crossed[c] |= std::uint32_t{1} << e;
    }
  }
  std::size_t kept = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const Eigen::Vector2d p = points[i];
    bool inside = true;
    for (std::uint32_t bits = crossed[cells.cell_of_point[i]]; bits != 0 && inside;
         bits &= bits - 1) {
      const std::size_t e = static_cast<std::size_t>(__builtin_ctz(bits));
      inside = cross(polygon[e], polygon[(e + 1) % corners], p) > 0;
    }
    if (!inside) points[kept++] = p;
  }
  if (points_sorted) *points_sorted = kept;
  std::vector<Eigen::Vector2d> hull(2 * kept + 1);
  hull.resize(monotoneChain(points.data(), kept, hull.data()));
  return hull;
}
}  // namespace hope
