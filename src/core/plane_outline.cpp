#include "hope/plane_outline.h"

#include <algorithm>
#include <cmath>

#include "hope/plane.h"

namespace hope {

namespace {

// Directions of the cell-boundary edges: +x, +y, −x, −y (a left turn is +1).
constexpr int kDx[4] = {1, 0, -1, 0};
constexpr int kDy[4] = {0, 1, 0, -1};

double pointSegmentDistance(const Eigen::Vector2d& p, const Eigen::Vector2d& a,
                            const Eigen::Vector2d& b) {
  const Eigen::Vector2d ab = b - a;
  const double length2 = ab.squaredNorm();
  if (length2 <= 0) return (p - a).norm();
  const double t = std::clamp((p - a).dot(ab) / length2, 0.0, 1.0);
  return (p - (a + t * ab)).norm();
}

// Douglas–Peucker on the open chain ring[first..last] (indices), marking the kept vertices.
void simplifyChain(const std::vector<Eigen::Vector2d>& ring, std::size_t first, std::size_t last,
                   double tolerance, std::vector<std::uint8_t>& keep) {
  std::vector<std::pair<std::size_t, std::size_t>> stack = {{first, last}};
  while (!stack.empty()) {
    const auto [a, b] = stack.back();
    stack.pop_back();
    double worst = -1;
    std::size_t at = a;
    for (std::size_t k = a + 1; k < b; ++k) {
      const double d = pointSegmentDistance(ring[k], ring[a], ring[b]);
      if (d > worst) {
        worst = d;
        at = k;
      }
    }
    if (worst > tolerance) {
      keep[at] = 1;
      stack.emplace_back(a, at);
      stack.emplace_back(at, b);
    }
  }
}

// A closed ring simplified within `tolerance`, split at its first vertex and the vertex
// farthest from it; left as it is when simplification would leave fewer than 3 vertices.
std::vector<Eigen::Vector2d> simplifyRing(const std::vector<Eigen::Vector2d>& ring,
                                          double tolerance) {
  const std::size_t n = ring.size();
  if (n <= 4) return ring;
  std::size_t far = 0;
  for (std::size_t k = 1; k < n; ++k) {
    if ((ring[k] - ring[0]).squaredNorm() > (ring[far] - ring[0]).squaredNorm()) far = k;
  }
  std::vector<Eigen::Vector2d> closed(ring);
  closed.push_back(ring[0]);
  std::vector<std::uint8_t> keep(n + 1, 0);
  keep[0] = keep[far] = keep[n] = 1;
  simplifyChain(closed, 0, far, tolerance, keep);
  simplifyChain(closed, far, n, tolerance, keep);
  std::vector<Eigen::Vector2d> out;
  for (std::size_t k = 0; k < n; ++k) {
    if (keep[k]) out.push_back(ring[k]);
  }
  return out.size() >= 3 ? out : ring;
}

// The shoelace formula: positive for a counter-clockwise ring.
template <class Point>
double signedArea(const std::vector<Point>& ring) {
  double twice = 0;
  for (std::size_t k = 0; k < ring.size(); ++k) {
    const Point& a = ring[k];
    const Point& b = ring[(k + 1) % ring.size()];
    twice += a.x() * b.y() - b.x() * a.y();
  }
  return 0.5 * twice;
}

}  // namespace

std::vector<std::vector<Eigen::Vector2d>> traceOutline(
    std::vector<std::pair<std::int64_t, std::int64_t>> cells, const Eigen::Vector2d& origin,
    double cell, double tolerance, double min_hole_cells) {
  std::vector<std::vector<Eigen::Vector2d>> rings;
  if (cells.empty()) return rings;
  std::int64_t x_lo = cells[0].first, x_hi = x_lo, y_lo = cells[0].second, y_hi = y_lo;
  for (const auto& [cx, cy] : cells) {
    x_lo = std::min(x_lo, cx);
    x_hi = std::max(x_hi, cx);
    y_lo = std::min(y_lo, cy);
    y_hi = std::max(y_hi, cy);
  }
  // A plane spanning more than 4 M cells (a hostile r_xy) is traced at a coarser cell.
  const double span = static_cast<double>(x_hi - x_lo + 1) * static_cast<double>(y_hi - y_lo + 1);
  const std::int64_t factor =
      span > 4e6 ? static_cast<std::int64_t>(std::ceil(std::sqrt(span / 4e6))) : 1;
  const std::int64_t width = (x_hi - x_lo) / factor + 3, height = (y_hi - y_lo) / factor + 3;
  // Occupancy with an empty border of one cell, so every boundary edge has an empty side.
  std::vector<std::uint8_t> occupied(static_cast<std::size_t>(width * height), 0);
  for (const auto& [cx, cy] : cells) {
    occupied[static_cast<std::size_t>(((cy - y_lo) / factor + 1) * width + (cx - x_lo) / factor +
                                      1)] = 1;
  }
  auto at = [&](std::int64_t i, std::int64_t j) {
    return occupied[static_cast<std::size_t>(j * width + i)] != 0;
  };

  // Directed edges with the occupied cell on their left: outer boundaries run counter-
  // clockwise, holes clockwise. out[vertex] holds the directions leaving that lattice vertex
  // (two at a vertex where cells touch only diagonally).
  const std::int64_t vertex_width = width + 1;
  auto vertex = [&](std::int64_t i, std::int64_t j) {
    return static_cast<std::size_t>(j * vertex_width + i);
  };
  std::vector<std::uint8_t> out(static_cast<std::size_t>(vertex_width * (height + 1)), 0);
  std::vector<std::size_t> starts;
  for (std::int64_t j = 1; j + 1 < height; ++j) {
    for (std::int64_t i = 1; i + 1 < width; ++i) {
      if (!at(i, j)) continue;
      // Every closed boundary has an edge running +x: those are the places to start.
      if (!at(i, j - 1)) {
        out[vertex(i, j)] |= 1 << 0;
        starts.push_back(vertex(i, j));
      }
      if (!at(i + 1, j)) out[vertex(i + 1, j)] |= 1 << 1;
      if (!at(i, j + 1)) out[vertex(i + 1, j + 1)] |= 1 << 2;
      if (!at(i - 1, j)) out[vertex(i, j + 1)] |= 1 << 3;
    }
  }
  const double step = cell * static_cast<double>(factor);
  const Eigen::Vector2d corner =
      origin + cell * Eigen::Vector2d(static_cast<double>(x_lo), static_cast<double>(y_lo)) -
      Eigen::Vector2d(step, step);  // lattice vertex (0, 0): one cell outside the border
  for (std::size_t start : starts) {
    while (out[start] != 0) {
      // Follow a loop, preferring a left turn at a vertex with two ways out: cells that touch
      // only at a corner are then bounded separately.
      std::vector<Eigen::Vector2d> ring;
      std::size_t v = start;
      int direction = -1;
      do {
        int next = -1;
        if (direction < 0) {
          for (int d = 0; d < 4 && next < 0; ++d) next = (out[v] >> d) & 1 ? d : -1;
        } else {
          for (int turn : {1, 0, 3}) {
            const int d = (direction + turn) % 4;
            if ((out[v] >> d) & 1) {
              next = d;
              break;
            }
          }
        }
        if (next < 0) break;  // cannot happen for a closed boundary; never loop forever
        out[v] &= static_cast<std::uint8_t>(~(1 << next));
        if (next != direction) {  // a corner: keep the vertex
          const std::int64_t i = static_cast<std::int64_t>(v % vertex_width);
          const std::int64_t j = static_cast<std::int64_t>(v / vertex_width);
          ring.push_back(corner +
                         step * Eigen::Vector2d(static_cast<double>(i), static_cast<double>(j)));
        }
        direction = next;
        v = vertex(static_cast<std::int64_t>(v % vertex_width) + kDx[next],
                   static_cast<std::int64_t>(v / vertex_width) + kDy[next]);
      } while (v != start);
      // The start may lie in the middle of a straight run.
      std::vector<Eigen::Vector2d> corners;
      for (std::size_t k = 0; k < ring.size(); ++k) {
        const Eigen::Vector2d& a = ring[(k + ring.size() - 1) % ring.size()];
        const Eigen::Vector2d& b = ring[(k + 1) % ring.size()];
        const Eigen::Vector2d u = ring[k] - a, w = b - ring[k];
        if (std::fabs(u.x() * w.y() - u.y() * w.x()) > 1e-12 * step * step) {
          corners.push_back(ring[k]);
        }
      }
      ring.swap(corners);
      if (ring.size() < 3) continue;
      const double area = signedArea(ring);
      if (area < 0 && -area < min_hole_cells * step * step) continue;  // a dropout, not a hole
      rings.push_back(simplifyRing(ring, tolerance));
    }
  }
  // Largest parts first, their holes after them: each ring's area computed once, not at every
  // comparison (a LiDAR's ground has hundreds of holes).
  std::vector<std::pair<double, std::size_t>> by_area(rings.size());
  for (std::size_t k = 0; k < rings.size(); ++k) by_area[k] = {signedArea(rings[k]), k};
  std::stable_sort(by_area.begin(), by_area.end(),
                   [](const auto& a, const auto& b) { return a.first > b.first; });
  std::vector<std::vector<Eigen::Vector2d>> sorted(rings.size());
  for (std::size_t k = 0; k < rings.size(); ++k) sorted[k] = std::move(rings[by_area[k].second]);
  return sorted;
}

double ringArea(const std::vector<Eigen::Vector3d>& ring) { return signedArea(ring); }

double outlineArea(const HorizontalPlane& plane) {
  double area = 0;
  for (const auto& ring : plane.outline) area += ringArea(ring);
  return area;
}

bool outlineContains(const HorizontalPlane& plane, double x, double y) {
  bool inside = false;
  for (const auto& ring : plane.outline) {
    for (std::size_t k = 0, prev = ring.size() - 1; k < ring.size(); prev = k++) {
      const Eigen::Vector3d& a = ring[k];
      const Eigen::Vector3d& b = ring[prev];
      if ((a.y() > y) != (b.y() > y) &&
          x < (b.x() - a.x()) * (y - a.y()) / (b.y() - a.y()) + a.x()) {
        inside = !inside;
      }
    }
  }
  return inside;
}

}  // namespace hope
