// Surface ids: the pieces of one physical surface in one frame. The extraction leaves two
// regions apart when something seen between them contradicts their being one (a table top cut
// by what stands on it, a counter by a sink's rim), and the tracker and the map keep each piece
// its own id; a robot asking "which surface is this?" wants one answer for all of them.
#pragma once

#include <array>
#include <cstddef>
#include <deque>
#include <optional>
#include <vector>

#include <Eigen/Core>

#include "hope/params.h"
#include "hope/plane.h"

namespace hope {

struct SurfaceGroupingOptions {
  // Pieces whose heights differ by at most this are one surface at any range: Z clustering's
  // own step (r_z, §2.3). Further away, where the sensor's range noise σ exceeds it, Z
  // clustering itself cuts one surface's points into slices about σ apart, so two pieces are
  // one surface when their heights differ by at most (σ(d_a)² + σ(d_b)²)^½, the noise of a
  // difference of readings at their ranges d, with the up's error below (assign()): a depth
  // camera's floor read 3 and 4 m away (σ 14 and 28 mm there) differs by centimetres in one
  // frame. One σ, not more: the extraction tells surfaces 2 cm apart at 2.5 m (a box on a
  // table) by their means, and they stay apart.
  double max_height_step = 0.02;
  // The error of the frame's up, degrees: the reference frame's z is the up only to within it
  // (an IMU's or an accelerometer's usual error, the scene levelling's on a table, a pose
  // estimate's), so one level surface reads higher by up to d·tan(error) at a horizontal
  // distance d (1° is 3.5 cm across 2 m). Two pieces are one surface when their heights
  // differ by at most that and the range noise together (assign()); pieces side by side (a
  // step 2 cm up from its neighbour 0.4 m away, 7 mm at 1°) still stand apart by their means.
  // The up's share is held to 2·max_height_step (reached 2.3 m apart at 1°): a thing as tall
  // as two of Z clustering's steps (a platform, a threshold) stays apart from the floor around
  // it however far their centres are. In [0, 45].
  double up_error_deg = 1.0;
  // Where a piece lies is where its id was seen within this many seconds (this frame
  // included): pieces the frame shows apart (an occluder's shadow between them) but whose ids'
  // recent extents overlap are one surface. A second: a sensor moves little in one, so the
  // boxes still hold in a frame that follows it (an IMU's, an accelerometer's), as the
  // levelling's hold assumes (PipelineOptions::level_hold_s).
  double memory_s = 1.0;
};

// Throws std::invalid_argument naming the option that is out of range: max_height_step in
// (0, 10] m, up_error_deg in [0, 45], memory_s in [0, 3600] s, all finite.
void validate(const SurfaceGroupingOptions& options);

// The grouping matched to an extraction's parameters: its step r_z.
SurfaceGroupingOptions surfaceGroupingOptionsFor(const Params& params);

class SurfaceGrouping {
 public:
  explicit SurfaceGrouping(const SurfaceGroupingOptions& options = SurfaceGroupingOptions());

  // Sets each plane's surface_id: planes facing the same way whose heights are one reading
  // (above) and whose ids' extents overlap are pieces of one surface (transitively); a piece
  // whose height is not one reading with the largest piece's (at the end of a chain) is a
  // surface of its own. A surface keeps its id from frame to frame: it carries the surface id
  // most of its pieces' area had when last seen within memory_s; where two surfaces ask for one
  // name (a surface that parted), the one holding the piece that named it keeps it (else the
  // one with more area there) and the other asks for its next; two surfaces of a frame never
  // share one. A surface new to the frame carries its largest piece's id (its area; the lower
  // id on a tie) that no other surface keeps, in the rare case none is left a number no plane
  // or remembered surface has. Without memory each surface is named by its largest piece and a
  // plane alone is its own surface: surface_id = id. `viewpoint` is the sensor's position in
  // the planes' frame (the range of each piece) and `noise` its range noise; without either,
  // the step and the up's error alone.
  // `remember`: the planes' ids are persistent (a tracker's or a map's), and this frame's
  // boxes and surface ids extend their extents and names for the frames to come; a stamp older
  // than the last forgets every extent and name (a looping bag). Without it (a frame answered
  // apart from the stream) the frame's own boxes alone decide, and nothing remembered changes.
  void assign(std::vector<HorizontalPlane>& planes, double stamp,
              const std::optional<Eigen::Vector3d>& viewpoint,
              const std::optional<RangeNoise>& noise, bool remember = true);
  // Forgets every id's extent and surface.
  void reset() { recent_.clear(); }

 private:
  // One plane of a frame remembered: where its id was, and the surface it was a piece of.
  struct Piece {
    int id;
    std::array<double, 4> bbox;
    int surface_id;
  };
  struct Seen {
    double stamp;
    std::vector<Piece> pieces;
  };
  // The surface id of each group; `group[i]` is the index of plane i's group's largest piece.
  std::vector<int> nameSurfaces(const std::vector<HorizontalPlane>& planes,
                                const std::vector<std::size_t>& group, bool remember) const;
  SurfaceGroupingOptions options_;
  std::deque<Seen> recent_;
};

}  // namespace hope
