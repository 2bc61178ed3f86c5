#include "hope/plane_tracker.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

#include <Eigen/Geometry>

#include "hope/box_index.h"
#include "hope/optimal_assignment.h"
#include "hope/plane_matching.h"

namespace hope {

TrackingMode trackingModeFromString(const std::string& name) {
  if (name == "paper") return TrackingMode::kPaper;
  if (name == "improved") return TrackingMode::kImproved;
  throw std::invalid_argument("unknown tracking mode '" + name + "' (use paper or improved)");
}

const char* toString(TrackingMode mode) {
  return mode == TrackingMode::kPaper ? "paper" : "improved";
}

const char* toString(TrackEvent::Kind kind) {
  switch (kind) {
    case TrackEvent::Kind::kNew:
      return "new";
    case TrackEvent::Kind::kLost:
      return "lost";
    case TrackEvent::Kind::kRecovered:
      return "recovered";
    case TrackEvent::Kind::kMerged:
      return "merged";
    case TrackEvent::Kind::kSplit:
      return "split";
    case TrackEvent::Kind::kEnded:
      return "ended";
  }
  return "?";
}

void validate(const TrackerOptions& o) {
  auto require = [](const char* name, double value, double lo, double hi) {
    if (!std::isfinite(value) || value < lo || value > hi) {
      std::ostringstream msg;
      msg << "tracker option " << name << " = " << value << " is out of range [" << lo << ", " << hi
          << "]";
      throw std::invalid_argument(msg.str());
    }
  };
  require("max_height_change (m)", o.max_height_change, 1e-4, 100.0);
  require("max_xy_gap (m)", o.max_xy_gap, 0.0, 1000.0);
  require("height_scale (m)", o.height_scale, 1e-4, 100.0);
  require("xy_scale (m)", o.xy_scale, 1e-4, 1000.0);
  require("max_match_cost", o.max_match_cost, 1e-3, 1e6);
  require("max_missed_frames", o.max_missed_frames, 0, 1e6);
  // A share of 0 would make every plane at the same height a part of any other.
  require("merge_split_overlap", o.merge_split_overlap, 0.01, 1.0);
}

namespace {

// Bounding boxes thinner than a millimetre still have an area, so overlap shares stay finite.
constexpr double kMinBoxSide = 1e-3;
// Pairs beyond a gate get this cost, which no pairing is worth.
constexpr double kForbidden = 1e9;
// A scene motion below both is not compensated: 1 mm, and 0.1 mrad (1 mm at 10 m).
constexpr double kNegligibleShift = 1e-3;
constexpr double kNegligibleTurn = 1e-4;

double boxArea(const std::array<double, 4>& b) {
  return std::max(b[2] - b[0], kMinBoxSide) * std::max(b[3] - b[1], kMinBoxSide);
}

double intersectionArea(const std::array<double, 4>& a, const std::array<double, 4>& b) {
  const double dx = std::min(a[2], b[2]) - std::max(a[0], b[0]);
  const double dy = std::min(a[3], b[3]) - std::max(a[1], b[1]);
  return std::max(dx, 0.0) * std::max(dy, 0.0);
}

// Share of box `a` that lies inside box `b`.
double shareInside(const std::array<double, 4>& a, const std::array<double, 4>& b) {
  return std::min(1.0, intersectionArea(a, b) / boxArea(a));
}

// The square of the xy gap between two boxes (0 when they touch or overlap): the cost needs
// only the square, and the gate compares squares.
double squaredBoxGap(const std::array<double, 4>& a, const std::array<double, 4>& b) {
  const double gx = std::max(std::max(a[0] - b[2], b[0] - a[2]), 0.0);
  const double gy = std::max(std::max(a[1] - b[3], b[1] - a[3]), 0.0);
  return gx * gx + gy * gy;
}

// Parts of one surface (a split, a merge) lie at the same height within noise; a book on a
// table, 5 cm above it, must not count as merged into the table when it is briefly hidden.
double sameSurfaceHeight(const TrackerOptions& o) { return 0.5 * o.height_scale; }

// The apparent motion of the whole scene between two frames in the reference frame: a turn
// by `yaw` about the vertical axis through the origin, then a shift. With gravity only, the
// reference frame's origin is the sensor, so a camera's yaw turns the scene about it.
struct SceneMotion {
  double yaw = 0.0;
  Eigen::Vector3d shift = Eigen::Vector3d::Zero();
};

// Far below the cost scales (a static sensor: the median of the planes' jitter): removing it
// would change no cost measurably.
bool negligible(const SceneMotion& motion) {
  return !(std::fabs(motion.yaw) > kNegligibleTurn || motion.shift.norm() > kNegligibleShift);
}

// What the pairing cost needs of a remembered plane, after the scene's motion.
struct MovedPlane {
  std::array<double, 4> bbox;
  double height;
  int age;
};

MovedPlane movedPlane(const HorizontalPlane& plane, const SceneMotion& motion) {
  if (motion.yaw == 0.0 && motion.shift.isZero()) return {plane.bbox, plane.height, plane.age};
  const Eigen::Rotation2Dd turn(motion.yaw);
  const Eigen::Vector2d t = motion.shift.head<2>();
  const auto& b = plane.bbox;
  Eigen::Vector2d lo(HUGE_VAL, HUGE_VAL), hi(-HUGE_VAL, -HUGE_VAL);
  for (const Eigen::Vector2d& corner : {Eigen::Vector2d(b[0], b[1]), Eigen::Vector2d(b[2], b[1]),
                                        Eigen::Vector2d(b[0], b[3]), Eigen::Vector2d(b[2], b[3])}) {
    const Eigen::Vector2d c = turn * corner + t;
    lo = lo.cwiseMin(c);
    hi = hi.cwiseMax(c);
  }
  return {{lo.x(), lo.y(), hi.x(), hi.y()}, plane.height + motion.shift.z(), plane.age};
}

// `plane` as it would appear after `motion`: height, bounding box (of the turned box's
// corners) and centroid.
HorizontalPlane moved(const HorizontalPlane& plane, const SceneMotion& motion) {
  HorizontalPlane out = plane;
  const Eigen::Rotation2Dd turn(motion.yaw);
  const Eigen::Vector2d t = motion.shift.head<2>();
  const MovedPlane footprint = movedPlane(plane, motion);
  out.bbox = footprint.bbox;
  out.height = footprint.height;
  out.centroid.head<2>() = turn * plane.centroid.head<2>() + t;
  out.centroid.z() += motion.shift.z();
  for (Eigen::Vector3d& h : out.hull) {
    h.head<2>() = turn * h.head<2>() + t;
    h.z() += motion.shift.z();
  }
  return out;
}

// `first` followed by `second`.
SceneMotion compose(const SceneMotion& first, const SceneMotion& second) {
  SceneMotion both;
  both.yaw = first.yaw + second.yaw;
  both.shift.head<2>() =
      Eigen::Rotation2Dd(second.yaw) * first.shift.head<2>() + second.shift.head<2>();
  both.shift.z() = first.shift.z() + second.shift.z();
  return both;
}

template <class Track>
SceneMotion sinceSeen(const Track& track) {
  SceneMotion m;
  m.yaw = track.turned;
  m.shift = track.shifted;
  return m;
}

// Cost of continuing `before` with `now`: height change and xy gap in units of their scales,
// plus two overlap terms of the bounding boxes. One minus the intersection over union,
// weighted close to the pairing limit: a fragment inside a big plane's box (IoU near 0) must
// not be worth pairing with it, or the assignment would trade the big plane's id to a
// fragment to pair more planes. The share of the smaller box outside the other, so a plane
// seen only in part still prefers its whole over a neighbour. A tiny bonus for age lets the
// older id win exact ties. Pairs beyond the gates cost kForbidden.
constexpr double kIouWeight = 0.8;
// `now` is a plane's box and height (read from compact arrays: the planes themselves are
// large structs, and the gating touches many of them).
double pairingCost(const MovedPlane& before, const BoxIndex::Box& now_bbox, double now_height,
                   const TrackerOptions& o) {
  const double dz = std::fabs(now_height - before.height);
  if (dz > o.max_height_change) return kForbidden;
  const double squared_gap = squaredBoxGap(before.bbox, now_bbox);
  if (squared_gap > o.max_xy_gap * o.max_xy_gap) return kForbidden;
  const double area_before = boxArea(before.bbox), area_now = boxArea(now_bbox);
  const double common = intersectionArea(before.bbox, now_bbox);
  const double overlap = std::min(1.0, common / std::min(area_before, area_now));
  const double iou = common / (area_before + area_now - common);
  const double height_term = dz / o.height_scale;
  return height_term * height_term + squared_gap / (o.xy_scale * o.xy_scale) + (1.0 - overlap) +
         kIouWeight * o.max_match_cost * (1.0 - iou) - 1e-6 * std::min(before.age, 1000);
}

// How far apart in xy a track and a plane can be and still cost less than `limit`. Boxes a
// gap apart share nothing (overlap and IoU 0), so such a pair costs at least
// 1 + kIouWeight·max_match_cost + (gap / xy_scale)², less the age bonus (at most 1e-3): with
// the defaults no pair more than 9 cm apart is ever made, whatever the 40 cm gate allows, and
// the search looks that far only. (A little slack keeps rounding from losing a pair on the
// edge; the exact test is the cost.)
double pairingReach(const TrackerOptions& o, double limit) {
  const double spare = limit - 1.0 - kIouWeight * o.max_match_cost + 1e-3;
  const double reach = spare > 0 ? o.xy_scale * std::sqrt(spare) : 0.0;
  return std::min(o.max_xy_gap, 1.001 * reach + 1e-9);
}

// Cells of the gating index: twice the search reach, so a small box grown by it spans about
// 2 x 2 cells (at least 40 cm: smaller cells cost more probes than they save visits), and four
// times the height gate, so a query spans one or two cells in height.
double gateCell(double reach) { return std::max(2.0 * reach, 0.4); }
double gateHeightCell(const TrackerOptions& o) { return 4.0 * o.max_height_change; }

// The pairs of a track (moved by the scene's motion) and a plane that pass the gates and
// cost less than `limit` (no dearer pair is ever made), priced.
// `boxes` and `heights` are the planes', in the order `index` was built from.
template <class Track>
std::vector<CandidatePair> candidatePairs(const std::vector<Track>& tracks,
                                          const std::vector<BoxIndex::Box>& boxes,
                                          const std::vector<double>& heights, const BoxIndex& index,
                                          const SceneMotion& motion, const TrackerOptions& o,
                                          double limit) {
  std::vector<CandidatePair> pairs;
  pairs.reserve(2 * tracks.size());
  const double reach = pairingReach(o, limit);
  for (std::size_t t = 0; t < tracks.size(); ++t) {
    const MovedPlane before = movedPlane(tracks[t].plane, compose(sinceSeen(tracks[t]), motion));
    index.forEachNear(before.bbox, before.height, reach, o.max_height_change, [&](int p) {
      const double cost = pairingCost(before, boxes[p], heights[p], o);
      if (cost < limit) pairs.push_back({static_cast<int>(t), p, cost});
    });
  }
  return pairs;
}

// How far a sensor carried by a person or a robot moves between two frames at most: it turns
// up to 45°/s, moves up to 0.75 m/s and climbs up to 0.25 m/s (a walking person's hand or
// head, a mobile base). Frames count at least a video frame apart and at most half a second
// (beyond that, the search would grow past its use; the measured motions still apply).
constexpr double kMaxTurnRate = 45.0 * M_PI / 180.0;                     // rad/s
constexpr double kMaxSpeed = 0.75;                                       // m/s
constexpr double kMaxClimbRate = 0.25;                                   // m/s
constexpr double kMinFrameSpacing = 1.0 / 30.0, kMaxFrameSpacing = 0.5;  // s

// The scene's motion is the large planes' (as estimateMotion weighs them): the search looks at
// the kMotionPlanes largest planes and tracks only, so that a frame of a thousand fragments
// costs no more than one of thirty planes.
constexpr std::size_t kMotionPlanes = 32;

// The indices of the `most` largest of `planes` (by point count), in any order.
std::vector<std::size_t> largest(const std::vector<const HorizontalPlane*>& planes,
                                 std::size_t most) {
  std::vector<std::size_t> order(planes.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  if (order.size() > most) {
    std::nth_element(order.begin(), order.begin() + static_cast<std::ptrdiff_t>(most), order.end(),
                     [&](std::size_t a, std::size_t b) {
                       return planes[a]->num_points > planes[b]->num_points;
                     });
    order.resize(most);
  }
  return order;
}

// The scene's motion from the last frame to this one at `stamp`, searched on a grid of turns
// and shifts within what a sensor can move in the time between: the motions measured from pairs
// made as the planes are, or after the last frame's motion, need those pairs, and a hand-held
// camera at 3 Hz turning 8° moves a plane 2 m away by 28 cm, past the 9 cm any pair reaches. Each
// motion is scored by the sum over the planes of the cheapest pairing with a track seen in the
// last frame (the unpaired cost at most; one to one is the assignment's job, made once for the
// best). The grid's steps follow the cost's scales: half of xy_scale across, half of
// height_scale in height, and the turn that moves the tracks' median distance from the
// origin by the xy step (at least 1 m away). Coarse to fine: four steps apart over the whole
// reach, then two and one step apart, two either side of the best so far. Ties keep the
// smaller motion: no motion is scored first.
template <class Track>
SceneMotion searchMotion(const std::vector<Track>& tracks,
                         const std::vector<HorizontalPlane>& planes, const TrackerOptions& o,
                         double unpaired, double stamp) {
  std::vector<const HorizontalPlane*> last_seen, now;
  double last_stamp = -HUGE_VAL;  // the last frame's: its tracks were seen then
  for (const Track& t : tracks) {
    if (t.missed > 0) continue;
    last_seen.push_back(&t.plane);
    last_stamp = std::max(last_stamp, t.plane.last_seen);
  }
  for (const HorizontalPlane& p : planes) now.push_back(&p);
  std::vector<const HorizontalPlane*> seen;
  std::vector<double> distances;
  for (std::size_t i : largest(last_seen, kMotionPlanes)) {
    seen.push_back(last_seen[i]);
    distances.push_back(last_seen[i]->centroid.head<2>().norm());
  }
  std::vector<BoxIndex::Box> boxes;
  std::vector<double> heights;
  for (std::size_t i : largest(now, kMotionPlanes)) {
    boxes.push_back(now[i]->bbox);
    heights.push_back(now[i]->height);
  }
  if (seen.empty() || boxes.empty()) return SceneMotion();
  std::nth_element(distances.begin(), distances.begin() + distances.size() / 2, distances.end());
  const double radius = std::max(1.0, distances[distances.size() / 2]);
  double spacing = stamp - last_stamp;
  if (!(spacing >= kMinFrameSpacing)) spacing = kMinFrameSpacing;  // also NaN
  spacing = std::min(spacing, kMaxFrameSpacing);
  const double xy_step = 0.5 * o.xy_scale, z_step = 0.5 * o.height_scale;
  const double turn_step = xy_step / radius;
  // A little over the limits, so that rounding does not drop a step that lies on one.
  const double turn_range = 1.001 * kMaxTurnRate * spacing, xy_range = 1.001 * kMaxSpeed * spacing,
               z_range = 1.001 * kMaxClimbRate * spacing;
  std::vector<MovedPlane> moved_tracks(seen.size());
  const auto score = [&](const SceneMotion& motion) {
    for (std::size_t t = 0; t < seen.size(); ++t) moved_tracks[t] = movedPlane(*seen[t], motion);
    double total = 0.0;
    for (std::size_t p = 0; p < boxes.size(); ++p) {
      double cheapest = unpaired;
      for (const MovedPlane& before : moved_tracks) {
        cheapest = std::min(cheapest, pairingCost(before, boxes[p], heights[p], o));
      }
      total += cheapest;
    }
    return total;
  };
  SceneMotion best;
  double best_score = score(best);
  // Every motion centre + k·step for |k| <= reach in each of yaw, x, y, z.
  const auto sweep = [&](const SceneMotion& centre, double scale, int turns, int shifts,
                         int climbs) {
    const SceneMotion from = centre;  // a copy: `best` may be the centre, and changes
    for (int k = -turns; k <= turns; ++k) {
      for (int z = -climbs; z <= climbs; ++z) {
        for (int x = -shifts; x <= shifts; ++x) {
          for (int y = -shifts; y <= shifts; ++y) {
            if (k == 0 && z == 0 && x == 0 && y == 0) continue;
            SceneMotion motion;
            motion.yaw = from.yaw + k * scale * turn_step;
            motion.shift =
                from.shift + scale * Eigen::Vector3d(x * xy_step, y * xy_step, z * z_step);
            if (std::fabs(motion.yaw) > turn_range || std::fabs(motion.shift.x()) > xy_range ||
                std::fabs(motion.shift.y()) > xy_range || std::fabs(motion.shift.z()) > z_range) {
              continue;
            }
            const double s = score(motion);
            if (s < best_score) {
              best_score = s;
              best = motion;
            }
          }
        }
      }
    }
  };
  const auto steps = [](double range, double step) {
    return static_cast<int>(std::floor(range / step));
  };
  sweep(SceneMotion(), 4.0, steps(turn_range, 4 * turn_step), steps(xy_range, 4 * xy_step),
        steps(z_range, 4 * z_step));
  sweep(best, 2.0, 2, 2, 2);
  sweep(best, 1.0, 2, 2, 2);
  return best;
}

// The weighted median of (value, weight) pairs: the smallest value at which the running
// weight, in ascending order of value, reaches half the total. Found by selection (expected
// linear time) rather than a full sort: it runs four times per motion measured (up to two a
// frame) over every pair.
double weightedMedian(std::vector<std::pair<double, double>>& samples) {
  double total = 0;
  for (const auto& s : samples) total += s.second;
  const double half = 0.5 * total;
  auto first = samples.begin(), last = samples.end();
  double below = 0;  // weight of the samples left of `first`, all smaller than the rest
  while (last - first > 1) {
    const auto mid = first + (last - first) / 2;
    std::nth_element(first, mid, last);
    double left = below;
    for (auto it = first; it != mid; ++it) left += it->second;
    if (left >= half) {
      last = mid;
    } else if (left + mid->second >= half) {
      return mid->first;
    } else {
      below = left + mid->second;
      first = mid + 1;
    }
  }
  return first->first;
}

// The apparent motion of the scene from the pairs with tracks seen in the previous frame,
// each weighted by its point count so that big planes outvote flickering fragments: the yaw
// is the weighted median turn of the centroids about the origin (from planes at least 0.5 m
// from it, where a turn is measurable), the shift the weighted median displacement of the
// turned bounding-box centres and heights. False when fewer than 3 pairs make it unreliable.
template <class Track>
bool estimateMotion(const std::vector<Track>& tracks, const std::vector<HorizontalPlane>& planes,
                    const std::vector<int>& assigned, SceneMotion& motion) {
  std::vector<std::pair<double, double>> turns;
  std::vector<std::size_t> pairs;
  for (std::size_t t = 0; t < tracks.size(); ++t) {
    if (assigned[t] < 0 || tracks[t].missed > 0) continue;
    pairs.push_back(t);
    const Eigen::Vector2d a = tracks[t].plane.centroid.template head<2>();
    const Eigen::Vector2d b = planes[assigned[t]].centroid.template head<2>();
    if (a.norm() < 0.5 || b.norm() < 0.5) continue;
    const double turn =
        std::remainder(std::atan2(b.y(), b.x()) - std::atan2(a.y(), a.x()), 2.0 * M_PI);
    turns.emplace_back(
        turn, static_cast<double>(std::max<std::size_t>(planes[assigned[t]].num_points, 1)));
  }
  if (pairs.size() < 3) return false;
  motion.yaw = turns.size() >= 3 ? weightedMedian(turns) : 0.0;
  const Eigen::Rotation2Dd turn(motion.yaw);
  std::vector<std::pair<double, double>> dx, dy, dz;
  for (std::size_t t : pairs) {
    const HorizontalPlane& now = planes[assigned[t]];
    const auto& a = tracks[t].plane.bbox;
    const auto& b = now.bbox;
    const Eigen::Vector2d from = turn * Eigen::Vector2d(0.5 * (a[0] + a[2]), 0.5 * (a[1] + a[3]));
    const double weight = static_cast<double>(std::max<std::size_t>(now.num_points, 1));
    dx.emplace_back(0.5 * (b[0] + b[2]) - from.x(), weight);
    dy.emplace_back(0.5 * (b[1] + b[3]) - from.y(), weight);
    dz.emplace_back(now.height - tracks[t].plane.height, weight);
  }
  motion.shift = Eigen::Vector3d(weightedMedian(dx), weightedMedian(dy), weightedMedian(dz));
  return true;
}

}  // namespace

struct PlaneTracker::Scratch {
  BoxIndex planes_index, matched_index;
  std::vector<BoxIndex::Box> boxes;
  std::vector<double> heights;
};

PlaneTracker::PlaneTracker(const TrackerOptions& options)
    : options_(options), scratch_(std::make_unique<Scratch>()) {
  validate(options_);
}
PlaneTracker::~PlaneTracker() = default;
PlaneTracker::PlaneTracker(const PlaneTracker& other)
    : options_(other.options_),
      tracks_(other.tracks_),
      next_id_(other.next_id_),
      last_turn_(other.last_turn_),
      last_shift_(other.last_shift_),
      scratch_(std::make_unique<Scratch>()) {}
PlaneTracker& PlaneTracker::operator=(const PlaneTracker& other) {
  if (this != &other) {
    options_ = other.options_;
    tracks_ = other.tracks_;
    next_id_ = other.next_id_;
    last_turn_ = other.last_turn_;
    last_shift_ = other.last_shift_;
  }
  return *this;
}
PlaneTracker::PlaneTracker(PlaneTracker&&) noexcept = default;
PlaneTracker& PlaneTracker::operator=(PlaneTracker&&) noexcept = default;

void PlaneTracker::reset() {
  tracks_.clear();
  last_turn_ = 0.0;
  last_shift_ = Eigen::Vector3d::Zero();
}

std::vector<HorizontalPlane> PlaneTracker::lostPlanes() const {
  std::vector<HorizontalPlane> lost;
  for (const Track& t : tracks_)
    if (t.missed > 0) lost.push_back(moved(t.plane, sinceSeen(t)));
  return lost;
}

std::vector<TrackEvent> PlaneTracker::update(std::vector<HorizontalPlane>& planes, double stamp) {
  return options_.mode == TrackingMode::kPaper ? updatePaper(planes, stamp)
                                               : updateImproved(planes, stamp);
}

void PlaneTracker::startTrack(HorizontalPlane& plane, double stamp,
                              std::vector<TrackEvent>& events) {
  plane.id = next_id_++;
  plane.age = 1;
  plane.last_seen = stamp;
  events.push_back({TrackEvent::Kind::kNew, plane.id});
}

std::vector<TrackEvent> PlaneTracker::updatePaper(std::vector<HorizontalPlane>& planes,
                                                  double stamp) {
  std::vector<TrackEvent> events;
  std::vector<HorizontalPlane> previous;
  for (const Track& t : tracks_) previous.push_back(t.plane);
  const std::vector<NearestNeighborMatch> matches = matchNearestNeighbors(previous, planes);
  std::vector<char> continued(previous.size(), 0);
  for (std::size_t j = 0; j < planes.size(); ++j) {
    planes[j].split_from = -1;
    const int i = matches[j].previous;
    if (i < 0) {
      startTrack(planes[j], stamp, events);
      continue;
    }
    continued[i] = 1;
    planes[j].id = previous[i].id;
    planes[j].age = previous[i].age + 1;
    planes[j].last_seen = stamp;
  }
  for (std::size_t i = 0; i < previous.size(); ++i) {
    if (!continued[i]) events.push_back({TrackEvent::Kind::kEnded, previous[i].id});
  }
  tracks_.clear();
  for (const HorizontalPlane& p : planes) tracks_.push_back({p, 0, 0.0, Eigen::Vector3d::Zero()});
  return events;
}

std::vector<TrackEvent> PlaneTracker::updateImproved(std::vector<HorizontalPlane>& planes,
                                                     double stamp) {
  const TrackerOptions& o = options_;
  std::vector<TrackEvent> events;
  const int num_tracks = static_cast<int>(tracks_.size());
  const int num_planes = static_cast<int>(planes.size());

  // A first pairing of the planes as they are gives the apparent motion of the whole scene (a
  // turn about the origin and a shift: large when only gravity is known, so the reference
  // frame moves with the camera), which a second pairing removes first; so does one made after
  // the last frame's motion. A motion is kept only when it explains the frame better than the
  // pairing kept so far.
  const double unpaired = 0.5 * o.max_match_cost;
  // Each track is priced against the planes near it only (gating before assignment: all
  // tracks × all planes would cost n²).
  scratch_->boxes.clear();
  scratch_->heights.clear();
  for (const HorizontalPlane& p : planes) {
    scratch_->boxes.push_back(p.bbox);
    scratch_->heights.push_back(p.height);
  }
  BoxIndex& planes_near = scratch_->planes_index;
  planes_near.rebuild(scratch_->boxes, scratch_->heights, gateCell(pairingReach(o, 2 * unpaired)),
                      gateHeightCell(o));
  const auto assignAfter = [&](const SceneMotion& m) {
    return assignWithUnpairedCost(candidatePairs(tracks_, scratch_->boxes, scratch_->heights,
                                                 planes_near, m, o, 2 * unpaired),
                                  num_tracks, num_planes, unpaired);
  };
  SceneMotion motion;
  SparseAssignment assignment = assignAfter(motion);
  // The motion the pairs of `first` measure, kept when pairing after it explains the frame
  // better than the best so far; a negligible one is not tried.
  const auto tryMeasuredMotion = [&](const SparseAssignment& first) {
    SceneMotion estimate;
    if (!estimateMotion(tracks_, planes, first.col_of_row, estimate) || negligible(estimate)) {
      return;
    }
    SparseAssignment compensated = assignAfter(estimate);
    if (compensated.total_cost < assignment.total_cost) {
      assignment = std::move(compensated);
      motion = estimate;
    }
  };
  // `first` is read only before `assignment` is replaced: the unmoved pairing itself may go in.
  tryMeasuredMotion(assignment);
  // A sensor moves on much as it moved: the pairs made after the last frame's motion measure
  // this frame's too, where the scene moved past the reach of pairs made as it is (a hand-held
  // camera at 3 Hz: ~7 cm and 4° a frame). Only the motion they measure is used, never the
  // last one itself, so a wrong motion is not carried on.
  SceneMotion last;
  last.yaw = last_turn_;
  last.shift = last_shift_;
  if (!negligible(last)) tryMeasuredMotion(assignAfter(last));
  // Where neither pairing reached the scene's motion (a sensor turning faster than it did),
  // the motion searched within what a sensor can move since the last frame (searchMotion). Its
  // pairing is kept only when it continues more planes than the pairing kept so far, not for
  // a lower cost alone: a turned box's corners span a larger box, which overlaps more, so a
  // small false turn would often cost less than none.
  const SceneMotion searched = searchMotion(tracks_, planes, o, unpaired, stamp);
  if (!negligible(searched)) {
    SparseAssignment after = assignAfter(searched);
    const auto paired = [](const SparseAssignment& a) {
      return std::count_if(a.col_of_row.begin(), a.col_of_row.end(), [](int p) { return p >= 0; });
    };
    if (paired(after) > paired(assignment)) {
      assignment = std::move(after);
      motion = searched;
    }
  }
  const std::vector<int>& assigned = assignment.col_of_row;
  last_turn_ = motion.yaw;
  last_shift_ = motion.shift;

  std::vector<int> track_of_plane(num_planes, -1);
  for (int t = 0; t < num_tracks; ++t) {
    if (assigned[t] >= 0) track_of_plane[assigned[t]] = t;
  }
  std::vector<char> matched(num_tracks, 0);
  for (int p = 0; p < num_planes; ++p) {
    HorizontalPlane& plane = planes[p];
    plane.split_from = -1;
    const int t = track_of_plane[p];
    if (t < 0) continue;
    matched[t] = 1;
    const Track& track = tracks_[t];
    if (track.missed > 0)
      events.push_back({TrackEvent::Kind::kRecovered, track.plane.id, track.missed});
    plane.id = track.plane.id;
    plane.age = track.plane.age + 1;
    plane.last_seen = stamp;
  }

  // New planes; one lying mostly inside the box of a continued plane at about the same
  // height is a part that split off it (the larger part kept the id through the assignment).
  // The continued planes' boxes (moved by the scene's motion) are indexed so that each new
  // plane is compared with those it overlaps only.
  // (In a steady scene no plane is new, and the index is not built.)
  const bool any_new = std::count(track_of_plane.begin(), track_of_plane.end(), -1) > 0;
  std::vector<int> matched_tracks;
  std::vector<BoxIndex::Box> matched_boxes;
  std::vector<double> matched_heights;
  for (int t = 0; any_new && t < num_tracks; ++t) {
    if (!matched[t]) continue;
    const MovedPlane before = movedPlane(tracks_[t].plane, compose(sinceSeen(tracks_[t]), motion));
    matched_tracks.push_back(t);
    matched_boxes.push_back(before.bbox);
    matched_heights.push_back(before.height);
  }
  BoxIndex& matched_near = scratch_->matched_index;
  if (any_new) {
    matched_near.rebuild(matched_boxes, matched_heights, gateCell(0.0), gateHeightCell(o));
  }
  for (int p = 0; p < num_planes; ++p) {
    if (track_of_plane[p] >= 0) continue;
    startTrack(planes[p], stamp, events);
    int parent = -1;  // the first such track, as tracks are ordered
    matched_near.forEachNear(
        planes[p].bbox, planes[p].height, 0.0, sameSurfaceHeight(o), [&](int k) {
          const int t = matched_tracks[k];
          if ((parent < 0 || t < parent) &&
              std::fabs(matched_heights[k] - planes[p].height) <= sameSurfaceHeight(o) &&
              shareInside(planes[p].bbox, matched_boxes[k]) >= o.merge_split_overlap) {
            parent = t;
          }
        });
    if (parent >= 0) {
      planes[p].split_from = tracks_[parent].plane.id;
      events.push_back({TrackEvent::Kind::kSplit, planes[p].id, tracks_[parent].plane.id});
    }
  }

  // Planes not seen: merged into a current plane that now covers them, or lost (remembered
  // for a while), or ended.
  std::vector<Track> next;
  next.reserve(num_tracks + num_planes);
  for (int t = 0; t < num_tracks; ++t) {
    if (matched[t]) continue;
    Track track = tracks_[t];
    // A remembered plane moves with the rest of the scene.
    const SceneMotion since = compose(sinceSeen(track), motion);
    track.turned = since.yaw;
    track.shifted = since.shift;
    int merged_into = -1;
    if (track.missed == 0) {
      const MovedPlane before = movedPlane(track.plane, since);
      int first = num_planes;  // the first such plane, as planes are ordered
      planes_near.forEachNear(before.bbox, before.height, 0.0, sameSurfaceHeight(o), [&](int p) {
        const HorizontalPlane& now = planes[p];
        if (p < first && now.id != track.plane.id &&
            std::fabs(now.height - before.height) <= sameSurfaceHeight(o) &&
            shareInside(before.bbox, now.bbox) >= o.merge_split_overlap) {
          first = p;
        }
      });
      if (first < num_planes) merged_into = planes[first].id;
    }
    if (merged_into >= 0) {
      events.push_back({TrackEvent::Kind::kMerged, track.plane.id, merged_into});
      continue;
    }
    if (++track.missed > o.max_missed_frames) {
      events.push_back({TrackEvent::Kind::kEnded, track.plane.id});
      continue;
    }
    if (track.missed == 1) events.push_back({TrackEvent::Kind::kLost, track.plane.id});
    next.push_back(std::move(track));
  }
  for (const HorizontalPlane& p : planes) next.push_back({p, 0, 0.0, Eigen::Vector3d::Zero()});
  tracks_ = std::move(next);
  return events;
}

}  // namespace hope
