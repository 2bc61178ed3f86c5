#include "hope/surface_grouping.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <map>
#include <numeric>
#include <stdexcept>
#include <string>
#include <unordered_map>
#include <unordered_set>

namespace hope {

namespace {

using Box = std::array<double, 4>;

bool boxesOverlap(const Box& a, const Box& b) {
  return a[0] < b[2] && b[0] < a[2] && a[1] < b[3] && b[1] < a[3];
}

std::size_t root(std::vector<std::size_t>& parent, std::size_t i) {
  while (parent[i] != i) i = parent[i] = parent[parent[i]];
  return i;
}

}  // namespace

void validate(const SurfaceGroupingOptions& options) {
  auto require = [](bool ok, const std::string& what) {
    if (!ok) throw std::invalid_argument("surface grouping: " + what);
  };
  require(options.max_height_step > 0 && options.max_height_step <= 10,
          "max_height_step = " + std::to_string(options.max_height_step) +
              " is out of range (0, 10] m");
  require(options.up_error_deg >= 0 && options.up_error_deg <= 45,
          "up_error_deg = " + std::to_string(options.up_error_deg) + " is out of range [0, 45]");
  require(options.memory_s >= 0 && options.memory_s <= 3600,
          "memory_s = " + std::to_string(options.memory_s) + " is out of range [0, 3600] s");
}

SurfaceGroupingOptions surfaceGroupingOptionsFor(const Params& params) {
  SurfaceGroupingOptions options;
  options.max_height_step = params.r_z;
  return options;
}

SurfaceGrouping::SurfaceGrouping(const SurfaceGroupingOptions& options) : options_(options) {
  validate(options_);
}

void SurfaceGrouping::assign(std::vector<HorizontalPlane>& planes, double stamp,
                             const std::optional<Eigen::Vector3d>& viewpoint,
                             const std::optional<RangeNoise>& noise, bool remember) {
  const std::size_t n = planes.size();
  // Each plane's extent: its box now and its id's boxes of the last memory_s seconds.
  std::unordered_map<int, std::vector<Box>> earlier;
  if (remember) {
    if (!recent_.empty() && stamp < recent_.back().stamp) recent_.clear();
    while (!recent_.empty() && recent_.front().stamp < stamp - options_.memory_s) {
      recent_.pop_front();
    }
    for (const Seen& seen : recent_) {
      for (const Piece& piece : seen.pieces) earlier[piece.id].push_back(piece.bbox);
    }
  }
  std::vector<std::vector<Box>> extent(n);
  for (std::size_t i = 0; i < n; ++i) {
    extent[i].push_back(planes[i].bbox);
    const auto it = earlier.find(planes[i].id);
    if (it != earlier.end())
      extent[i].insert(extent[i].end(), it->second.begin(), it->second.end());
  }
  // σ of each piece's height: the sensor's range noise at its centroid's range.
  std::vector<double> sigma(n, 0.0);
  if (noise && viewpoint) {
    for (std::size_t i = 0; i < n; ++i) {
      sigma[i] = noise->at((planes[i].centroid - *viewpoint).norm());
    }
  }
  const double up_slope = std::tan(options_.up_error_deg * M_PI / 180.0);
  auto oneReading = [&](std::size_t a, std::size_t b) {
    // Independent errors of the difference of two heights: each reading's range noise, and the
    // up's error across the horizontal distance between the pieces, at most two steps (a
    // platform stays apart from the floor around it). A piece with no finite centroid has no
    // distance to lean across.
    const double distance = (planes[a].centroid - planes[b].centroid).head<2>().norm();
    const double lean = std::isfinite(distance)
                            ? std::min(distance * up_slope, 2.0 * options_.max_height_step)
                            : 0.0;
    const double tolerance =
        std::max(options_.max_height_step,
                 std::sqrt(sigma[a] * sigma[a] + sigma[b] * sigma[b] + lean * lean));
    return std::fabs(planes[a].height - planes[b].height) <= tolerance;
  };
  auto extentsOverlap = [&](std::size_t a, std::size_t b) {
    for (const Box& p : extent[a]) {
      for (const Box& q : extent[b]) {
        if (boxesOverlap(p, q)) return true;
      }
    }
    return false;
  };
  std::vector<std::size_t> parent(n);
  std::iota(parent.begin(), parent.end(), 0);
  // A frame holds tens of planes and a second of frames tens of boxes an id: every pair is cheap.
  for (std::size_t i = 0; i < n; ++i) {
    for (std::size_t j = i + 1; j < n; ++j) {
      if (planes[i].facing == planes[j].facing && oneReading(i, j) && extentsOverlap(i, j)) {
        parent[root(parent, i)] = root(parent, j);
      }
    }
  }
  // Each group's largest piece; a chain of pieces each one reading with the next may drift from
  // it: one that is not one reading with it is not at the surface's height, and stays its own.
  std::vector<std::size_t> largest(n, n);
  for (std::size_t i = 0; i < n; ++i) {
    std::size_t& best = largest[root(parent, i)];
    if (best == n || planes[i].area > planes[best].area ||
        (planes[i].area == planes[best].area && planes[i].id < planes[best].id)) {
      best = i;
    }
  }
  std::vector<std::size_t> group(n);
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t named = largest[root(parent, i)];
    group[i] = oneReading(i, named) ? named : i;
  }
  const std::vector<int> names = nameSurfaces(planes, group, remember);
  for (std::size_t i = 0; i < n; ++i) planes[i].surface_id = names[group[i]];
  if (remember) {
    Seen seen{stamp, {}};
    seen.pieces.reserve(n);
    for (const HorizontalPlane& plane : planes) {
      seen.pieces.push_back({plane.id, plane.bbox, plane.surface_id});
    }
    recent_.push_back(std::move(seen));
  }
}

std::vector<int> SurfaceGrouping::nameSurfaces(const std::vector<HorizontalPlane>& planes,
                                               const std::vector<std::size_t>& group,
                                               bool remember) const {
  const std::size_t n = planes.size();
  // The surface each id was a piece of when last seen within memory_s (recent_ holds just those
  // frames, oldest first, so the latest overwrites).
  std::unordered_map<int, int> earlier_surface;
  if (remember) {
    for (const Seen& seen : recent_) {
      for (const Piece& piece : seen.pieces) earlier_surface[piece.id] = piece.surface_id;
    }
  }
  // What each group could keep: the surfaces its pieces belonged to, with the area of its
  // pieces that were there, the most first (the surface most of the group was).
  struct Claim {
    double area = 0.0;
    bool has_namesake = false;  // the piece whose id names the surface is in the group
    int surface = 0;
  };
  std::vector<std::vector<Claim>> claims(n);
  for (std::size_t i = 0; i < n; ++i) {
    const auto it = earlier_surface.find(planes[i].id);
    if (it == earlier_surface.end()) continue;
    std::vector<Claim>& of_group = claims[group[i]];
    auto claim = std::find_if(of_group.begin(), of_group.end(),
                              [&](const Claim& c) { return c.surface == it->second; });
    if (claim == of_group.end())
      claim = of_group.insert(of_group.end(), Claim{0.0, false, it->second});
    claim->area += planes[i].area;
    claim->has_namesake = claim->has_namesake || it->second == planes[i].id;
  }
  for (std::vector<Claim>& of_group : claims) {
    std::sort(of_group.begin(), of_group.end(), [](const Claim& a, const Claim& b) {
      return a.area != b.area ? a.area > b.area : a.surface < b.surface;
    });
  }
  // Each group asks for its first claim no other surface has kept; where several ask for one
  // name, the group holding its namesake piece keeps it (when a surface parts, the piece that
  // named it takes the name along, whichever side is larger), else the one with more area
  // there; the others ask for their next claim. Every round names at least one group.
  constexpr int kUnnamed = std::numeric_limits<int>::min();
  std::vector<int> names(n, kUnnamed);
  std::vector<std::size_t> next_claim(n, 0);
  std::unordered_set<int> taken;
  for (;;) {
    std::map<int, std::size_t> winner;  // name -> the group that keeps it this round
    for (std::size_t g = 0; g < n; ++g) {
      if (names[g] != kUnnamed) continue;
      while (next_claim[g] < claims[g].size() && taken.count(claims[g][next_claim[g]].surface)) {
        ++next_claim[g];
      }
      if (next_claim[g] == claims[g].size()) continue;
      const Claim& mine = claims[g][next_claim[g]];
      const auto [it, first] = winner.emplace(mine.surface, g);
      if (first) continue;
      const Claim& theirs = claims[it->second][next_claim[it->second]];
      if (mine.has_namesake != theirs.has_namesake ? mine.has_namesake : mine.area > theirs.area) {
        it->second = g;
      }
    }
    if (winner.empty()) break;
    for (const auto& [surface, g] : winner) {
      names[g] = surface;
      taken.insert(surface);
    }
  }
  // A surface new to the frame is named by its largest piece (the lower id on a tie) whose id no
  // surface kept; the largest surfaces choose first.
  std::vector<double> group_area(n, 0.0);
  std::vector<std::vector<std::size_t>> pieces(n);
  for (std::size_t i = 0; i < n; ++i) {
    group_area[group[i]] += planes[i].area;
    pieces[group[i]].push_back(i);
  }
  std::vector<std::size_t> unnamed;
  for (std::size_t g = 0; g < n; ++g) {
    if (!pieces[g].empty() && names[g] == kUnnamed) unnamed.push_back(g);
  }
  auto larger = [&](std::size_t a, std::size_t b) {
    if (planes[a].area != planes[b].area) return planes[a].area > planes[b].area;
    return planes[a].id < planes[b].id;
  };
  std::sort(unnamed.begin(), unnamed.end(), [&](std::size_t a, std::size_t b) {
    if (group_area[a] != group_area[b]) return group_area[a] > group_area[b];
    return larger(a, b);  // a group's index is its largest piece
  });
  int next_free = 0;
  for (const HorizontalPlane& plane : planes) next_free = std::max(next_free, plane.id + 1);
  for (const auto& [id, surface] : earlier_surface) next_free = std::max(next_free, surface + 1);
  for (std::size_t g : unnamed) {
    std::sort(pieces[g].begin(), pieces[g].end(), larger);
    for (std::size_t i : pieces[g]) {
      if (!taken.count(planes[i].id)) {
        names[g] = planes[i].id;
        break;
      }
    }
    // Every piece's id names another surface this frame (they kept names their pieces once
    // carried): a number no plane or remembered surface has, so no two surfaces share one.
    if (names[g] == kUnnamed) names[g] = next_free++;
    taken.insert(names[g]);
  }
  return names;
}

}  // namespace hope
