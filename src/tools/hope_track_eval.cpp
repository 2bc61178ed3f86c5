// hope_track_eval: how well plane ids survive camera motion, paper mode vs improved mode, on
// synthetic sequences whose surfaces are known (docs/tracking.md is made by this tool).
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <functional>
#include <iostream>
#include <map>
#include <optional>
#include <set>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "hope/evaluation/tracking_metrics.h"
#include "hope/extractor.h"
#include "hope/plane_tracker.h"
#include "hope/surface_map.h"
#include "hope/synthetic/sequences.h"
#include "hope/tools/cli.h"
#include "hope/tools/output_file.h"

namespace {

// Every option of hope_track_eval, grouped as the help shows them.
hope::tools::CommandLine commandLine() {
  hope::tools::CommandLine cl(
      "hope_track_eval",
      {"[--frames N] [--width W] [--r-xy M] [--r-z M] [--sequences \"pan rpy ...\"] "
       "[--markdown FILE]"},
      "Renders each synthetic tracking sequence (pan, rpy, shake, occlusion, leave_enter: a depth "
      "camera moving over floor, table, book, cabinet, stairs and the paper's pattern object), "
      "extracts planes in every frame, and scores the ids given by the paper's NNPM and by the "
      "improved tracker against the known surfaces. Two orientation sources: the full camera "
      "pose (world frame, like TUM groundtruth.txt) and gravity only (like an accelerometer: no "
      "yaw, no translation, so everything moves in the reference frame when the camera moves).");
  cl.section("sequences")
      .value("--sequences", "\"pan rpy ...\"",
             "the sequences to run, separated by spaces (default: all of pan, rpy, shake, "
             "occlusion, leave_enter)")
      .value("--frames", "N", "frames per sequence, at 30 Hz (default 90)")
      .value("--width", "W", "image width in pixels, intrinsics scaled (default 640)");
  cl.section("parameters")
      .value("--r-xy", "M", "grid resolution in xy, metres (default: the extractor's default r_xy)")
      .value("--r-z", "M", "grid resolution in z, metres (default: the extractor's default r_z)");
  cl.section("output").value(
      "--markdown", "FILE",
      "also write the report with its explanations as Markdown (docs/tracking.md); the "
      "tables always go to stdout");
  return cl;
}

// The head of docs/tracking.md: what is measured and how.
const char* kPreamble =
    R"(# Plane identities across frames: paper mode, improved mode, fragments merged, the surface map

Made by `bash scripts/evaluate_tracking.sh` (`hope_track_eval --markdown docs/tracking.md`);
every figure below comes from that run. Do not edit by hand.

**Scene and ground truth.** A simulated 640 × 480 depth camera (TUM freiburg1 intrinsics,
structured-light noise σ = 1.5 mm · z²) moves over a floor, a table (0.75 m) with a book
(0.80 m), a cabinet (0.45 m), two stair treads (0.17, 0.34 m) and the paper's pattern object
(26 faces, 0.10–0.20 m). Every pixel carries the surface it sees, so each extracted plane's
true surface is the label of most of its points (planes with no majority over 50 % are noise
and not scored). Identities are scored with the extractor's default r_xy and r_z, as a user
starts; at these settings the pattern object's faces 2 cm apart are partly merged, which
is the extractor's resolution, not the tracker's concern.

**Orientation.** `pose`: the camera's full pose (like TUM `groundtruth.txt`): the reference
frame is the world, so planes stand still. `gravity`: only the direction of gravity (like an
accelerometer): no yaw and no translation, so every plane moves in the reference frame
whenever the camera moves — the hard case.

**Metrics.** *Accuracy (paper's)*, as in §3.2 / Table 2: over consecutive frames, the share of
planes whose id is right (its id was on the same surface in the previous frame; or it is new
and no id of its surface was left unused — a surface split into parts counts each part).
*Id switches*: times a surface's id (that of its largest part) differs from the id it had
when last seen, however long ago; a re-numbering after an occlusion or after leaving the
view counts. *Fragmentations*: times a surface in view lost its plane and got one back later
(extraction gaps; the same for both modes). *Duplicate ids*: one id on two planes in a frame.
*IDF1* (identity F1, Ristani et al. 2016): ids and true surfaces paired one-to-one for the
whole sequence (the pairing sharing the most area), then 2 · shared area / (area of every
extracted plane + area of every surface in view), over all frames: counted per observation
and weighted by area (grid cells of r_xy), so a floor carried by four ids scores by the share
its best id holds. *Floor ids*, *table ids*: distinct ids given to planes on the floor and on
the table top during the sequence (1 is what a robot wants). *Tracking µs/frame*: the
tracker alone.

**Modes.** `paper`: NNPM of §2.5 (Eq 11–14 joint normalization, nearest neighbour with
cv::flann, the closest of competing planes keeps the id, no memory). `improved` (default):
physical gates (5 cm height, 0.4 m box gap), costs from height change, box gap and box
overlap (IoU-weighted so fragments cannot steal a big plane's id), optimal one-to-one
assignment (Hungarian) per group of competing planes with a cost for leaving a plane
unpaired, the scene's apparent motion (a turn about the origin and a shift) estimated from a
first pass and removed (kept only when
it explains the frame better; the first pass also tried after the last frame's motion, of which
only the motion its pairs measure is used, and a motion searched within what a sensor can do
since the last frame, kept when it pairs more planes), lost planes remembered for 30 frames and moved with the
scene, merges and splits reported. `improved + merge` (the default of the extractor and the
nodelet): the improved tracker on planes whose fragments were merged into one surface
(docs/evaluation.md §5); the other two rows are the paper's one-plane-per-connected-region.
`map + merge` (pose only: it needs the fixed frame): the surface map (`hope::SurfaceMap`,
the default of `hope_extract --sequence` with poses) on the merged surfaces: one entry per
surface, extents grown over the frames, until it is unseen in 30 frames in a row (as the
tracker's lost planes); its µs/frame include growing the extents.

)";

struct FramePlanes {
  std::vector<hope::HorizontalPlane> planes;
  std::vector<int> truth;
  std::vector<std::size_t> sizes;
  std::vector<double> areas;
  std::set<int> visible;
  std::map<int, double> true_areas;  // m² of each surface in view
};

struct Row {
  std::string sequence, orientation, mode;
  hope::evaluation::IdentityScores scores;
  double idf1 = 0;
  // Distinct ids given to planes on the floor (surface 0) and the table top (1) over the
  // sequence: 1 is a robot's ideal.
  std::size_t floor_ids = 0, table_ids = 0;
  double track_us_per_frame = 0;
  double planes_per_frame = 0;
};

hope::Orientation gravityOnly(const Eigen::Isometry3d& pose) {
  // What a resting accelerometer in the optical frame reads: the world's up axis.
  const Eigen::Vector3d up = pose.linear().transpose() * Eigen::Vector3d::UnitZ() * 9.81;
  return hope::Orientation::fromGravity(up.x(), up.y(), up.z());
}

std::set<int> visibleSurfaces(const cv::Mat& labels, int min_pixels) {
  std::map<int, int> counts;
  for (int r = 0; r < labels.rows; ++r)
    for (int c = 0; c < labels.cols; ++c) ++counts[labels.at<std::int32_t>(r, c)];
  std::set<int> visible;
  for (const auto& [label, count] : counts)
    if (label >= 0 && count >= min_pixels) visible.insert(label);
  return visible;
}

// Gives frame f's planes their ids, in place (a PlaneTracker's or a SurfaceMap's update).
using AssignIds = std::function<void(std::vector<hope::HorizontalPlane>& planes, std::size_t f)>;

Row score(const std::vector<FramePlanes>& frames, const AssignIds& assign) {
  hope::evaluation::IdentityScorer scorer;
  hope::evaluation::IdentityF1 idf1;
  std::set<int> floor_ids, table_ids;
  double seconds = 0;
  std::size_t planes = 0;
  for (std::size_t f = 0; f < frames.size(); ++f) {
    std::vector<hope::HorizontalPlane> planes_now = frames[f].planes;
    const auto start = std::chrono::steady_clock::now();
    assign(planes_now, f);
    seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::vector<int> ids;
    for (const auto& p : planes_now) ids.push_back(p.id);
    scorer.addFrame(ids, frames[f].truth, frames[f].sizes, frames[f].visible);
    idf1.addFrame(ids, frames[f].truth, frames[f].areas, frames[f].true_areas);
    for (std::size_t k = 0; k < ids.size(); ++k) {
      if (frames[f].truth[k] == 0) floor_ids.insert(ids[k]);
      if (frames[f].truth[k] == 1) table_ids.insert(ids[k]);
    }
    planes += planes_now.size();
  }
  Row row;
  row.scores = scorer.scores();
  row.idf1 = idf1.score();
  row.floor_ids = floor_ids.size();
  row.table_ids = table_ids.size();
  row.track_us_per_frame = 1e6 * seconds / frames.size();
  row.planes_per_frame = double(planes) / frames.size();
  return row;
}

int run(const hope::tools::ParsedArgs& args) {
  const auto& values = args.values;
  using hope::tools::leadingDouble;
  using hope::tools::leadingInt;
  const int frames = values.count("--frames") ? leadingInt("--frames", values.at("--frames")) : 90;
  const int width = values.count("--width") ? leadingInt("--width", values.at("--width")) : 640;
  hope::Params params;  // the defaults a user starts with
  if (values.count("--r-xy")) params.r_xy = leadingDouble("--r-xy", values.at("--r-xy"));
  if (values.count("--r-z")) params.r_z = leadingDouble("--r-z", values.at("--r-z"));
  std::vector<std::string> names = hope::synthetic::trackingSequenceNames();
  if (values.count("--sequences")) {
    names.clear();
    std::istringstream list(values.at("--sequences"));
    for (std::string name; list >> name;) names.push_back(name);
  }
  const std::string markdown = values.count("--markdown") ? values.at("--markdown") : "";
  // Opened now (a temporary beside it), so an unwritable path fails before minutes of work;
  // renamed into place when complete.
  std::optional<hope::tools::OutputFile> markdown_file;
  if (!markdown.empty()) markdown_file.emplace(markdown);
  // The paper's pipeline (one plane per connected region) and the default (fragments merged).
  hope::Params paper_params = params;
  paper_params.merge_fragments = false;  // the paper: no merge, no bridging
  paper_params.bridge_scan_gaps = false;
  hope::Extractor merging(params), paper_extractor(paper_params);
  const hope::SurfaceMapOptions map_options =
      hope::surfaceMapOptionsFor(params);  // as hope_extract
  const hope::synthetic::TrackingScene scene;
  std::vector<Row> rows;
  std::map<std::string, std::string> descriptions;
  for (const std::string& name : names) {
    const auto sequence = hope::synthetic::makeTrackingSequence(name, frames, width);
    descriptions[name] = sequence.description;
    // [source][merge]: source 0 pose, 1 gravity; merge 0 off (the paper), 1 on.
    std::vector<FramePlanes> extracted[2][2];
    std::vector<double> stamps;
    std::vector<Eigen::Vector3d> viewpoints;  // the camera's position in the world
    for (std::size_t f = 0; f < sequence.frames.size(); ++f) {
      const auto& frame = sequence.frames[f];
      hope::synthetic::SensorNoise noise;
      noise.seed = static_cast<std::uint32_t>(f + 1);
      const auto rendered = scene.render(frame.camera, frame.occluder_xy, noise);
      const auto cloud = hope::depthToCloud(rendered.depth, frame.camera.intrinsics, 1.0);
      std::vector<int> point_truth(rendered.labels.begin<std::int32_t>(),
                                   rendered.labels.end<std::int32_t>());
      const std::set<int> visible = visibleSurfaces(rendered.labels, 500);
      stamps.push_back(frame.stamp);
      viewpoints.push_back(frame.camera.pose.translation());
      for (int source = 0; source < 2; ++source) {
        const hope::Orientation orientation =
            source == 0 ? hope::Orientation::fromTransform(frame.camera.pose)
                        : gravityOnly(frame.camera.pose);
        for (int merge = 0; merge < 2; ++merge) {
          hope::Extractor& extractor = merge ? merging : paper_extractor;
          const hope::Result result = extractor.extract(cloud, orientation);
          FramePlanes fp;
          fp.planes = result.planes;
          fp.truth = hope::evaluation::groundTruthOfPlanes(result, point_truth);
          for (const auto& p : result.planes) {
            fp.sizes.push_back(p.num_points);
            fp.areas.push_back(p.area);
          }
          fp.visible = visible;
          fp.true_areas =
              hope::evaluation::trueAreas(extractor.alignedPoints(), point_truth, params.r_xy);
          for (auto it = fp.true_areas.begin(); it != fp.true_areas.end();) {
            it = visible.count(it->first) ? std::next(it) : fp.true_areas.erase(it);
          }
          extracted[source][merge].push_back(std::move(fp));
        }
      }
      if (isatty(2))
        std::fprintf(stderr, "\r%s: frame %zu/%zu", name.c_str(), f + 1, sequence.frames.size());
    }
    if (isatty(2)) std::fprintf(stderr, "\n");
    for (int source = 0; source < 2; ++source) {
      // The paper's tracker on the paper's planes; the improved tracker without and with the
      // fragment merge.
      const struct {
        int merge;
        hope::TrackingMode mode;
        const char* name;
      } variants[] = {{0, hope::TrackingMode::kPaper, "paper"},
                      {0, hope::TrackingMode::kImproved, "improved, no merge"},
                      {1, hope::TrackingMode::kImproved, "improved + merge"}};
      for (const auto& variant : variants) {
        hope::TrackerOptions options;
        options.mode = variant.mode;
        hope::PlaneTracker tracker(options);
        Row row = score(extracted[source][variant.merge],
                        [&](std::vector<hope::HorizontalPlane>& planes, std::size_t f) {
                          tracker.update(planes, stamps[f]);
                        });
        row.mode = variant.name;
        row.sequence = name;
        row.orientation = source == 0 ? "pose" : "gravity";
        rows.push_back(row);
      }
      if (source == 0) {
        // The surface map on the same planes, as hope_extract --sequence keeps it with poses:
        // it needs the fixed frame and the camera's position in it.
        hope::SurfaceMap map(map_options);
        Row row = score(extracted[source][1],
                        [&](std::vector<hope::HorizontalPlane>& planes, std::size_t f) {
                          map.update(planes, stamps[f], viewpoints[f]);
                        });
        row.mode = "map + merge";
        row.sequence = name;
        row.orientation = "pose";
        rows.push_back(row);
      }
    }
  }

  std::ostringstream table;
  table << "| sequence | orientation | mode | planes/frame | accuracy (paper's) | IDF1 | "
           "floor ids | table ids | id switches | fragmentations | duplicate ids | "
           "tracking µs/frame |\n"
        << "|---|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n";
  struct Total {
    hope::evaluation::IdentityScores scores;
    double idf1_sum = 0;
    std::size_t rows = 0, floor_ids = 0, table_ids = 0;
  };
  std::map<std::string, Total> totals;
  char line[400];
  for (const Row& r : rows) {
    std::snprintf(line, sizeof(line),
                  "| %s | %s | %s | %.1f | %.1f %% | %.3f | %zu | %zu | %zu | %zu | %zu | %.1f |\n",
                  r.sequence.c_str(), r.orientation.c_str(), r.mode.c_str(), r.planes_per_frame,
                  100.0 * r.scores.accuracy(), r.idf1, r.floor_ids, r.table_ids,
                  r.scores.id_switches, r.scores.fragmentations, r.scores.duplicate_ids,
                  r.track_us_per_frame);
    table << line;
    Total& t = totals[r.orientation + " / " + r.mode];
    t.scores.pairs_checked += r.scores.pairs_checked;
    t.scores.pairs_correct += r.scores.pairs_correct;
    t.scores.id_switches += r.scores.id_switches;
    t.scores.fragmentations += r.scores.fragmentations;
    t.idf1_sum += r.idf1;
    t.floor_ids += r.floor_ids;
    t.table_ids += r.table_ids;
    ++t.rows;
  }
  table << "\n| all sequences | accuracy (paper's) | mean IDF1 | floor ids | table ids | id "
           "switches | fragmentations |\n"
        << "|---|---:|---:|---:|---:|---:|---:|\n";
  for (const auto& [key, t] : totals) {
    std::snprintf(line, sizeof(line),
                  "| %s | %.2f %% (%zu of %zu) | %.3f | %zu | %zu | %zu | %zu |\n", key.c_str(),
                  100.0 * t.scores.accuracy(), t.scores.pairs_correct, t.scores.pairs_checked,
                  t.idf1_sum / std::max<std::size_t>(t.rows, 1), t.floor_ids, t.table_ids,
                  t.scores.id_switches, t.scores.fragmentations);
    table << line;
  }
  std::cout << table.str();
  if (markdown_file) {
    hope::tools::writeText(*markdown_file, [&](std::ostream& out) {
      out << kPreamble << "Sequences (" << frames << " frames at 30 Hz, " << width
          << " px wide, r_xy " << params.r_xy << " m, r_z " << params.r_z << " m):\n\n";
      for (const std::string& name : names)
        out << "- `" << name << "`: " << descriptions[name] << "\n";
      out << "\n" << table.str();
    });
    markdown_file->commit();
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  return hope::tools::runTool("hope_track_eval", commandLine, run, argc, argv);
}
