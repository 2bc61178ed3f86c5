// A map of the surfaces seen in a fixed frame (a pose per frame, or tf to odom / map): each
// physical surface one entry, its id kept until it is out of view for forget_after_frames. The
// paper's NNPM (§2.5) and the PlaneTracker keep ids between recent frames; a robot that looks away
// and back, or walks around a room, wants each table once, with all it has seen of it (as ARCore
// keeps its planes and says which plane subsumed which). An entry's extent is the union of the
// cells its observations occupied (grown as the sensor moves, never replaced by the last view), its
// height and normal the area-weighted estimate from all of them. An entry out of view keeps
// its extent and takes it back when seen again, however much later, with its id if that is
// within forget_after_frames frames (always with 0) and a new one otherwise, unless the space where
// it was is seen empty (the sensor's rays to a surface below pass through it): then it is removed,
// with an event. Two entries that one observation shows to be one surface merge into the one seen
// in more frames. Heights are compared in the map's frame: the frame's own height error, measured
// by the surfaces seen again, is taken off first. Memory and time are bounded: at most max_entries
// entries (the one seen longest ago goes first), and a frame costs what its planes and the entries
// they touch cost, not what the map has accumulated elsewhere.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <unordered_set>
#include <vector>

#include <Eigen/Core>

#include "hope/params.h"
#include "hope/plane.h"
#include "hope/plane_tracker.h"

namespace hope {

struct SurfaceMapOptions {
  // The grid the extents are kept on, metres (the extraction's r_xy is a good choice).
  double cell = 0.05;
  // An observation whose height is within this of an entry's and which has at least
  // min_overlap_share of the smaller of the two (in cells) in common with it is that surface
  // seen again, metres (a pose's error of a few centimetres included).
  double max_height_change = 0.05;
  double min_overlap_share = 0.3;
  // One whose cells only touch the entry's (a part of it coming into view), or overlap it less,
  // must be within this
  // of its height, metres: a book lying in the hole it leaves in a table's extent, 5 cm above
  // it, stays a surface of its own (the extraction's r_z is a good choice).
  double max_extension_height_change = 0.02;
  // The pose's error, as the prior of the frame's height error the surfaces seen again measure
  // (surface_map.cpp, heightsInMap): its tilt, degrees (an IMU's or a motion-capture rig's usual
  // error; a tilt of θ moves a surface d metres from the sensor by d·tan θ in height), and its
  // height, metres (0: heights are taken as measured).
  double tilt_error_deg = 1.0;
  double height_error = 0.025;
  // At most this many entries; beyond it the one seen longest ago is removed (an event).
  std::size_t max_entries = 1000;
  // The id of an entry not seen in this many frames in a row (update() calls) ends (an event)
  // before the next frame is matched: a surface out of view that long has a new id when seen
  // again (kNew then), as the tracker ends a track after its max_missed_frames (30) and
  // id_accuracy.py counts a surface unseen for 30 frames as a new one (docs/quality.md, "The
  // surface map's memory"). The entry and its extent stay, to recognise it by. In frames, not
  // seconds, so that it means the same at 30 Hz and for keyframes 1 s apart. 0 keeps every id
  // however long it is out of view.
  int forget_after_frames = 30;
  // An entry not seen in a frame whose inner cells (not on its rim) were seen through (rays
  // from the sensor to a lower surface's observed cells cross them) for at least this share is
  // gone (0–1]. An entry with no inner cell (narrower than three cells) is never seen empty.
  double emptied_share = 0.5;
};

// Throws std::invalid_argument naming the option that is out of range.
void validate(const SurfaceMapOptions& options);

// The map matched to an extraction's parameters: cells of r_xy, and surfaces the extraction
// tells apart (r_z) kept apart where they meet.
SurfaceMapOptions surfaceMapOptionsFor(const Params& params);

class SurfaceMap {
 public:
  explicit SurfaceMap(const SurfaceMapOptions& options = SurfaceMapOptions());

  // Gives each plane of a frame (in the map's fixed frame) the id of its map entry, in place,
  // growing the entries; age and last_seen are set as the tracker sets them. Returns what
  // happened: kNew (an entry added, or seen again after its id ended), kMerged (id subsumed
  // by other_id), kEnded (an id ended: its entry not seen in forget_after_frames; or an entry
  // removed: its space seen empty, or the oldest beyond max_entries). `viewpoint` is the sensor's
  // position in the map's frame; without it nothing is seen empty.
  std::vector<TrackEvent> update(std::vector<HorizontalPlane>& planes, double stamp,
                                 const std::optional<Eigen::Vector3d>& viewpoint = std::nullopt);

  // The entries as planes, oldest first: id (for an entry whose id ended, the one it takes when
  // seen again), height, normal and centroid estimated from all observations; bbox, area (cells ×
  // cell²) and outline of the union of their cells; age (the number of frames it was seen in) and
  // last_seen; the rest as last observed.
  std::vector<HorizontalPlane> surfaces() const;
  std::size_t size() const { return entries_.size(); }
  const SurfaceMapOptions& options() const { return options_; }
  // Forgets every entry; ids go on from where they were (never reused).
  void reset();
  // The same, and the map is kept with `options` from now on (validated first: on a bad value
  // it throws std::invalid_argument and nothing changes).
  void reset(const SurfaceMapOptions& options);

 private:
  struct Entry {
    int id = 0;
    double first_seen = 0, last_seen = 0;
    int frames = 0;
    std::int64_t last_frame = 0;  // the update() it was last seen in (SurfaceMap::updates_)
    // Seen in no frame under its id: its last id ended after forget_after_frames unseen, `id` is
    // the one it takes when seen again (observe() counts frames from 1 on).
    bool dormant() const { return frames == 0; }
    double weight = 0;  // observed area summed over frames
    double height_sum = 0;
    Eigen::Vector3d normal_sum = Eigen::Vector3d::Zero();
    Eigen::Vector3d centroid_sum = Eigen::Vector3d::Zero();
    std::unordered_set<std::uint64_t> cells;
    std::int64_t x0 = 0, y0 = 0, x1 = -1, y1 = -1;  // the cells' box, inclusive
    HorizontalPlane last;                           // the last observation
    double height() const { return height_sum / weight; }
  };
  void absorb(Entry& into, Entry& from);
  void observe(Entry& entry, const HorizontalPlane& plane, double height,
               const std::vector<std::uint64_t>& cells, double stamp);
  std::vector<double> heightsInMap(const std::vector<HorizontalPlane>& planes,
                                   const std::vector<std::vector<std::uint64_t>>& plane_cells,
                                   const std::optional<Eigen::Vector3d>& viewpoint) const;

  SurfaceMapOptions options_;
  std::vector<Entry> entries_;
  int next_id_ = 0;
  std::int64_t updates_ = 0;  // update() calls so far: the frames forget_after_frames counts
};

}  // namespace hope
