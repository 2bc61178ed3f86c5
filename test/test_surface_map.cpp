// The map of the surfaces (surface_map.h) on frames whose answer is known by construction:
// level rectangles (with holes where something stands) in a fixed frame, as a moving sensor
// would report them.
#include <algorithm>
#include <array>
#include <cmath>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include "hope/depth_image.h"
#include "hope/extractor.h"
#include "hope/surface_map.h"
#include "hope/synthetic/scene.h"

namespace hope {
namespace {

using Ring = std::vector<Eigen::Vector3d>;

Ring rectangle(double x0, double y0, double x1, double y1, double z, bool hole = false) {
  Ring ring = {{x0, y0, z}, {x1, y0, z}, {x1, y1, z}, {x0, y1, z}};
  if (hole) std::reverse(ring.begin(), ring.end());
  return ring;
}

// A level plane [x0, x1] × [y0, y1] at z, less the `holes` (xy rectangles x0 y0 x1 y1).
HorizontalPlane plane(double x0, double y0, double x1, double y1, double z,
                      const std::vector<std::array<double, 4>>& holes = {}) {
  HorizontalPlane p;
  p.height = z;
  p.bbox = {x0, y0, x1, y1};
  p.centroid = Eigen::Vector3d((x0 + x1) / 2, (y0 + y1) / 2, z);
  p.area = (x1 - x0) * (y1 - y0);
  p.outline.push_back(rectangle(x0, y0, x1, y1, z));
  for (const auto& h : holes) {
    p.outline.push_back(rectangle(h[0], h[1], h[2], h[3], z, true));
    p.area -= (h[2] - h[0]) * (h[3] - h[1]);
  }
  p.hull = p.outline.front();
  return p;
}

const HorizontalPlane* surfaceWithId(const std::vector<HorizontalPlane>& surfaces, int id) {
  for (const auto& s : surfaces) {
    if (s.id == id) return &s;
  }
  return nullptr;
}

bool hasEvent(const std::vector<TrackEvent>& events, TrackEvent::Kind kind, int id,
              int other = -1) {
  for (const auto& e : events) {
    if (e.kind == kind && e.id == id && (other < 0 || e.other_id == other)) return true;
  }
  return false;
}

const Eigen::Vector3d kEye(0.6, -1.5, 1.6);  // a sensor in front of the table, above it

// A table seen in its left half, out of view for 100 frames (the sensor looks at the floor
// elsewhere), then seen in its right half: with no memory limit (forget_after_frames 0), one
// id, and the map holds the whole table.
TEST(SurfaceMap, ATableOutOfViewFor100FramesKeepsItsIdAndItsWholeExtent) {
  SurfaceMapOptions permanent;
  permanent.forget_after_frames = 0;
  SurfaceMap map(permanent);
  int table = -1, floor = -1;
  double stamp = 0;
  for (int f = 0; f < 10; ++f, stamp += 0.1) {
    std::vector<HorizontalPlane> frame = {plane(-1, -1, 0.6, 2, 0), plane(0, 0, 0.6, 0.8, 0.75)};
    map.update(frame, stamp, kEye);
    if (f == 0) floor = frame[0].id, table = frame[1].id;
    EXPECT_EQ(frame[1].id, table);
  }
  for (int f = 0; f < 100; ++f, stamp += 0.1) {
    std::vector<HorizontalPlane> frame = {plane(3, -1, 5, 2, 0)};
    map.update(frame, stamp, Eigen::Vector3d(4, -1.5, 1.6));
  }
  for (int f = 0; f < 5; ++f, stamp += 0.1) {
    std::vector<HorizontalPlane> frame = {plane(0.6, -1, 2, 2, 0), plane(0.6, 0, 1.2, 0.8, 0.75)};
    map.update(frame, stamp, kEye);
    EXPECT_EQ(frame[1].id, table) << "frame " << f << " after 100 away";
    EXPECT_EQ(frame[0].id, floor);
  }
  const std::vector<HorizontalPlane> surfaces = map.surfaces();
  const HorizontalPlane* t = surfaceWithId(surfaces, table);
  ASSERT_NE(t, nullptr);
  EXPECT_NEAR(t->area, 1.2 * 0.8, 0.05);  // both halves, to a row of 5 cm cells
  EXPECT_NEAR(t->bbox[0], 0.0, 0.051);
  EXPECT_NEAR(t->bbox[2], 1.2, 0.051);
  EXPECT_NEAR(t->height, 0.75, 1e-9);
  EXPECT_EQ(t->age, 15);  // frames seen in
}

// A box on the table (its top a plane at 0.95 m, a hole in the table where it and its shadow
// from the sensor above are), then lifted off: the table is seen where the box stood, so the
// box's entry is dropped with an event. The same box merely not reported (the table still
// shows the hole: nothing seen through where it was) stays.
TEST(SurfaceMap, ABoxTakenOffTheTableIsDroppedWhenItsSpaceIsSeenEmpty) {
  const Eigen::Vector3d eye(0.5, 0.0, 2.0);
  const std::array<double, 4> box = {0.4, 0.3, 0.6, 0.5};
  // The box's top seen from the eye hides [0.381, 0.619] × [0.357, 0.595] of the table.
  const std::array<double, 4> hidden_table = {0.38, 0.3, 0.62, 0.6};
  SurfaceMap map, unseen_map;
  int box_id = -1, table = -1;
  double stamp = 0;
  for (int f = 0; f < 5; ++f, stamp += 0.1) {
    std::vector<HorizontalPlane> frame = {plane(0, 0, 1.2, 0.8, 0.75, {hidden_table}),
                                          plane(box[0], box[1], box[2], box[3], 0.95)};
    std::vector<HorizontalPlane> copy = frame;
    map.update(frame, stamp, eye);
    unseen_map.update(copy, stamp, eye);
    table = frame[0].id, box_id = frame[1].id;
  }
  ASSERT_NE(box_id, table);
  // Lifted off: the table whole.
  std::vector<HorizontalPlane> emptied = {plane(0, 0, 1.2, 0.8, 0.75)};
  const std::vector<TrackEvent> events = map.update(emptied, stamp, eye);
  EXPECT_TRUE(hasEvent(events, TrackEvent::Kind::kEnded, box_id));
  EXPECT_EQ(emptied[0].id, table);
  EXPECT_EQ(surfaceWithId(map.surfaces(), box_id), nullptr);
  ASSERT_NE(surfaceWithId(map.surfaces(), table), nullptr);
  // Not seen, but nothing seen through it either (the hole is still there): kept.
  std::vector<HorizontalPlane> hidden = {plane(0, 0, 1.2, 0.8, 0.75, {hidden_table})};
  const std::vector<TrackEvent> kept = unseen_map.update(hidden, stamp, eye);
  EXPECT_FALSE(hasEvent(kept, TrackEvent::Kind::kEnded, box_id));
  EXPECT_NE(surfaceWithId(unseen_map.surfaces(), box_id), nullptr);
}

// A table seen first in one half, then in the other with the middle unseen (two entries), then
// whole: the younger entry is subsumed by the older, whose id the table keeps from then on.
TEST(SurfaceMap, TwoHalvesOfATableThatLaterMeetMergeIntoTheOlderId) {
  SurfaceMap map;
  double stamp = 0;
  std::vector<HorizontalPlane> a = {plane(0, 0, 0.5, 0.8, 0.75)};
  map.update(a, stamp += 0.1, kEye);
  std::vector<HorizontalPlane> b = {plane(0.8, 0, 1.3, 0.8, 0.75)};
  map.update(b, stamp += 0.1, kEye);
  ASSERT_NE(a[0].id, b[0].id) << "a 30 cm gap: two surfaces as far as anyone knows";
  EXPECT_EQ(map.size(), 2u);
  std::vector<HorizontalPlane> whole = {plane(0, 0, 1.3, 0.8, 0.75)};
  const std::vector<TrackEvent> events = map.update(whole, stamp += 0.1, kEye);
  EXPECT_EQ(whole[0].id, a[0].id);
  EXPECT_TRUE(hasEvent(events, TrackEvent::Kind::kMerged, b[0].id, a[0].id));
  ASSERT_EQ(map.size(), 1u);
  EXPECT_NEAR(map.surfaces()[0].area, 1.3 * 0.8, 0.05);
  std::vector<HorizontalPlane> again = {plane(0.8, 0, 1.3, 0.8, 0.75)};
  map.update(again, stamp += 0.1, kEye);
  EXPECT_EQ(again[0].id, a[0].id);
}

// Two halves mapped apart, the second seen in more frames: when one view shows them one
// surface, the merged entry keeps the id most observations carried (the second's), so the
// fewest observations change id.
TEST(SurfaceMap, TwoEntriesThatMeetMergeIntoTheOneSeenInMoreFrames) {
  SurfaceMap map;
  double stamp = 0;
  std::vector<HorizontalPlane> a = {plane(0, 0, 0.5, 0.8, 0.75)};
  map.update(a, stamp += 0.1, kEye);
  int b_id = -1;
  for (int f = 0; f < 3; ++f) {
    std::vector<HorizontalPlane> b = {plane(0.8, 0, 1.3, 0.8, 0.75)};
    map.update(b, stamp += 0.1, kEye);
    ASSERT_NE(b[0].id, a[0].id) << "a 30 cm gap: two surfaces as far as anyone knows";
    b_id = b[0].id;
  }
  std::vector<HorizontalPlane> whole = {plane(0, 0, 1.3, 0.8, 0.75)};
  const std::vector<TrackEvent> events = map.update(whole, stamp += 0.1, kEye);
  EXPECT_EQ(whole[0].id, b_id);
  EXPECT_TRUE(hasEvent(events, TrackEvent::Kind::kMerged, a[0].id, b_id));
  EXPECT_EQ(map.size(), 1u);
}

// A pose whose tilt is 1.2° off (beyond an IMU's usual 1°, as a motion-capture pose can be)
// moves a surface 3 m from the sensor by 6.3 cm in height, past max_height_change: the map
// would take it for a new surface. Two surfaces 1.6 m away, moved by 3.4 cm and still matched,
// measure the tilt; the far ones then keep their ids. Without the pose's error as a prior
// (tilt_error_deg and height_error 0: heights as measured) they take new ids.
TEST(SurfaceMap, APoseTiltedByMoreThanTheHeightGateIsMeasuredByTheSurfacesSeenAgain) {
  const Eigen::Vector3d sensor(0, 0, 1.5);
  const double tilt = std::tan(1.2 * M_PI / 180.0);
  // Four level surfaces in the map's frame, centred 3 m and 1.6 m either side of the sensor.
  const auto scene = [&](double slope) {
    const std::array<std::array<double, 2>, 4> surfaces = {
        {{-3.0, 0.75}, {-1.6, 0.0}, {1.6, 0.4}, {3.0, 0.9}}};  // x, height
    std::vector<HorizontalPlane> planes;
    for (const auto& [x, height] : surfaces) {
      planes.push_back(plane(x - 0.4, -0.4, x + 0.4, 0.4, height + slope * x));
    }
    return planes;
  };
  for (const bool prior : {true, false}) {
    SurfaceMapOptions options;
    if (!prior) options.tilt_error_deg = options.height_error = 0;
    SurfaceMap map(options);
    std::vector<HorizontalPlane> level = scene(0);
    map.update(level, 0.1, sensor);
    std::vector<HorizontalPlane> tilted = scene(tilt);
    ASSERT_GT(std::fabs(tilted[0].height - level[0].height), options.max_height_change);
    map.update(tilted, 0.2, sensor);
    for (std::size_t k = 1; k < 3; ++k) EXPECT_EQ(tilted[k].id, level[k].id) << "near " << k;
    for (std::size_t k : {std::size_t{0}, std::size_t{3}}) {
      if (prior) {
        EXPECT_EQ(tilted[k].id, level[k].id) << "far " << k;
      } else {
        EXPECT_NE(tilted[k].id, level[k].id) << "far " << k;
      }
    }
    if (prior) {
      EXPECT_EQ(map.size(), 4u);
    }
  }
}

// Surfaces at other heights are other entries even where they overlap in xy (a shelf above a
// table), and a height within max_height_change of an entry is that entry (a pose's error).
TEST(SurfaceMap, HeightSeparatesSurfacesAndItsNoiseDoesNot) {
  SurfaceMap map;
  std::vector<HorizontalPlane> frame = {plane(0, 0, 1, 0.5, 0.75), plane(0, 0, 1, 0.5, 1.2)};
  map.update(frame, 0.1, kEye);
  EXPECT_NE(frame[0].id, frame[1].id);
  std::vector<HorizontalPlane> noisy = {plane(0.02, 0, 1, 0.5, 0.78), plane(0, 0.02, 1, 0.5, 1.17)};
  map.update(noisy, 0.2, kEye);
  EXPECT_EQ(noisy[0].id, frame[0].id);
  EXPECT_EQ(noisy[1].id, frame[1].id);
  EXPECT_EQ(map.size(), 2u);
  // A book 5 cm high lying on the table, in the hole it leaves in the table's extent: beside
  // the table, not over it, and above r_z: a surface of its own, frame after frame.
  SurfaceMap table_map;
  for (int f = 0; f < 3; ++f) {
    std::vector<HorizontalPlane> seen = {plane(0, 0, 1.2, 0.8, 0.75, {{0.4, 0.3, 0.65, 0.5}}),
                                         plane(0.4, 0.3, 0.65, 0.5, 0.80)};
    table_map.update(seen, 0.1 * (f + 1), kEye);
    EXPECT_NE(seen[0].id, seen[1].id) << "frame " << f;
  }
  EXPECT_EQ(table_map.size(), 2u);
}

// A surface's height drifts with the pose and the range it is seen at (on the kitchen sequence
// a far shelf read 5 cm apart over 20 frames). A fragment the extraction once left beside it,
// a few centimetres lower, becomes an entry of its own (the shelf's entry was taken in that
// frame); when the drifted shelf is seen whole again, nearer in height to the fragment, it is
// still the shelf: the entry it shares most of its extent with.
TEST(SurfaceMap, ADriftingSurfaceKeepsItsIdOverAFragmentNearerInHeight) {
  SurfaceMap map;
  double stamp = 0;
  std::vector<HorizontalPlane> first = {plane(0, 0, 0.3, 0.6, 1.0)};
  map.update(first, stamp += 0.1, kEye);
  const int shelf = first[0].id;
  std::vector<HorizontalPlane> split = {plane(0, 0, 0.3, 0.45, 1.0),
                                        plane(0, 0.45, 0.3, 0.6, 0.975)};
  map.update(split, stamp += 0.1, kEye);
  ASSERT_EQ(split[0].id, shelf);
  ASSERT_NE(split[1].id, shelf) << "ids are distinct within a frame";
  for (int f = 0; f < 5; ++f) {
    std::vector<HorizontalPlane> drifted = {plane(0, 0, 0.3, 0.6, 0.97)};
    map.update(drifted, stamp += 0.1, kEye);
    EXPECT_EQ(drifted[0].id, shelf) << "frame " << f;
  }
}

// The other side of the same choice: extent is weighed against height. A step 6 cm above a
// wider one (both entries), then seen a little wider than before and 1.5 cm low (as a plane the
// extraction blended from two faces reads): it shares more cells with the lower step, 4.5 cm
// away, but is the upper one, 1.5 cm away.
TEST(SurfaceMap, HeightIsWeighedAgainstExtentWhenTwoEntriesOverlapAPlane) {
  SurfaceMap map;
  std::vector<HorizontalPlane> steps = {plane(0, 0, 0.6, 0.6, 0.10), plane(0.3, 0, 0.6, 0.6, 0.16)};
  map.update(steps, 0.1, kEye);
  ASSERT_NE(steps[0].id, steps[1].id);
  std::vector<HorizontalPlane> blended = {plane(0.2, 0, 0.6, 0.6, 0.145)};
  map.update(blended, 0.2, kEye);
  EXPECT_EQ(blended[0].id, steps[1].id);
}

// The demo room as a robot turning in place sees it: a camera at 1.5 m yawing from -40° to +40°
// in 10° steps, each view's pose known (as tf gives it), the map updated frame by frame. The
// same room seen at once (every view's points in one cloud, one extraction, one update) gives
// the same map: the same entries at the same heights with the same extents. And each of the
// room's larger level surfaces (ground truth: floor 0, stair treads 0.17 and 0.34, cabinet
// 0.45, table 0.75) is one entry.
TEST(SurfaceMap, ARobotTurningInPlaceMapsWhatTheSameSceneSeenAtOnceGives) {
  const synthetic::Scene room = synthetic::demoRoom();
  const Eigen::Vector3d eye = synthetic::demoCamera().pose.translation();
  Extractor extractor;
  const Params params;
  SurfaceMap turning(surfaceMapOptionsFor(params));
  pcl::PointCloud<pcl::PointXYZ> at_once;
  int frame = 0;
  for (int degrees = -40; degrees <= 40; degrees += 10, ++frame) {
    const synthetic::Camera camera = synthetic::demoCameraTurned(degrees * M_PI / 180);
    synthetic::SensorNoise noise;
    noise.seed = static_cast<std::uint32_t>(frame + 1);
    const auto cloud = depthToCloud(room.render(camera, noise).depth, camera.intrinsics, 1.0);
    Result result = extractor.extract(cloud, Orientation::fromTransform(camera.pose));
    turning.update(result.planes, 0.1 * (frame + 1), eye);
    for (const auto& p : cloud) {
      if (!std::isfinite(p.z)) continue;
      const Eigen::Vector3d w = camera.pose * Eigen::Vector3d(p.x, p.y, p.z);
      at_once.push_back(pcl::PointXYZ(static_cast<float>(w.x()), static_cast<float>(w.y()),
                                      static_cast<float>(w.z())));
    }
  }
  SurfaceMap seen_at_once(surfaceMapOptionsFor(params));
  Result whole = extractor.extract(at_once, Orientation::identity().withViewpoint(eye));
  seen_at_once.update(whole.planes, 0.1, eye);

  // Entries of at least 0.1 m² (40 cells): slivers of the ramp and the ball come and go with
  // the noise in either map (the 0.05 m² book is left to the other tests).
  auto substantial = [](const std::vector<HorizontalPlane>& surfaces) {
    std::vector<HorizontalPlane> out;
    for (const auto& s : surfaces) {
      if (s.area >= 0.1) out.push_back(s);
    }
    return out;
  };
  const std::vector<HorizontalPlane> expected = substantial(seen_at_once.surfaces());
  const std::vector<HorizontalPlane> mapped = substantial(turning.surfaces());
  for (double truth : {0.0, 0.17, 0.34, 0.45, 0.75}) {
    int entries = 0;
    for (const auto& s : mapped) entries += std::fabs(s.height - truth) < 0.015 ? 1 : 0;
    EXPECT_EQ(entries, 1) << "the surface at " << truth << " m";
  }
  // One entry for each of the other's, at its height, its extent's box the same to within a
  // cell (r_xy) on every side: the union of nine views' rims against one view of all points.
  ASSERT_GE(expected.size(), 5u);
  EXPECT_EQ(mapped.size(), expected.size());
  const double cell = surfaceMapOptionsFor(params).cell + 1e-9;
  for (const auto& e : expected) {
    const HorizontalPlane* match = nullptr;
    for (const auto& m : mapped) {
      if (std::fabs(m.height - e.height) < 0.01) match = &m;
    }
    ASSERT_NE(match, nullptr) << "no entry at " << e.height << " m";
    for (int side = 0; side < 4; ++side) {
      EXPECT_NEAR(match->bbox[side], e.bbox[side], cell)
          << "side " << side << " of the entry at " << e.height << " m";
    }
  }
  // The cabinet's top (wholly in view from -10° on) against its true extent, 1.3–1.9 ×
  // 0.45–1.1 m, to within a cell on every side.
  const std::array<double, 4> cabinet = {1.3, 0.45, 1.9, 1.1};
  const HorizontalPlane* top = nullptr;
  for (const auto& m : mapped) {
    if (std::fabs(m.height - 0.45) < 0.015) top = &m;
  }
  ASSERT_NE(top, nullptr);
  for (int side = 0; side < 4; ++side) {
    EXPECT_NEAR(top->bbox[side], cabinet[side], cell) << "side " << side << " of the cabinet";
  }
}

// At most max_entries: the entry seen longest ago goes, with an event; ids are never reused.
TEST(SurfaceMap, MemoryIsBoundedByDroppingTheEntrySeenLongestAgo) {
  SurfaceMapOptions options;
  options.max_entries = 3;
  SurfaceMap map(options);
  std::vector<int> ids;
  std::vector<TrackEvent> last;
  for (int k = 0; k < 4; ++k) {
    std::vector<HorizontalPlane> frame = {plane(3.0 * k, 0, 3.0 * k + 1, 1, 0.7)};
    last = map.update(frame, 0.1 * (k + 1));
    ids.push_back(frame[0].id);
  }
  EXPECT_EQ(map.size(), 3u);
  EXPECT_TRUE(hasEvent(last, TrackEvent::Kind::kEnded, ids[0]));
  EXPECT_EQ(std::set<int>(ids.begin(), ids.end()).size(), 4u);
}

// A table not seen in forget_after_frames frames in a row takes a new id when seen again (an
// end event for the old id in that frame, a new event for the new one), one unseen in one frame
// fewer keeps its id: the default memory, 30 frames, as id_accuracy.py joins two planes at most
// 30 frames apart; the stamps (1 s apart, keyframes) do not matter. The entry keeps its extent:
// its left half seen first, its right half after the memory passed is the same entry (it
// touches it at its height), and the map holds the whole table under the new id.
TEST(SurfaceMap, ATableOutOfViewLongerThanTheMemoryIsNewWhenSeenAgain) {
  SurfaceMap map;
  const int memory = SurfaceMapOptions().forget_after_frames;
  ASSERT_EQ(memory, 30);
  int frames = 0;
  std::vector<int> ended_in, new_in;  // the frames of the table's end and new events
  int table = -1, again = -1;
  enum class View { kLeftHalf, kRightHalf, kAway };
  const auto look = [&](View view) {
    const int index = frames++;
    std::vector<HorizontalPlane> frame = {view == View::kLeftHalf    ? plane(0, 0, 0.6, 0.8, 0.75)
                                          : view == View::kRightHalf ? plane(0.6, 0, 1.2, 0.8, 0.75)
                                                                     : plane(3, -1, 5, 2, 0)};
    for (const TrackEvent& e : map.update(frame, 1.0 * index, kEye)) {
      if (e.kind == TrackEvent::Kind::kEnded && e.id == table) ended_in.push_back(index);
      if (e.kind == TrackEvent::Kind::kNew && view == View::kRightHalf) new_in.push_back(index);
    }
    return frame[0].id;
  };
  table = look(View::kLeftHalf);                                     // frame 0
  for (int f = 0; f < memory - 1; ++f) look(View::kAway);            // frames 1-29
  EXPECT_EQ(look(View::kLeftHalf), table) << "unseen in 29 frames";  // frame 30
  for (int f = 0; f < memory; ++f) look(View::kAway);                // frames 31-60
  again = look(View::kRightHalf);                                    // frame 61
  EXPECT_NE(again, table) << "unseen in 30 frames: past the memory";
  ASSERT_EQ(ended_in.size(), 1u);
  EXPECT_EQ(ended_in[0], 61) << "ended in the frame its memory had passed, before it matched";
  EXPECT_EQ(new_in, std::vector<int>{61});
  EXPECT_EQ(look(View::kLeftHalf), again) << "the new id holds";  // frame 62
  // The floor and the table, one entry each; the table's entry is whole under its new id.
  EXPECT_EQ(map.size(), 2u);
  const std::vector<HorizontalPlane> surfaces = map.surfaces();
  EXPECT_EQ(surfaceWithId(surfaces, table), nullptr);
  const HorizontalPlane* whole = surfaceWithId(surfaces, again);
  ASSERT_NE(whole, nullptr);
  EXPECT_NEAR(whole->area, 1.2 * 0.8, 0.05);  // both halves, to a row of 5 cm cells
  EXPECT_EQ(whole->age, 2);                   // frames seen in with its new id
}

TEST(SurfaceMap, BadOptionsAreRefusedByName) {
  SurfaceMapOptions options;
  options.cell = 0;
  EXPECT_THROW(
      {
        try {
          SurfaceMap map(options);
        } catch (const std::invalid_argument& e) {
          EXPECT_NE(std::string(e.what()).find("cell"), std::string::npos) << e.what();
          throw;
        }
      },
      std::invalid_argument);
  options = SurfaceMapOptions();
  options.emptied_share = 1.5;
  EXPECT_THROW(SurfaceMap{options}, std::invalid_argument);
  options = SurfaceMapOptions();
  options.tilt_error_deg = -1;
  EXPECT_THROW(SurfaceMap{options}, std::invalid_argument);
  options = SurfaceMapOptions();
  options.height_error = std::nan("");
  EXPECT_THROW(SurfaceMap{options}, std::invalid_argument);
  options = SurfaceMapOptions();
  options.forget_after_frames = -1;
  EXPECT_THROW(SurfaceMap{options}, std::invalid_argument);
}

// Restarted with other options (the nodelet's r_xy changed): the entries are forgotten, the
// new cell is used, ids are never given twice; bad options change nothing.
TEST(SurfaceMap, ARestartWithOtherOptionsForgetsTheEntriesButNotTheIds) {
  SurfaceMap map;
  std::vector<HorizontalPlane> frame = {plane(0, 0, 1, 0.5, 0.75)};
  map.update(frame, 0.1, kEye);
  const int first = frame[0].id;
  SurfaceMapOptions bad;
  bad.cell = -1;
  EXPECT_THROW(map.reset(bad), std::invalid_argument);
  EXPECT_EQ(map.size(), 1u);
  EXPECT_DOUBLE_EQ(map.options().cell, SurfaceMapOptions().cell);
  Params params;
  params.r_xy = 0.1;
  map.reset(surfaceMapOptionsFor(params));
  EXPECT_EQ(map.size(), 0u);
  EXPECT_DOUBLE_EQ(map.options().cell, 0.1);
  map.update(frame, 0.2, kEye);
  EXPECT_GT(frame[0].id, first);
  ASSERT_EQ(map.surfaces().size(), 1u);
  EXPECT_NEAR(map.surfaces()[0].area, 0.5, 1e-9);  // 10 × 5 cells of 10 cm
}

}  // namespace
}  // namespace hope
