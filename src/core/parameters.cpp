#include "hope/parameters.h"

#include <algorithm>

#include <cmath>
#include <limits>

namespace hope {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

ParameterSpec number(const char* name, const char* option, double value, double min, double max,
                     const char* unit, const char* stage, bool live, const char* doc,
                     std::function<void(PipelineOptions&, double)> set) {
  ParameterSpec p;
  p.name = name;
  p.option = option;
  p.default_value = value;
  p.min = min;
  p.max = max;
  p.unit = unit;
  p.stage = stage;
  p.live = live;
  p.doc = doc;
  p.set = std::move(set);
  return p;
}

ParameterSpec typed(ParameterSpec p, ParameterSpec::Type type) {
  p.type = type;
  return p;
}

ParameterSpec aboveMin(ParameterSpec p) {
  p.min_excluded = true;
  return p;
}

std::vector<ParameterSpec> makeTable() {
  const PipelineOptions d;
  const Params& e = d.extraction;
  std::vector<ParameterSpec> t;
  // The ranges are validate()'s (params.cpp, standing_objects.cpp, frame_pipeline.cpp,
  // up_estimation.cpp): test_parameters.cpp holds them to it.
  t.push_back(number("r_xy", "--r-xy", e.r_xy, 1e-4, 10.0, "m", "grid filter (§2.2)", true,
                     "grid resolution in xy: a surface must cover about 2 x 2 cells",
                     [](PipelineOptions& o, double v) { o.extraction.r_xy = v; }));
  t.push_back(number("r_z", "--r-z", e.r_z, 1e-4, 10.0, "m", "grid filter (§2.2)", true,
                     "grid resolution in z; slopes steeper than atan(r_z / r_xy) are not "
                     "horizontal (Eq 3)",
                     [](PipelineOptions& o, double v) { o.extraction.r_z = v; }));
  t.push_back(number("min_height", "--min-height", e.min_height, -kInf, kInf, "m",
                     "plane description", true, "planes below this height are dropped",
                     [](PipelineOptions& o, double v) { o.extraction.min_height = v; }));
  t.push_back(number("max_height", "--max-height", e.max_height, -kInf, kInf, "m",
                     "plane description", true, "planes above this height are dropped",
                     [](PipelineOptions& o, double v) { o.extraction.max_height = v; }));
  t.push_back(number("min_area", "--min-area", e.min_area, 0.0, 1e6, "m²", "plane description",
                     true, "planes with a smaller footprint are dropped",
                     [](PipelineOptions& o, double v) { o.extraction.min_area = v; }));
  t.push_back(
      typed(number("merge_fragments", "--no-merge", e.merge_fragments, 0, 1, "", "fragment merge",
                   true, "join the fragments of one surface cut apart by clutter or occlusion",
                   [](PipelineOptions& o, double v) { o.extraction.merge_fragments = v != 0; }),
            ParameterSpec::Type::kBool));
  t.push_back(number("max_merge_gap", "--max-merge-gap", e.max_merge_gap, 0.0, 100.0, "m",
                     "fragment merge", true,
                     "the widest gap between two fragments the merge bridges",
                     [](PipelineOptions& o, double v) { o.extraction.max_merge_gap = v; }));
  t.push_back(
      typed(number("bridge_scan_gaps", "--no-bridge", e.bridge_scan_gaps, 0, 1, "",
                   "scan-gap bridging", true,
                   "voxels between a LiDAR's rings take the normal of the next ring "
                   "along the sensor's ray",
                   [](PipelineOptions& o, double v) { o.extraction.bridge_scan_gaps = v != 0; }),
            ParameterSpec::Type::kBool));
  t.push_back(typed(
      number("threads", "--threads", e.threads, 0, 1024, "", "every stage", true,
             "threads for the passes over points and voxels (0: every core); the "
             "planes do not depend on it",
             [](PipelineOptions& o, double v) { o.extraction.threads = static_cast<int>(v); }),
      ParameterSpec::Type::kInt));
  ParameterSpec tracking;
  tracking.name = "tracking_mode";
  tracking.option = "--tracking";
  tracking.type = ParameterSpec::Type::kChoice;
  tracking.default_choice = toString(d.identity);
  tracking.choices = {"auto", "improved", "paper", "map", "odometry"};
  tracking.stage = "plane matching (§2.5)";
  tracking.live = true;
  tracking.doc =
      "persistent ids: auto (map with poses in a fixed frame, else odometry), the improved "
      "tracker, the paper's NNPM, a map of the surfaces (poses in a fixed frame only), or that "
      "map in the frame of the scene's own odometry (an orientation only)";
  tracking.set = [](PipelineOptions& o, double v) {
    static const Identity kByChoice[] = {Identity::kAuto, Identity::kImproved, Identity::kPaper,
                                         Identity::kMap, Identity::kOdometry};
    o.identity = kByChoice[std::min(4, std::max(0, static_cast<int>(v)))];
  };
  t.push_back(tracking);
  t.push_back(typed(number("objects", "--no-objects", d.objects, 0, 1, "", "standing objects", true,
                           "find what stands on each plane",
                           [](PipelineOptions& o, double v) { o.objects = v != 0; }),
                    ParameterSpec::Type::kBool));
  t.push_back(aboveMin(number(
      "object_max_height", "--object-max-height", d.object_params.max_height, 0.0, 100.0, "m",
      "standing objects", true, "points higher than this above a plane do not stand on it",
      [](PipelineOptions& o, double v) { o.object_params.max_height = v; })));
  t.push_back(aboveMin(number("level_bound", "--level-bound", d.level_bound_deg, 0.0, 30.0, "deg",
                              "up from the scene", false,
                              "the largest correction a refinement makes to a given orientation",
                              [](PipelineOptions& o, double v) { o.level_bound_deg = v; })));
  t.push_back(
      aboveMin(number("level_smoothing", "--level-smoothing", d.level_smoothing, 0.0, 1.0, "",
                      "up from the scene", false,
                      "the share of each frame's up in the running one (1: none); for frames "
                      "1/30 s apart when estimated",
                      [](PipelineOptions& o, double v) { o.level_smoothing = v; })));
  t.push_back(number("level_hold_s", "--level-hold", d.level_hold_s, 0.0, 3600.0, "s",
                     "up from the scene", false,
                     "a frame with nothing level in view keeps the last up this long",
                     [](PipelineOptions& o, double v) { o.level_hold_s = v; }));
  t.push_back(number("gravity_window_s", "--gravity-window", d.gravity_window_s, 0.0, 60.0, "s",
                     "gravity alignment (§2.2)", false,
                     "an accelerometer's samples over this long are averaged",
                     [](PipelineOptions& o, double v) { o.gravity_window_s = v; }));
  t.push_back(number("obstacle_min_height", "--obstacle-min-height", d.obstacle_min_height, 0.0,
                     1.0, "m", "obstacles", true,
                     "obstacle points are more than this above the floor under them",
                     [](PipelineOptions& o, double v) { o.obstacle_min_height = v; }));
  t.push_back(aboveMin(number("obstacle_max_height", "--obstacle-max-height", d.obstacle_max_height,
                              1.0, 100.0, "m", "obstacles", true, "and at most this far above it",
                              [](PipelineOptions& o, double v) { o.obstacle_max_height = v; })));
  t.push_back(
      typed(number("map_forget_frames", "--map-forget", d.map_forget_frames, 0, 1000000, "frames",
                   "surface map", false,
                   "tracking_mode map: a surface not seen in this many frames in a row "
                   "takes a new id when seen again, as the tracker's ids end (0: never)",
                   [](PipelineOptions& o, double v) { o.map_forget_frames = static_cast<int>(v); }),
            ParameterSpec::Type::kInt));
  t.push_back(number("grid_resolution", "--grid-resolution", d.grid_resolution, 0.005, 10.0, "m",
                     "floor grid", true, "the floor grid's cells, metres a side",
                     [](PipelineOptions& o, double v) { o.grid_resolution = v; }));
  return t;
}

}  // namespace

const std::vector<ParameterSpec>& pipelineParameters() {
  static const std::vector<ParameterSpec> table = makeTable();
  return table;
}

}  // namespace hope
