#include "hope/crease_splitting.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <Eigen/Eigenvalues>

#include "cell_keys.h"

namespace hope {

namespace {

// A patch key: 16 bits each for the object and the patch's x, y, z (relative to the objects'
// lowest corner, plus one, so a neighbour one step down stays inside its field).
constexpr int kFieldBits = 16;
constexpr long kFieldLimit = (1L << kFieldBits) - 2;

std::uint64_t neighbourKey(std::uint64_t key, int dx, int dy, int dz) {
  // Unsigned arithmetic wraps by definition; no field over- or underflows (see kFieldLimit).
  return key + static_cast<std::uint64_t>(dx) * (std::uint64_t{1} << 32) +
         static_cast<std::uint64_t>(dy) * (std::uint64_t{1} << 16) + static_cast<std::uint64_t>(dz);
}

struct Patch {
  std::size_t count = 0;
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  Eigen::Matrix3d outer = Eigen::Matrix3d::Zero();
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();
  // Flat enough for its normal to mean something: not too few points, not a corner or an edge
  // where two faces share the patch (its normal lies between theirs and would bridge a crease).
  bool flat = false;
  // Its points span a surface, not one line (a scanline fits any plane through it). A patch that
  // tells no normal (this, or too few points) is evidence of no crease: see the regions below.
  bool tells_normal = false;
};

// Fewer points than this give no normal worth trusting.
constexpr std::size_t kLeastPatchPoints = 6;
// The share of a patch's variance across its best plane (surface variation, Pauly et al.)
// above which it is not flat. A patch holding a sliver of a second face (a crease, an edge) has
// a normal tilted towards it and would bridge the crease. On mosd_dev's Kinect scenes 0.02 keeps
// touching objects apart (weighted overlap 0.871); 0.03 lets slivers through (0.762), 0.06
// joins nearly everything that touches (0.717; scripts/score_objects.sh).
constexpr double kMostFlatVariation = 0.02;
// The least ratio of a patch's middle spread to its largest for its points to span a surface
// (across at least a quarter as far as along), not a line.
constexpr double kLeastSurfaceSpread = 1.0 / 16;
// Patch sides between two flat patches that meet convexly across patches that tell no normal,
// at most: a region two patches wide.
constexpr double kConvexAcross = 3.0;
// cos 60°: the least angle between a convex step and the line where the faces meet.
constexpr double kSaneCos = 0.5;

// A part that hangs on another part of its object is that part's: a jug's or a mug's handle,
// which meets the body at concave creases as two things that touch do. Heights are the
// patches' centroids, told apart by more than a patch (their resolution); a part's top is the
// height under which nine tenths of its points lie (not its highest: the edge patches of a
// thing on it, given to it at the crease, would raise that). A part hangs on a part it touches
// when its lowest patch lies
// - above its object's lowest (it does not stand where the thing stands: its foot is not seen
//   reaching the plane),
// - above the other's lowest (the other reaches further down, towards the plane),
// - below the other's top (beside it, not resting on it: a box on a box with no plane found
//   between them stays a thing of its own),
// and it rises no higher than the other's top (a taller thing whose foot something nearer
// hides, beside a lower one, stays apart: on mosd_dev, without this, seven scenes of stacked
// and occluded things lost objects). Each joins the largest part it hangs on, round by round.
template <class PatchOf>
void joinHangingParts(const std::vector<std::uint64_t>& keys, const std::vector<Patch>& patches,
                      const std::vector<std::pair<std::uint32_t, std::uint32_t>>& adjacent,
                      const PatchOf& patchOf, UnionFind& parts) {
  constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();
  constexpr double kInf = std::numeric_limits<double>::infinity();
  constexpr double kTopShare = 0.9;
  std::vector<double> object_lowest;
  for (std::size_t k = 0; k < keys.size(); ++k) {
    const std::size_t o = keys[k] >> 48;
    if (o >= object_lowest.size()) object_lowest.resize(o + 1, kInf);
    object_lowest[o] = std::min(object_lowest[o], patches[k].centroid.z());
  }
  std::vector<double> low(keys.size()), top(keys.size());
  std::vector<std::size_t> points(keys.size());
  std::vector<std::uint32_t> held_by(keys.size());
  std::vector<std::pair<std::uint32_t, std::uint32_t>> by_height;  // (root, patch)
  for (bool joined = true; joined;) {
    std::fill(low.begin(), low.end(), kInf);
    std::fill(points.begin(), points.end(), 0);
    by_height.clear();
    for (std::uint32_t k = 0; k < keys.size(); ++k) {
      const std::uint32_t root = parts.find(k);
      low[root] = std::min(low[root], patches[k].centroid.z());
      points[root] += patches[k].count;
      by_height.emplace_back(root, k);
    }
    std::sort(by_height.begin(), by_height.end(), [&](const auto& a, const auto& b) {
      return a.first != b.first ? a.first < b.first
                                : patches[a.second].centroid.z() < patches[b.second].centroid.z();
    });
    // Each part's top: the height under which kTopShare of its points lie.
    std::size_t below = 0;
    for (std::size_t e = 0; e < by_height.size(); ++e) {
      const auto [root, k] = by_height[e];
      below = e > 0 && by_height[e - 1].first == root ? below : 0;
      if (static_cast<double>(below) < kTopShare * static_cast<double>(points[root])) {
        top[root] = patches[k].centroid.z();
      }
      below += patches[k].count;
    }
    std::fill(held_by.begin(), held_by.end(), kNone);
    for (const auto& [a, b] : adjacent) {
      const std::uint32_t ra = parts.find(a), rb = parts.find(b);
      if (ra == rb) continue;
      for (const auto& [part, other] : {std::make_pair(ra, rb), std::make_pair(rb, ra)}) {
        const std::size_t o = keys[part] >> 48;
        const double patch = patchOf(static_cast<std::int32_t>(o));
        if (low[part] > object_lowest[o] + patch && low[part] > low[other] + patch &&
            low[part] < top[other] - patch && top[part] <= top[other] + patch &&
            (held_by[part] == kNone || points[other] > points[held_by[part]])) {
          held_by[part] = other;
        }
      }
    }
    joined = false;
    for (std::uint32_t k = 0; k < keys.size(); ++k) {
      if (held_by[k] != kNone && parts.find(k) != parts.find(held_by[k])) {
        parts.join(k, held_by[k]);
        joined = true;
      }
    }
  }
}

}  // namespace

std::size_t splitAtConcaveCreases(const AlignedPoints& points, const Eigen::Vector3d& viewpoint,
                                  const CreaseParams& params,
                                  std::vector<std::int32_t>& object_of_point,
                                  std::vector<int>& parent) {
  parent.clear();
  int num_objects = 0;
  Eigen::Vector3f lowest = Eigen::Vector3f::Constant(std::numeric_limits<float>::infinity());
  Eigen::Vector3f highest = -lowest;
  for (std::size_t i = 0; i < object_of_point.size(); ++i) {
    if (object_of_point[i] < 0) continue;
    num_objects = std::max(num_objects, object_of_point[i] + 1);
    lowest = lowest.cwiseMin(points[i]);
    highest = highest.cwiseMax(points[i]);
  }
  const auto unchanged = [&] {
    parent.resize(static_cast<std::size_t>(num_objects));
    for (int o = 0; o < num_objects; ++o) parent[o] = o;
    return static_cast<std::size_t>(num_objects);
  };
  const auto patchOf = [&](std::int32_t object) {
    return params.object_patch.size() > static_cast<std::size_t>(object)
               ? params.object_patch[object]
               : params.patch;
  };
  double finest_patch = params.patch;
  for (int o = 0; o < num_objects; ++o) finest_patch = std::min(finest_patch, patchOf(o));
  if (num_objects == 0 || num_objects > kFieldLimit || !(finest_patch > 0) ||
      ((highest - lowest) / finest_patch).maxCoeff() >= kFieldLimit - 1) {
    return unchanged();
  }
  // Each object point's patch, then the distinct patches in key order. The patches' sides lie a
  // thousandth of a patch below multiples of a patch from the lowest corner (1 on top: the
  // field's margin): a cloud sampled on a lattice from there (a simulator's, a mesh's) has
  // samples on the sides, where float rounding would put a row either way and could leave a
  // layer of patches empty between two faces of one thing (a box's top cut off its sides).
  // The z layers start at the lowest point, the surface things stand on: a layer across it
  // would hold a sliver of every thing's foot (on mosd_dev, starting the layers half a patch
  // lower took the weighted overlap from 0.959 to 0.949).
  constexpr float kLatticeNudge = 1.001f;
  // Kept from frame to frame (cell_keys.h); room for every point ahead: growing it point by
  // point copied it several times over.
  thread_local std::vector<std::pair<std::uint64_t, std::uint32_t>> keyed;
  keyed.clear();
  keyed.reserve(object_of_point.size());
  for (std::size_t i = 0; i < object_of_point.size(); ++i) {
    if (object_of_point[i] < 0) continue;
    const Eigen::Vector3f q =
        (points[i] - lowest) / static_cast<float>(patchOf(object_of_point[i]));
    keyed.emplace_back((static_cast<std::uint64_t>(object_of_point[i]) << 48) |
                           (static_cast<std::uint64_t>(q.x() + kLatticeNudge) << 32) |
                           (static_cast<std::uint64_t>(q.y() + kLatticeNudge) << 16) |
                           static_cast<std::uint64_t>(q.z() + kLatticeNudge),
                       static_cast<std::uint32_t>(i));
  }
  sortByKey(keyed);
  std::vector<std::uint64_t> keys;
  thread_local std::vector<Patch> patches;  // kept from frame to frame (cell_keys.h)
  patches.clear();
  std::size_t num_patches = keyed.empty() ? 0 : 1;
  for (std::size_t e = 1; e < keyed.size(); ++e)
    num_patches += keyed[e].first != keyed[e - 1].first;
  keys.reserve(num_patches);
  patches.reserve(num_patches);
  thread_local std::vector<std::uint32_t> patch_of_entry;  // kept from frame to frame
  patch_of_entry.resize(keyed.size());
  for (std::size_t e = 0; e < keyed.size(); ++e) {
    if (keys.empty() || keys.back() != keyed[e].first) {
      keys.push_back(keyed[e].first);
      patches.emplace_back();
    }
    patch_of_entry[e] = static_cast<std::uint32_t>(keys.size() - 1);
    // Relative to the lowest corner: sums of squares of small numbers keep their precision.
    const Eigen::Vector3d q = (points[keyed[e].second] - lowest).cast<double>();
    Patch& patch = patches.back();
    ++patch.count;
    patch.sum += q;
    patch.outer += q * q.transpose();
  }
  const Eigen::Vector3d eye = viewpoint - lowest.cast<double>();
  for (Patch& patch : patches) {
    patch.centroid = patch.sum / static_cast<double>(patch.count);
    if (patch.count < kLeastPatchPoints) continue;
    const Eigen::Matrix3d covariance = patch.outer / static_cast<double>(patch.count) -
                                       patch.centroid * patch.centroid.transpose();
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver;
    solver.computeDirect(covariance);
    patch.normal = solver.eigenvectors().col(0);  // smallest eigenvalue first
    if (patch.normal.dot(eye - patch.centroid) < 0) patch.normal = -patch.normal;
    const Eigen::Vector3d spread = solver.eigenvalues();
    patch.tells_normal = spread(2) > 0 && spread(1) >= kLeastSurfaceSpread * spread(2);
    patch.flat = patch.tells_normal && spread(0) <= kMostFlatVariation * spread.sum();
  }

  // An object whose points lie mostly in patches that are not flat (a sparse cloud: too few
  // points per patch; a crumpled bag) shows no creases to cut at: it stays whole.
  std::vector<std::size_t> object_points(static_cast<std::size_t>(num_objects), 0),
      object_flat_points(static_cast<std::size_t>(num_objects), 0);
  for (std::size_t k = 0; k < keys.size(); ++k) {
    const std::size_t o = keys[k] >> 48;
    object_points[o] += patches[k].count;
    object_flat_points[o] += patches[k].flat ? patches[k].count : 0;
  }
  const auto whole = [&](std::uint64_t key) {
    const std::size_t o = key >> 48;
    return 10 * object_flat_points[o] < object_points[o];
  };
  // Adjacent patches (26-neighbourhood) of one object join when they meet smoothly or convexly.
  // Each pair once, from the smaller key, by one forward sweep per offset (as the objects' cells).
  const double smooth = std::cos(params.smooth_deg * M_PI / 180.0);
  // Convex: (n1 − n2)·(c1 − c2) > 0, and sane (LCCP's sanity criterion): the step between
  // the centroids runs across the line where the two planes meet, at 60° or more to it. Two
  // faces that touch only at a corner (a box's top edge beside another box's side) are
  // offset along that line, and their sign says nothing.
  const auto convex = [](const Patch& p, const Patch& q) {
    const Eigen::Vector3d step = p.centroid - q.centroid;
    if ((p.normal - q.normal).dot(step) <= 0) return false;
    const Eigen::Vector3d meet = p.normal.cross(q.normal);
    return std::fabs(meet.dot(step)) <= kSaneCos * meet.norm() * step.norm();
  };
  UnionFind parts(keys.size());
  thread_local std::vector<std::pair<std::uint32_t, std::uint32_t>> adjacent;  // kept, too
  adjacent.clear();
  for (int dx = 0; dx <= 1; ++dx) {
    for (int dy = -1; dy <= 1; ++dy) {
      for (int dz = -1; dz <= 1; ++dz) {
        if (dx == 0 && (dy < 0 || (dy == 0 && dz <= 0))) continue;
        std::size_t other = 0;
        for (std::uint32_t a = 0; a < keys.size(); ++a) {
          const std::uint64_t wanted = neighbourKey(keys[a], dx, dy, dz);
          while (other < keys.size() && keys[other] < wanted) ++other;
          if (other == keys.size()) break;
          if (keys[other] != wanted) continue;
          const auto b = static_cast<std::uint32_t>(other);
          adjacent.emplace_back(a, b);
          const Patch &p = patches[a], &q = patches[b];
          if (whole(keys[a]) ||
              (p.flat && q.flat && (std::fabs(p.normal.dot(q.normal)) >= smooth || convex(p, q)))) {
            parts.join(a, b);
          }
        }
      }
    }
  }
  // Patches that tell no normal (too few points, or one scanline: a noise-free camera's samples
  // on a surface seen at a slant or edge-on) carry no evidence of a crease. Those that touch
  // form one region; so does every other patch that is not flat (an edge, a corner) alone.
  constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();
  // The flags and counts apart from the patches' sums: the passes over the pairs below read
  // them for every pair, and a compact copy stays in cache.
  std::vector<std::uint8_t> flat(keys.size()), tells_normal(keys.size());
  std::vector<std::size_t> count(keys.size());
  for (std::size_t k = 0; k < keys.size(); ++k) {
    flat[k] = patches[k].flat;
    tells_normal[k] = patches[k].tells_normal;
    count[k] = patches[k].count;
  }
  UnionFind regions(keys.size());
  for (const auto& [a, b] : adjacent) {
    if (!tells_normal[a] && !tells_normal[b]) regions.join(a, b);
  }
  // A patch that is not flat belongs with the flat patch next to it that has the most points,
  // or, with none next to it, with its region's: it never bridges a concave crease.
  std::vector<std::uint32_t> region_flat(keys.size(), kNone);  // per region root
  std::vector<std::uint32_t> flat_neighbour(keys.size(), kNone);
  const auto better = [&](std::uint32_t& best, std::uint32_t to) {
    if (best == kNone || count[to] > count[best]) best = to;
  };
  for (const auto& [a, b] : adjacent) {
    if (flat[a] == flat[b]) continue;
    const std::uint32_t from = flat[a] ? b : a, to = flat[a] ? a : b;
    better(flat_neighbour[from], to);
    better(region_flat[regions.find(from)], to);
  }
  for (std::uint32_t k = 0; k < keys.size(); ++k) {
    if (flat[k]) continue;
    const std::uint32_t own = flat_neighbour[k], region = region_flat[regions.find(k)];
    if (own != kNone || region != kNone) parts.join(k, own != kNone ? own : region);
  }
  // The flat patches next to a region meet its flat patch across it: one surface when they lie
  // in one plane (parallel patches at two heights, the tops of two boxes, do not) or meet
  // convexly close by. Rows of sparse patches
  // between rows of flat ones (a noise-free camera's scanlines) would otherwise cut a box's top
  // into strips.
  const double coplanar = std::sin(params.coplanar_deg * M_PI / 180.0);
  const auto meetAcross = [&](const Patch& p, const Patch& q, double patch) {
    const Eigen::Vector3d step = p.centroid - q.centroid;
    // In one plane: normals within smooth_deg, the step between them running along both within
    // coplanar_deg and leaving each by at most two patch sides (the angle alone would let two
    // parallel tops a few centimetres apart in height join across a long region).
    const double off_plane = std::max(std::fabs(p.normal.dot(step)), std::fabs(q.normal.dot(step)));
    const bool one_plane = std::fabs(p.normal.dot(q.normal)) >= smooth &&
                           off_plane <= coplanar * step.norm() && off_plane <= 2 * patch;
    // A convex edge only across a region one or two patches wide: far apart, two faces of two
    // things that touch can look convex to each other.
    return one_plane || (step.norm() <= kConvexAcross * patch && convex(p, q));
  };
  for (const auto& [a, b] : adjacent) {
    if (tells_normal[a] == tells_normal[b]) continue;  // one tells no normal, the other does
    const std::uint32_t from = tells_normal[a] ? b : a, to = tells_normal[a] ? a : b;
    if (!flat[to]) continue;
    const std::uint32_t best = region_flat[regions.find(from)];
    const double patch = patchOf(static_cast<std::int32_t>(keys[to] >> 48));
    if (best != to && parts.find(best) != parts.find(to) &&
        meetAcross(patches[best], patches[to], patch)) {
      parts.join(best, to);
    }
  }
  // An edge patch (it tells a normal but is not flat: it holds two faces, or a curve, or a
  // face seen at a slant, whose noise spreads it) lies between flat patches that then touch no
  // flat patch of each other: a box's faces meeting at its edge, a ball's surface at its rim.
  // Flat patches next to one edge patch, or to two edge patches that touch, are one surface
  // when they meet as the regions' patches do above (in one plane, or convexly close by) and
  // the edge patches lie behind both their planes (within a quarter patch), as the edge
  // between two faces of one solid does. A thing's edge in front of another thing lies in
  // front of the far one's plane: the two stay apart (mOSD test52, a bottle before a jar), as
  // do two things that touch at a concave crease.
  // Each edge patch's flat neighbours, in one list (first_flat[e] .. first_flat[e + 1]).
  std::vector<std::uint32_t> first_flat(keys.size() + 1, 0), flat_of_edge;
  const auto edgeAndFlat = [&](std::uint32_t a, std::uint32_t b) {
    return flat[a] != flat[b] && tells_normal[flat[a] ? b : a];
  };
  for (const auto& [a, b] : adjacent) {
    if (edgeAndFlat(a, b)) ++first_flat[(flat[a] ? b : a) + 1];
  }
  for (std::size_t e = 0; e < keys.size(); ++e) first_flat[e + 1] += first_flat[e];
  flat_of_edge.resize(first_flat.back());
  {
    std::vector<std::uint32_t> next(first_flat.begin(), first_flat.end() - 1);
    for (const auto& [a, b] : adjacent) {
      if (edgeAndFlat(a, b)) flat_of_edge[next[flat[a] ? b : a]++] = flat[a] ? a : b;
    }
  }
  const auto behindBoth = [](const Patch& edge, const Patch& p, const Patch& q, double patch) {
    const double tolerance = 0.25 * patch;
    return p.normal.dot(edge.centroid - p.centroid) <= tolerance &&
           q.normal.dot(edge.centroid - q.centroid) <= tolerance;
  };
  const auto joinAcrossEdge = [&](std::uint32_t e1, std::uint32_t e2) {
    const double patch = patchOf(static_cast<std::int32_t>(keys[e1] >> 48));
    for (std::uint32_t i = first_flat[e1]; i < first_flat[e1 + 1]; ++i) {
      for (std::uint32_t j = e1 == e2 ? i + 1 : first_flat[e2]; j < first_flat[e2 + 1]; ++j) {
        const std::uint32_t p = flat_of_edge[i], q = flat_of_edge[j];
        if (parts.find(p) != parts.find(q) && meetAcross(patches[p], patches[q], patch) &&
            behindBoth(patches[e1], patches[p], patches[q], patch) &&
            behindBoth(patches[e2], patches[p], patches[q], patch)) {
          parts.join(p, q);
        }
      }
    }
  };
  for (std::uint32_t e = 0; e < keys.size(); ++e) joinAcrossEdge(e, e);
  for (const auto& [a, b] : adjacent) {
    if (!flat[a] && !flat[b] && tells_normal[a] && tells_normal[b]) joinAcrossEdge(a, b);
  }
  // Parts too small to be faces (a crease's own sliver, a handle's stub) join the neighbour
  // with the most points, in one round: a second round would also swallow the small objects
  // that the first left small. Then parts too small to be objects at all join theirs until none
  // is left that touches another part (each round at least halves them).
  std::vector<std::size_t> part_points(keys.size());
  std::vector<std::uint32_t> best_neighbour(keys.size());
  const auto joinSmallParts = [&](std::size_t least_points) {
    std::fill(part_points.begin(), part_points.end(), 0);
    for (std::uint32_t k = 0; k < keys.size(); ++k) part_points[parts.find(k)] += patches[k].count;
    std::fill(best_neighbour.begin(), best_neighbour.end(), kNone);
    for (const auto& [a, b] : adjacent) {
      const std::uint32_t ra = parts.find(a), rb = parts.find(b);
      if (ra == rb) continue;
      for (const auto& [small, large] : {std::make_pair(ra, rb), std::make_pair(rb, ra)}) {
        if (part_points[small] >= least_points) continue;
        std::uint32_t& best = best_neighbour[small];
        if (best == kNone || part_points[large] > part_points[best]) best = large;
      }
    }
    bool joined = false;
    for (std::uint32_t k = 0; k < keys.size(); ++k) {
      if (best_neighbour[k] != kNone && parts.find(k) != parts.find(best_neighbour[k])) {
        parts.join(k, best_neighbour[k]);
        joined = true;
      }
    }
    return joined;
  };
  joinSmallParts(params.min_part_points);
  while (joinSmallParts(params.min_points)) {
  }
  joinHangingParts(keys, patches, adjacent, patchOf, parts);
  // In an object joined across a gap (params.joined_across_gap), a part that touches no other
  // part of it was cut off by no crease (a table's leg whose top the table's edge hides): it
  // stays with the object's largest part.
  std::fill(part_points.begin(), part_points.end(), 0);
  for (std::uint32_t k = 0; k < keys.size(); ++k) part_points[parts.find(k)] += patches[k].count;
  std::vector<std::uint8_t> touches(keys.size(), 0);
  for (const auto& [a, b] : adjacent) {
    const std::uint32_t ra = parts.find(a), rb = parts.find(b);
    if (ra != rb) touches[ra] = touches[rb] = 1;
  }
  std::vector<std::uint32_t> largest(static_cast<std::size_t>(num_objects), kNone);
  for (std::uint32_t k = 0; k < keys.size(); ++k) {
    const std::uint32_t root = parts.find(k);
    std::uint32_t& best = largest[keys[k] >> 48];
    if (best == kNone || part_points[root] > part_points[best]) best = root;
  }
  for (std::uint32_t k = 0; k < keys.size(); ++k) {
    const std::uint32_t root = parts.find(k);
    const std::size_t o = keys[k] >> 48;
    if (!touches[root] && o < params.joined_across_gap.size() && params.joined_across_gap[o]) {
      parts.join(root, largest[o]);
    }
  }
  // The parts' indices in the order of their first point.
  std::vector<std::int32_t> index_of_part(keys.size(), -1);
  thread_local std::vector<std::uint32_t> patch_of_point;  // kept from frame to frame
  patch_of_point.resize(object_of_point.size());
  for (std::size_t e = 0; e < keyed.size(); ++e)
    patch_of_point[keyed[e].second] = patch_of_entry[e];
  for (std::size_t i = 0; i < object_of_point.size(); ++i) {
    if (object_of_point[i] < 0) continue;
    const std::uint32_t root = parts.find(patch_of_point[i]);
    if (index_of_part[root] < 0) {
      index_of_part[root] = static_cast<std::int32_t>(parent.size());
      parent.push_back(object_of_point[i]);
    }
    object_of_point[i] = index_of_part[root];
  }
  return parent.size();
}

}  // namespace hope
