// Persistent plane ids across frames: the paper's NNPM (§2.5) or an improved tracker.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "hope/plane.h"

namespace hope {

enum class TrackingMode {
  // §2.5 as published: nearest neighbour in jointly normalized (z_mean, bbox) space between
  // the previous and the current frame only; conflicts go to the closest.
  kPaper,
  // Gated, optimal one-to-one assignment on physical costs after removing the scene's
  // apparent motion (a turn and a shift estimated from a first pass, made both as the planes
  // are and after the last frame's motion, or searched within what a sensor can do between
  // the frames' stamps: 45°/s, 0.75 m/s), with memory of lost planes and explicit merge /
  // split handling. The default.
  kImproved,
};

// "paper" or "improved"; throws std::invalid_argument for anything else.
TrackingMode trackingModeFromString(const std::string& name);
const char* toString(TrackingMode mode);

struct TrackerOptions {
  TrackingMode mode = TrackingMode::kImproved;
  // Improved mode only. A plane cannot move more than this in height between two frames in
  // which it is seen (metres): a 30 cm jump is another surface.
  double max_height_change = 0.05;
  // ...nor can its xy bounding box end up further than this from where the scene's motion
  // puts it (metres).
  double max_xy_gap = 0.40;
  // Scales of the matching cost: a height difference of `height_scale` costs as much as a
  // bounding box gap of `xy_scale` or a complete loss of bounding-box overlap.
  double height_scale = 0.02;
  double xy_scale = 0.10;
  // A track and a plane are paired only when their cost is below this; otherwise the track
  // counts as missed and the plane as new. 9 = a 6 cm height change at full overlap.
  double max_match_cost = 9.0;
  // A plane not seen for up to this many frames keeps its id and can come back with it.
  int max_missed_frames = 30;
  // A lost plane whose bounding box lies at least this much (share of its own area) inside a
  // current plane at the same height (within height_scale / 2) was merged into it; a new plane
  // at the same height lying this much inside a matched plane's box split off it (0.01–1).
  double merge_split_overlap = 0.5;
};

// Throws std::invalid_argument naming the option that is out of range.
void validate(const TrackerOptions& options);

// What happened to an id in the last update, beyond an ordinary match.
struct TrackEvent {
  enum class Kind {
    kNew,        // `id` appeared (split-offs also report kSplit)
    kLost,       // `id` was not seen this frame; it is remembered (improved mode)
    kRecovered,  // `id` was seen again after `other_id` missed frames
    kMerged,     // `id` merged into `other_id` and ended (like ARCore's subsumedBy)
    kSplit,      // `id` is a new plane split off `other_id`, which kept its id
    kEnded,      // `id` was not seen for too long (or, in paper mode, for one frame)
  };
  Kind kind;
  int id;
  int other_id = -1;
};
const char* toString(TrackEvent::Kind kind);

class PlaneTracker {
 public:
  explicit PlaneTracker(const TrackerOptions& options = TrackerOptions());
  ~PlaneTracker();
  PlaneTracker(const PlaneTracker& other);
  PlaneTracker& operator=(const PlaneTracker& other);
  PlaneTracker(PlaneTracker&&) noexcept;
  PlaneTracker& operator=(PlaneTracker&&) noexcept;

  // Gives each plane of a new frame its persistent id, age and last_seen (in place) and
  // returns what happened to ids. Ids start at 0 in extraction order on the first frame and
  // are never reused. `stamp` is the frame time in seconds (the motion search reaches as far as a
  // sensor moves in the time since the last frame, from 1/30 s to 0.5 s).
  std::vector<TrackEvent> update(std::vector<HorizontalPlane>& planes, double stamp);

  // Forgets all planes and the scene's last motion; the next frame starts ids from where they
  // were (never reused).
  void reset();

  // Planes that are remembered but were not seen in the last frame (improved mode), with the
  // frame stamp they were last seen at.
  std::vector<HorizontalPlane> lostPlanes() const;
  const TrackerOptions& options() const { return options_; }

 private:
  struct Track {
    HorizontalPlane plane;  // as last seen
    int missed = 0;
    // The scene's apparent motion since the plane was last seen (a turn about the vertical
    // axis through the origin, then a shift), applied to `plane` when it is compared: kept
    // apart so that turning its bounding box frame after frame does not inflate it.
    double turned = 0.0;
    Eigen::Vector3d shifted = Eigen::Vector3d::Zero();
  };
  std::vector<TrackEvent> updatePaper(std::vector<HorizontalPlane>& planes, double stamp);
  std::vector<TrackEvent> updateImproved(std::vector<HorizontalPlane>& planes, double stamp);
  void startTrack(HorizontalPlane& plane, double stamp, std::vector<TrackEvent>& events);

  TrackerOptions options_;
  std::vector<Track> tracks_;
  int next_id_ = 0;
  // The scene's apparent motion over the last frame (improved mode): a sensor moves on much as
  // it moved, so the next frame's first pairing is also tried with it.
  double last_turn_ = 0.0;
  Eigen::Vector3d last_shift_ = Eigen::Vector3d::Zero();
  // Gating indexes and the planes' boxes and heights in compact arrays, kept so that their
  // memory is reused frame after frame (not copied with the tracker).
  struct Scratch;
  std::unique_ptr<Scratch> scratch_;
};

}  // namespace hope
