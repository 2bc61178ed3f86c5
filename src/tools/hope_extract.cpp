// hope_extract: horizontal planes of one point cloud or depth image, from the command line.
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <limits>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <sstream>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "hope/extractor.h"
#include "hope/frame_pipeline.h"
#include "hope/parameters.h"
#include "hope/tools/cli.h"
#include "hope/tools/io.h"
#include "hope/tools/map_extents.h"
#include "hope/tools/output_file.h"
#include "hope/tools/overlay.h"
#include "hope/tools/report.h"
#include "hope/tools/run_summary.h"
#include "hope/tools/sequence.h"
#include "hope/up_estimation.h"

namespace {

// Every option of hope_extract, grouped as the help shows them.
hope::tools::CommandLine commandLine() {
  hope::tools::CommandLine cl(
      "hope_extract",
      {"(--input FILE.pcd|.ply | --depth FILE.png [--rgb FILE.png]) [options]",
       "--sequence DIR [--groundtruth FILE | --accelerometer FILE] [options]"},
      "Finds the horizontal planes of one cloud (HoPE, Dong et al. 2018), or of every frame of "
      "a sequence, with plane ids kept across frames.");
  cl.section("input")
      .value("--input", "FILE", "point cloud, .pcd or .ply, fields x y z in metres (rgb optional)")
      .value("--depth", "FILE", "depth image: 16-bit PNG (raw units) or 32-bit float (metres)")
      .value("--rgb", "FILE", "colour image registered to the depth image (for the overlay)")
      .value("--intrinsics", "\"fx fy cx cy\"",
             "pinhole intrinsics in pixels (default: with --sequence the folder's "
             "intrinsics.txt when it has one; otherwise TUM freiburg1, 517.3 516.5 318.6 255.3)")
      .value("--depth-scale", "S", "raw depth units per metre (default 5000, TUM; OpenNI: 1000)");
  cl.section("orientation",
             "of the sensor in the reference frame (z up): at most one of --pose, --quaternion, "
             "--rpy, --gravity, and/or --level; default: none (the cloud is taken as z-up, with "
             "a warning when it does not look it)")
      .value("--pose", "\"tx ty tz qx qy qz qw\"",
             "full pose, e.g. a TUM ground-truth line (heights are real)")
      .value("--quaternion", "\"qx qy qz qw\"", "rotation only (normalized; zero/NaN rejected)")
      .value("--rpy", "\"roll pitch yaw\"", "radians, fixed axes x, y, z (R = Rz Ry Rx)")
      .value("--gravity", "\"gx gy gz\"", "accelerometer at rest in the sensor frame (points UP)")
      .flag("--level",
            "up from the scene: alone, estimated from the cloud's level surfaces (a camera pitched "
            "from 15° up to straight down and rolled up to 35°, or a LiDAR within 45° of z; the "
            "sensor at the origin, heights relative to it); with one of the options above, that "
            "orientation corrected by at most --level-bound. A scene with nothing level is an "
            "error, not a guess")
      .value("--level-bound", "DEG",
             "the largest correction --level makes to a given orientation (default 5)")
      .value("--viewpoint", "\"x y z\"",
             "where the sensor was, in the reference frame (default: the pose's translation; "
             "the origin for a rotation or a depth image; unknown for a cloud without "
             "orientation). The fragment merge uses it to tell shadows from gaps, the scan-gap "
             "bridging to find a LiDAR's next ring; each plane's facing (up/down) needs it. A "
             "LiDAR scan in its own z-up frame: --viewpoint \"0 0 0\"");
  cl.section("sequences",
             "each frame's orientation from --groundtruth (the default) or --accelerometer, or "
             "one fixed --pose/--quaternion/--rpy/--gravity for every frame")
      .value("--sequence", "DIR",
             "a TUM RGB-D folder (depth.txt, rgb.txt, the PNGs), or a folder of .pcd files named "
             "by timestamp (or sorted by name)")
      .value(
          "--groundtruth", "FILE",
          "TUM poses \"timestamp tx ty tz qx qy qz qw\" (default DIR/groundtruth.txt); each "
          "frame takes the pose of its own time, interpolated between the two around it; heights "
          "are real heights")
      .value("--accelerometer", "FILE",
             "TUM accelerometer.txt \"timestamp ax ay az\" (m/s^2, optical frame, pointing up at "
             "rest): gravity only, heights relative to the camera")
      .value("--orientation-source", "NAME",
             "groundtruth (the default when the folder has groundtruth.txt), accelerometer "
             "(averaged over 0.1 s of frames), fixed (--pose/--quaternion/--rpy/--gravity) or "
             "scene (up from each frame's level surfaces, smoothed over frames, the last up held "
             "for 1 s with nothing level in view): the nodelet's orientation_source. "
             "--level with any other source refines it, as the nodelet's refine_orientation")
      .value("--level-smoothing", "SHARE",
             "the share of each frame's up in the running one, in (0, 1] (default 0.3; 1: none; "
             "scene: for frames 1/30 s apart, more for frames further apart)")
      .value("--level-hold", "S",
             "scene: seconds a frame with nothing level in view keeps the last up (default 1)")
      .value("--gravity-window", "S", "accelerometer: seconds of samples averaged (default 0.1)")
      .value("--every", "N",
             "every N-th frame only (the 1st, the N+1-th, ...): a robot that processes at a "
             "lower rate, or keyframes (default 1: every frame)")
      .value("--max-time-difference", "S",
             "largest frame-to-orientation gap (default 0.02 s); frames without an orientation "
             "that close are skipped and counted")
      .value("--tracking", "MODE",
             "auto (the default: map with world poses whose position changes, else odometry), "
             "map (one id per surface until it is unseen in --map-forget frames, extents grown "
             "over frames), odometry (the same map in the frame of the scene's own odometry), "
             "improved (the frame-to-frame tracker) or paper (NNPM of §2.5, Eq 11-14)")
      .value("--map-forget", "N",
             "with --tracking map or odometry: a surface not seen in N frames in a row takes a new "
             "id when seen again, as the tracker's ids end (default 30; 0: never)")
      .value("--map", "FILE.json", "with --tracking map or odometry: the final map of the surfaces")
      .value("--map-extents", "FILE.md",
             "with --tracking map or odometry: each entry's outline against the union of all "
             "points given its id (area ratio, IoU in xy on a 2 cm grid), largest first, as a "
             "Markdown table")
      .value("--jsonl", "FILE",
             "one JSON line per frame: {\"stamp\", \"file\", \"planes\": [...], \"events\"}")
      .value("--overlay-dir", "DIR", "one overlay PNG per frame, named by stamp")
      .flag("--strict",
            "stop at the first frame or list line that cannot be used (default: skip it, count "
            "it, name it in the summary and in the JSON lines, and go on)");
  cl.section("parameters")
      .value("--r-xy", "M", "grid resolution in xy, metres (default 0.05)")
      .value("--r-z", "M",
             "grid resolution in z, metres (default 0.02); slopes steeper than atan(r_z / r_xy) "
             "are rejected")
      .value("--min-height", "M", "keep planes inside this height band: its lower end")
      .value("--max-height", "M", "keep planes inside this height band: its upper end")
      .value("--min-area", "M2", "keep planes of at least this footprint")
      .flag("--no-merge",
            "one plane per connected region, as in the paper (default: fragments of one surface "
            "cut apart by clutter or occlusion are merged)")
      .value("--max-merge-gap", "M", "widest gap the fragment merge bridges (default 1.0 m)")
      .flag("--no-bridge",
            "no scan-gap bridging, as in the paper (default: voxels between a LiDAR's sparse "
            "rings take their normal from the next ring along the sensor's ray; needs the "
            "viewpoint). LiDAR: --r-xy 0.3 --r-z 0.1")
      .value("--threads", "N",
             "threads for the passes over points and voxels (default 1, the fastest while "
             "other programs keep the cores busy; 0: every core, faster on an idle machine; "
             "the planes are the same for any number)")
      .value("--repeat", "N",
             "extract N times from the loaded input and print the first (cold) call's time and "
             "the median of the others (steady state, as in a node that keeps its buffers); "
             "outputs are from the last call")
      .value("--max-points", "N",
             "refuse files claiming more points (default 100000000), so a corrupt header cannot "
             "make hope allocate gigabytes");
  cl.section("objects and placements",
             "what stands on each plane seen from above, and where a new object fits; made "
             "whenever --json, --labels, --overlay or --place is given (with --sequence: "
             "--jsonl or --overlay-dir)")
      .value("--place", "\"W D [CLEARANCE]\"",
             "a footprint W x D m (clearance default 0.02 m): up to 5 poses where it rests on "
             "observed surface clear of every object, best first, printed and in the JSON's "
             "\"placements\"")
      .value("--object-max-height", "M",
             "points up to this far above a plane stand on it (default 0.5)")
      .flag("--no-objects", "planes only: no objects, free areas or the labels' object field");
  cl.section("output",
             "each file is written under a temporary name and renamed when complete: a failed "
             "run leaves no partial file")
      .value("--json", "FILE", "every plane field as JSON")
      .value("--labels", "FILE.pcd",
             "x y z label per input point, same order (0 = none, k = id + 1)")
      .value("--overlay", "FILE.png",
             "picture: tinted image for image-like input, top-down view otherwise")
      .value("--obstacles", "FILE.pcd",
             "the points more than --obstacle-min-height (default 0.05) and at most "
             "--obstacle-max-height (default 2) m above the floor under them (the lowest level "
             "surface of 0.25 m² or more seen from above), x y z (rgb) as read; none without a "
             "floor")
      .value("--obstacle-min-height", "M", "see --obstacles and --floor-grid")
      .value("--obstacle-max-height", "M", "see --obstacles and --floor-grid")
      .value("--floor-grid", "FILE.pgm",
             "the floor as ROS map_server loads a map (FILE.pgm and FILE.yaml): cells of "
             "--grid-resolution (default 0.05) m in the reference frame, black where an "
             "obstacle point stands, white where only the floor was seen, grey unseen; none "
             "written without a floor")
      .value("--grid-resolution", "M", "see --floor-grid")
      .flag("--quiet", "no table on stdout");
  return cl;
}

// The parsed command line, as every helper below reads it.
using Options = hope::tools::ParsedArgs;

double number(const Options& o, const std::string& key, double fallback) {
  const auto it = o.values.find(key);
  if (it == o.values.end()) return fallback;
  return hope::tools::parseNumbers(it->second, 1, key.c_str())[0];
}

// A whole-number option in [lo, hi], or `fallback` when absent.
int wholeNumber(const Options& o, const std::string& key, int fallback, int lo, int hi) {
  const double value = number(o, key, fallback);
  if (!(value >= lo && value <= hi) || value != std::floor(value)) {
    throw std::invalid_argument(key + " must be a whole number in [" + std::to_string(lo) + ", " +
                                std::to_string(hi) + "]");
  }
  return static_cast<int>(value);
}

std::uint64_t maxPoints(const Options& o) {
  const double value = number(o, "--max-points", double(hope::tools::kDefaultMaxPoints));
  if (!(value >= 1 && value <= 1e12) || value != std::floor(value)) {
    throw std::invalid_argument("--max-points must be a whole number in [1, 1e12]");
  }
  return static_cast<std::uint64_t>(value);
}

hope::Orientation rotationOrPose(const Options& o) {
  using hope::tools::parseNumbers;
  int given = 0;
  for (const char* key : {"--pose", "--quaternion", "--rpy", "--gravity"}) {
    given += o.values.count(key) ? 1 : 0;
  }
  if (given > 1) {
    throw std::invalid_argument("give at most one of --pose, --quaternion, --rpy, --gravity");
  }
  if (o.values.count("--pose")) {
    const auto v = parseNumbers(o.values.at("--pose"), 7, "--pose");
    return hope::Orientation::fromPose(v[0], v[1], v[2], v[3], v[4], v[5], v[6]);
  }
  if (o.values.count("--quaternion")) {
    const auto v = parseNumbers(o.values.at("--quaternion"), 4, "--quaternion");
    return hope::Orientation::fromQuaternion(v[0], v[1], v[2], v[3]);
  }
  if (o.values.count("--rpy")) {
    const auto v = parseNumbers(o.values.at("--rpy"), 3, "--rpy");
    return hope::Orientation::fromRollPitchYaw(v[0], v[1], v[2]);
  }
  if (o.values.count("--gravity")) {
    const auto v = parseNumbers(o.values.at("--gravity"), 3, "--gravity");
    return hope::Orientation::fromGravity(v[0], v[1], v[2]);
  }
  return hope::Orientation::identity();
}

bool orientationGiven(const Options& o) {
  return o.values.count("--pose") || o.values.count("--quaternion") || o.values.count("--rpy") ||
         o.values.count("--gravity");
}

// `orientation` with --viewpoint applied when it is given.
hope::Orientation withViewpointOption(const Options& o, const hope::Orientation& orientation) {
  if (!o.values.count("--viewpoint")) return orientation;
  const auto v = hope::tools::parseNumbers(o.values.at("--viewpoint"), 3, "--viewpoint");
  return orientation.withViewpoint(Eigen::Vector3d(v[0], v[1], v[2]));
}

// The orientation options, with --viewpoint applied. `sensor_frame_cloud`: the points are in
// the sensor's own frame (a depth image), so the sensor is at the origin when nothing else says.
hope::Orientation orientation(const Options& o, bool sensor_frame_cloud = false) {
  hope::Orientation result = rotationOrPose(o);
  if (o.values.count("--viewpoint")) return withViewpointOption(o, result);
  if (sensor_frame_cloud && !result.viewpoint()) {
    result = result.withViewpoint(Eigen::Vector3d::Zero());
  }
  return result;
}

hope::PinholeIntrinsics intrinsics(const Options& o) {
  hope::PinholeIntrinsics k = hope::PinholeIntrinsics::tumFreiburg1();
  if (o.values.count("--intrinsics")) {
    const auto v = hope::tools::parseNumbers(o.values.at("--intrinsics"), 4, "--intrinsics");
    k = {v[0], v[1], v[2], v[3]};
  }
  return k;
}

// A sequence's camera: --intrinsics, else the folder's intrinsics.txt, else TUM freiburg1's,
// said on stderr (unless --quiet) since depth images give wrong planes with wrong intrinsics
// and nothing else would show it: 3 cm off and areas 15 % too large on a Kinect folder read
// with TUM fr1's.
hope::PinholeIntrinsics sequenceIntrinsics(const Options& o,
                                           const hope::tools::SequenceListing& listing) {
  if (listing.layout != "TUM RGB-D") return intrinsics(o);  // point clouds: not used
  std::string source;
  hope::PinholeIntrinsics k = intrinsics(o);
  if (o.values.count("--intrinsics")) {
    source = "--intrinsics";
    if (!listing.intrinsics_file.empty()) source += " (not " + listing.intrinsics_file + ")";
  } else if (!listing.intrinsics_file.empty()) {
    k = hope::tools::readIntrinsics(listing.intrinsics_file);
    source = listing.intrinsics_file;
  } else {
    source = "TUM freiburg1's: the folder has no intrinsics.txt (give --intrinsics)";
  }
  if (!o.flag("--quiet")) {
    std::cerr << "hope_extract: intrinsics " << k.fx << " " << k.fy << " " << k.cx << " " << k.cy
              << " from " << source << "\n";
  }
  return k;
}

// Every parameter of the table (hope/parameters.h) that hope_extract takes, from its option: a
// number, a choice, or a "--no-..." flag switching a default-on part off.
hope::PipelineOptions pipelineOptions(const Options& o) {
  hope::PipelineOptions options;
  for (const hope::ParameterSpec& spec : hope::pipelineParameters()) {
    if (spec.option.empty()) continue;
    if (spec.type == hope::ParameterSpec::Type::kBool) {
      if (o.flag(spec.option)) spec.set(options, 0.0);
    } else if (!o.values.count(spec.option)) {
      continue;
    } else if (spec.type == hope::ParameterSpec::Type::kChoice) {
      const std::string& value = o.values.at(spec.option);
      const auto choice = std::find(spec.choices.begin(), spec.choices.end(), value);
      if (choice == spec.choices.end()) {
        std::string known;
        for (const auto& c : spec.choices) known += (known.empty() ? "" : ", ") + c;
        throw std::invalid_argument(spec.name.substr(0, spec.name.find('_')) + " '" + value +
                                    "' is not one of " + known);
      }
      spec.set(options, static_cast<double>(choice - spec.choices.begin()));
    } else if (spec.type == hope::ParameterSpec::Type::kInt) {
      spec.set(options, wholeNumber(o, spec.option, 0, static_cast<int>(spec.min),
                                    static_cast<int>(spec.max)));
    } else {
      spec.set(options, number(o, spec.option, spec.default_value));
    }
  }
  // One thread unless asked (the table's default): on a loaded machine a second one gains
  // nothing (docs/performance.md).
  int& threads = options.extraction.threads;
  const int cores = static_cast<int>(std::thread::hardware_concurrency());
  if (cores > 0 && threads > cores) {
    std::cerr << "hope_extract: warning: --threads " << threads << ": this machine has " << cores
              << " core(s); using " << cores << "\n";
    threads = cores;
  }
  return options;
}

// --place "W D [CLEARANCE]", checked before any file is read.
std::optional<hope::PlacementQuery> placementQuery(const Options& o) {
  if (!o.values.count("--place")) return std::nullopt;
  if (o.flag("--no-objects"))
    throw std::invalid_argument("--place needs objects: drop --no-objects");
  const std::string& text = o.values.at("--place");
  std::istringstream words(text);
  std::size_t count = 0;
  for (std::string word; words >> word;) ++count;
  if (count != 2 && count != 3) {
    throw std::invalid_argument("--place: expected \"W D [CLEARANCE]\" in metres, got '" +
                                hope::tools::printableExcerpt(text) + "'");
  }
  const std::vector<double> v = hope::tools::parseNumbers(text, count, "--place");
  hope::PlacementQuery query;
  query.footprint.width = v[0];
  query.footprint.depth = v[1];
  if (count == 3) query.footprint.clearance = v[2];
  hope::validate(query.footprint);
  return query;
}

void printPlacements(const hope::PlacementQuery& query,
                     const std::vector<hope::Placement>& placements) {
  std::printf("%zu placement(s) for %.3f x %.3f m, clearance %.3f m%s\n", placements.size(),
              query.footprint.width, query.footprint.depth, query.footprint.clearance,
              placements.empty() ? ": no observed free surface holds it" : ", best first:");
  for (const hope::Placement& p : placements) {
    std::printf("  plane %d: x %.3f y %.3f z %.3f yaw %.1f deg, margin %.3f m\n", p.plane_id,
                p.centre.x(), p.centre.y(), p.centre.z(), p.yaw * 180.0 / M_PI, p.margin);
  }
}

// A progress bar with frames per second, only when stderr is a terminal.
class Progress {
 public:
  Progress(std::size_t total, bool enabled) : total_(total), enabled_(enabled && isatty(2)) {}
  void update(std::size_t done) {
    if (!enabled_) return;
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
    const int width = 30;
    const int filled = static_cast<int>(width * done / std::max<std::size_t>(total_, 1));
    std::fprintf(stderr, "\r[%s%s] %zu/%zu frames, %.1f frames/s ",
                 std::string(filled, '#').c_str(), std::string(width - filled, '.').c_str(), done,
                 total_, seconds > 0 ? done / seconds : 0.0);
    if (done == total_) std::fprintf(stderr, "\n");
  }

 private:
  std::size_t total_;
  bool enabled_;
  std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
};

// How a sequence's frames are oriented and levelled, as the nodelet's orientation_source and
// refine_orientation say it.
struct SequencePlan {
  hope::tools::SequenceOptions listing;
  std::string source;  // groundtruth, accelerometer, fixed or scene
  hope::SceneLevelling levelling = hope::SceneLevelling::kOff;
};

// The sequence's options checked against each other and the folder before any frame is read:
// an option that cannot apply is an error, never silently ignored.
SequencePlan sequencePlan(const Options& o) {
  for (const char* single : {"--input", "--depth", "--rgb", "--json", "--labels", "--overlay",
                             "--place", "--obstacles", "--floor-grid"}) {
    if (o.values.count(single) || o.flag(single)) {
      throw std::invalid_argument(std::string(single) +
                                  " is for one frame; with --sequence use --jsonl / --overlay-dir");
    }
  }
  if (o.values.count("--repeat")) {
    throw std::invalid_argument(
        "--repeat times repeated extractions of one input; it does not go with --sequence");
  }
  SequencePlan plan;
  hope::tools::SequenceOptions& seq = plan.listing;
  seq.dir = o.values.at("--sequence");
  if (!std::filesystem::is_directory(seq.dir)) {
    throw std::invalid_argument(
        "--sequence '" + seq.dir + "' " +
        (std::filesystem::exists(seq.dir) ? "is not a folder" : "does not exist"));
  }
  seq.max_time_difference = number(o, "--max-time-difference", seq.max_time_difference);
  seq.strict = o.flag("--strict");
  const bool fixed = orientationGiven(o);
  const bool has_gt = o.values.count("--groundtruth") > 0;
  const bool has_acc = o.values.count("--accelerometer") > 0;
  const bool folder_gt =
      std::filesystem::exists(std::filesystem::path(seq.dir) / "groundtruth.txt");
  if (int(fixed) + int(has_gt) + int(has_acc) > 1) {
    throw std::invalid_argument(
        "give one orientation source: --groundtruth, --accelerometer, or a fixed one");
  }
  std::string& source = plan.source;
  if (o.values.count("--orientation-source")) {
    source = o.values.at("--orientation-source");
    const bool consistent = source == "groundtruth"     ? !fixed && !has_acc
                            : source == "accelerometer" ? !fixed && !has_gt
                            : source == "fixed"         ? fixed
                            : source == "scene"         ? !fixed && !has_gt && !has_acc
                                                        : false;
    if (source != "groundtruth" && source != "accelerometer" && source != "fixed" &&
        source != "scene") {
      throw std::invalid_argument("--orientation-source '" + source +
                                  "' is not one of groundtruth, accelerometer, fixed, scene");
    }
    if (!consistent) {
      throw std::invalid_argument("--orientation-source " + source +
                                  (source == "fixed"
                                       ? " needs one of --pose, --quaternion, --rpy, --gravity"
                                       : " does not go with the other orientation option given"));
    }
  } else {
    // A folder's poses are the default orientation, refined by --level like any other; --level
    // alone on a folder without poses levels every frame from its scene.
    source = fixed                 ? "fixed"
             : has_acc             ? "accelerometer"
             : has_gt || folder_gt ? "groundtruth"
             : o.flag("--level")   ? "scene"
                                   : "";
    if (source.empty()) {
      throw std::invalid_argument("no " + seq.dir +
                                  "/groundtruth.txt: give --groundtruth FILE, --accelerometer "
                                  "FILE, one fixed --pose/--quaternion/--rpy/--gravity, or "
                                  "--level to level every frame from its scene");
    }
  }
  plan.levelling = source == "scene"   ? hope::SceneLevelling::kEstimate
                   : o.flag("--level") ? hope::SceneLevelling::kRefine
                                       : hope::SceneLevelling::kOff;
  if (source == "accelerometer") {
    seq.source = hope::tools::OrientationSource::kAccelerometer;
    seq.orientation_file = has_acc ? o.values.at("--accelerometer") : std::string();
  } else if (source == "groundtruth") {
    seq.source = hope::tools::OrientationSource::kGroundTruth;
    seq.orientation_file = has_gt ? o.values.at("--groundtruth") : std::string();
    if (o.values.count("--viewpoint")) {
      throw std::invalid_argument(
          "--viewpoint does not go with ground-truth poses: each frame's viewpoint is its "
          "pose's translation");
    }
  } else {
    seq.source = hope::tools::OrientationSource::kNone;
  }
  if (seq.source == hope::tools::OrientationSource::kNone &&
      o.values.count("--max-time-difference") && !o.values.count("--overlay-dir")) {
    std::cerr << "hope_extract: warning: --max-time-difference pairs frames with poses, "
                 "accelerometer samples or colour images; with a fixed orientation or up from "
                 "the scene and no --overlay-dir it has nothing to pair\n";
  }
  return plan;
}

// A frame's overlay file: named by its stamp, made unique when two frames share one.
std::string overlayName(const std::string& dir, double stamp, std::set<std::string>& used) {
  std::string name = hope::tools::stampText(stamp);
  for (int copy = 2; !used.insert(name).second; ++copy) {
    name = hope::tools::stampText(stamp) + "_" + std::to_string(copy);
  }
  return dir + "/" + name + ".png";
}

// A JSON line's opening members, a frame's and a skipped frame's alike.
std::string lineStart(double stamp, const std::string& file) {
  return "{\"stamp\": " + hope::tools::stampText(stamp) +
         ", \"file\": " + hope::tools::jsonString(file);
}

void writeFrameLine(std::ostream& jsonl, const std::string& file, const hope::Frame& frame,
                    bool objects) {
  const hope::Result& result = frame.result;
  jsonl << lineStart(frame.stamp, file) << ", "
        << hope::tools::orientationJson(result.sensor_to_reference);
  if (frame.levelling) {
    jsonl << ", \"levelling\": " << hope::tools::levellingJson(*frame.levelling);
  }
  if (frame.level_held) {
    jsonl << ", \"level_held\": " << hope::tools::jsonString(frame.skipped);
  }
  if (frame.odometry) {
    jsonl << ", \"odometry\": {\"tracked\": " << (frame.odometry->tracked ? "true" : "false")
          << ", \"started\": " << (frame.odometry->started ? "true" : "false")
          << ", \"overlap\": " << frame.odometry->overlap << ", \"ms\": " << frame.odometry->ms
          << ", \"world_from_frame\": " << hope::tools::matrixJson(frame.odometry->world_from_frame)
          << "}";
  }
  if (!result.warnings.empty()) {
    jsonl << ", \"warnings\": [";
    for (std::size_t w = 0; w < result.warnings.size(); ++w) {
      jsonl << (w ? ", " : "") << hope::tools::jsonString(result.warnings[w]);
    }
    jsonl << "]";
  }
  jsonl << ", \"planes\": [";
  for (std::size_t p = 0; p < result.planes.size(); ++p) {
    jsonl << (p ? ", " : "");
    hope::tools::writePlaneJson(jsonl, result.planes[p]);
  }
  if (objects) {
    jsonl << "], \"objects\": [";
    for (std::size_t k = 0; k < result.objects.size(); ++k) {
      jsonl << (k ? ", " : "");
      hope::tools::writeObjectJson(jsonl, result.objects[k]);
    }
  }
  jsonl << "], \"events\": [";
  for (std::size_t e = 0; e < frame.events.size(); ++e) {
    const hope::TrackEvent& event = frame.events[e];
    jsonl << (e ? ", " : "") << "{\"kind\": \"" << hope::toString(event.kind)
          << "\", \"id\": " << event.id << ", \"other_id\": " << event.other_id << "}";
  }
  jsonl << "]}\n";
}

// Whether any frame's position (its pose's translation) is more than 1 mm from the first's.
bool positionsChange(const std::vector<hope::tools::SequenceFrame>& frames) {
  if (frames.empty()) return true;  // nothing to judge: the folder says why elsewhere
  for (const hope::tools::SequenceFrame& frame : frames) {
    const Eigen::Vector3d moved = frame.orientation.sensorToReference().translation() -
                                  frames.front().orientation.sensorToReference().translation();
    if (moved.norm() > 1e-3) return true;
  }
  return false;
}

int runSequence(const Options& o) {
  const SequencePlan plan = sequencePlan(o);
  const hope::tools::SequenceOptions& seq = plan.listing;
  hope::PipelineOptions pipeline_options = pipelineOptions(o);
  pipeline_options.levelling = plan.levelling;
  if (!o.flag("--level") && o.values.count("--level-bound")) {
    throw std::invalid_argument("--level-bound goes with --level");
  }
  // World poses put every frame in one fixed frame: then a map of the surfaces keeps each one
  // entry for the whole run (its id until --map-forget frames unseen). Gravity alone leaves the
  // camera's position unknown: the scene's own odometry finds it, and the same map is kept in
  // its frame. --tracking auto (the default) takes the one that fits (hope::defaultIdentity),
  // once the poses are read.
  const bool fixed_frame = seq.source == hope::tools::OrientationSource::kGroundTruth;
  std::string tracking = hope::toString(pipeline_options.identity);
  const bool use_map = hope::keepsSurfaceMap(pipeline_options.identity);
  if (pipeline_options.identity == hope::Identity::kMap && !fixed_frame) {
    throw std::invalid_argument(
        "--tracking map needs a fixed frame: world poses (the folder's groundtruth.txt or "
        "--groundtruth); with --accelerometer, a fixed orientation or up from the scene the "
        "camera's position is unknown (--tracking odometry finds it from the scene)");
  }
  hope::FramePipeline pipeline(pipeline_options);  // validates every option
  if (o.values.count("--map-forget") && !use_map) {
    throw std::invalid_argument("--map-forget is the surface map's memory, which --tracking " +
                                tracking + " does not keep");
  }
  std::optional<hope::tools::OutputFile> map_file;
  if (o.values.count("--map")) {
    if (!use_map) {
      throw std::invalid_argument("--map writes the surface map, which --tracking " + tracking +
                                  " does not keep");
    }
    map_file.emplace(o.values.at("--map"));
  }
  std::optional<hope::tools::OutputFile> extents_file;
  std::optional<hope::tools::MapExtentCheck> extents;
  if (o.values.count("--map-extents")) {
    if (!use_map) {
      throw std::invalid_argument("--map-extents compares the surface map, which --tracking " +
                                  tracking + " does not keep");
    }
    extents_file.emplace(o.values.at("--map-extents"));
    extents.emplace();
  }
  const hope::Orientation fixed_orientation = orientation(o);
  const double depth_scale = number(o, "--depth-scale", 5000);
  const std::uint64_t max_points = maxPoints(o);

  hope::tools::SequenceListing listing = hope::tools::listSequence(seq);
  const int every = wholeNumber(o, "--every", 1, 1, 1000000);
  if (every > 1) {
    std::vector<hope::tools::SequenceFrame> kept;
    for (std::size_t f = 0; f < listing.frames.size(); f += static_cast<std::size_t>(every)) {
      kept.push_back(listing.frames[f]);
    }
    listing.frames = std::move(kept);
  }
  // Poses whose position never changes are an orientation written as poses (or a camera that
  // only turns): they cannot put a moving camera's surfaces in one fixed frame, and the map
  // would take every surface seen from a new place for a new one. The scene's odometry finds
  // the position by default; a warning when the map was asked for.
  const bool positions_change = fixed_frame && positionsChange(listing.frames);
  const hope::PoseInput input =
      positions_change ? hope::PoseInput::kFixedFramePoses : hope::PoseInput::kOrientation;
  if (pipeline_options.identity == hope::Identity::kAuto) {
    pipeline.setOptions([&] {
      hope::PipelineOptions resolved = pipeline.options();
      resolved.identity = hope::defaultIdentity(input);
      return resolved;
    }());
    tracking = hope::toString(pipeline.options().identity);
    if (fixed_frame && !positions_change) {
      std::cerr << "hope_extract: the poses' position never changes (an orientation only): the "
                   "scene's odometry finds it, and the surface map is kept in its frame\n";
    }
  } else if (fixed_frame && !positions_change &&
             pipeline_options.identity == hope::Identity::kMap) {
    std::cerr << "hope_extract: warning: the poses' position never changes (an orientation "
                 "only?): the surface map needs poses in a fixed frame; if the camera moved, "
                 "its ids will not hold (--tracking odometry)\n";
  }

  const bool depth_frames = listing.layout == "TUM RGB-D";
  if (!depth_frames && (o.values.count("--intrinsics") || o.values.count("--depth-scale"))) {
    throw std::invalid_argument("--intrinsics and --depth-scale are for depth images; '" + seq.dir +
                                "' is a folder of .pcd clouds");
  }
  hope::tools::RunSummary summary;
  for (const std::string& line : listing.bad_lines) summary.skipLine(line);

  const hope::PinholeIntrinsics k = sequenceIntrinsics(o, listing);
  // Outputs last, after every argument was checked; the JSON lines are renamed into place
  // when the run ends, with a record for every frame that was skipped.
  std::unique_ptr<hope::tools::OutputFile> jsonl_file;
  std::ofstream jsonl;
  if (o.values.count("--jsonl")) {
    jsonl_file = std::make_unique<hope::tools::OutputFile>(o.values.at("--jsonl"));
    jsonl.open(jsonl_file->writePath());
    if (!jsonl) hope::tools::throwCannotWrite(jsonl_file->path());
  }
  const std::string overlay_dir =
      o.values.count("--overlay-dir") ? o.values.at("--overlay-dir") : "";
  if (!overlay_dir.empty()) std::filesystem::create_directories(overlay_dir);
  std::set<std::string> overlay_names;

  Progress progress(listing.frames.size(), !o.flag("--quiet"));
  std::set<int> ids;
  std::size_t total_planes = 0, processed = 0, uncorrected = 0;
  std::vector<double> objects_per_frame;  // when the outputs ask for objects
  std::string first_uncorrected;
  double extract_ms = 0, track_ms = 0, level_ms = 0, odometry_ms = 0;
  std::size_t odometry_untracked = 0;  // frames the odometry could not align (not a world's first)
  // What the outputs show: objects in the JSON lines and overlays, the points for overlays and
  // the map's extents.
  hope::FrameOutputs wanted;
  wanted.keep_points = !overlay_dir.empty() || extents;
  wanted.point_labels = wanted.keep_points;
  wanted.objects = jsonl.is_open() || !overlay_dir.empty();
  // Frames with no orientation near enough in time: recorded among the others, by stamp.
  std::size_t next_unoriented = 0;
  auto recordUnorientedUntil = [&](double stamp) {
    for (; next_unoriented < listing.without_orientation.size() &&
           listing.without_orientation[next_unoriented].stamp < stamp;
         ++next_unoriented) {
      const hope::tools::StampedFile& unoriented = listing.without_orientation[next_unoriented];
      std::ostringstream reason;
      reason << "no orientation within " << seq.max_time_difference << " s";
      summary.skipFrame(reason.str(), unoriented.path, reason.str());
      if (jsonl.is_open()) {
        jsonl << lineStart(unoriented.stamp, unoriented.path)
              << ", \"skipped\": " << hope::tools::jsonString(reason.str()) << "}\n";
      }
    }
  };
  for (std::size_t f = 0; f < listing.frames.size(); ++f) {
    const hope::tools::SequenceFrame& frame = listing.frames[f];
    recordUnorientedUntil(frame.stamp);
    const std::string& file = frame.depth.empty() ? frame.cloud : frame.depth;
    // A frame that cannot be used is skipped, named and counted (--strict: the run stops):
    // one corrupt file must not lose the frames around it.
    auto skip = [&](const std::string& kind, const std::string& reason) {
      if (seq.strict) {
        throw std::runtime_error(hope::tools::withFile(file, reason));
      }
      summary.skipFrame(kind, file, reason);
      if (jsonl.is_open()) {
        jsonl << lineStart(frame.stamp, file)
              << ", \"skipped\": " << hope::tools::jsonString(reason) << "}\n";
      }
      progress.update(f + 1);
    };
    hope::tools::InputCloud input;
    try {
      input = frame.depth.empty()
                  ? hope::tools::loadCloud(frame.cloud, max_points)
                  : hope::tools::loadDepth(frame.depth, overlay_dir.empty() ? "" : frame.rgb, k,
                                           depth_scale, max_points);
    } catch (const std::bad_alloc&) {
      skip("could not be read", "out of memory reading it");
      continue;
    } catch (const std::exception& error) {
      skip("could not be read", error.what());
      continue;
    }
    hope::Orientation frame_orientation =
        seq.source == hope::tools::OrientationSource::kNone ? fixed_orientation : frame.orientation;
    // A depth image's points are in the camera's frame: the sensor is at the origin unless
    // the orientation says where it was (a pose) or --viewpoint does.
    if (depth_frames && !frame_orientation.viewpoint()) {
      frame_orientation = frame_orientation.withViewpoint(Eigen::Vector3d::Zero());
    }
    if (seq.source != hope::tools::OrientationSource::kGroundTruth) {
      frame_orientation = withViewpointOption(o, frame_orientation);
    }
    hope::Frame result;
    try {
      result = seq.source == hope::tools::OrientationSource::kAccelerometer
                   ? pipeline.processWithGravity(input.view(), frame.stamp, frame.specific_force,
                                                 wanted, *frame_orientation.viewpoint())
                   : pipeline.process(input.view(), frame.stamp, frame_orientation, wanted);
    } catch (const std::invalid_argument& error) {
      skip("could not be used", error.what());
      continue;
    }
    if (result.levelling) level_ms += result.levelling->time_ms;
    if (result.odometry) {
      odometry_ms += result.odometry->ms;
      odometry_untracked += !result.odometry->tracked && !result.odometry->started;
    }
    if (!result.processed) {
      // Nothing level in view, and no earlier up to hold: skipped, not guessed; the tracker
      // does not see it, the JSON lines record it.
      skip("nothing level in view to find up from", result.skipped);
      continue;
    }
    if (result.levelling && result.levelling->refinement && !result.levelling->applied &&
        uncorrected++ == 0) {
      first_uncorrected = file + ": " + result.levelling->note;
    }
    ++processed;
    track_ms += result.identity_ms;
    if (extents) extents->addFrame(result.result, result.points, result.events);
    extract_ms += result.result.timings.total_ms;
    total_planes += result.result.planes.size();
    if (wanted.objects && pipeline.options().objects) {
      objects_per_frame.push_back(static_cast<double>(result.result.objects.size()));
    }
    for (const auto& p : result.result.planes) ids.insert(p.id);
    for (const auto& warning : result.result.warnings) summary.warn(file, warning);

    if (jsonl.is_open()) writeFrameLine(jsonl, file, result, wanted.objects);
    if (!overlay_dir.empty()) {
      hope::tools::OutputFile overlay(overlayName(overlay_dir, frame.stamp, overlay_names));
      hope::tools::writeImage(overlay,
                              hope::tools::renderOverlay(input, result.points, result.result));
      overlay.commit();
    }
    progress.update(f + 1);
  }
  recordUnorientedUntil(std::numeric_limits<double>::infinity());
  if (jsonl_file) {
    jsonl.close();
    if (jsonl.fail()) hope::tools::throwCannotWrite(jsonl_file->path());
    jsonl_file->commit();
  }
  if (map_file) {
    hope::tools::writeText(*map_file, [&](std::ostream& out) {
      out << "{\"surfaces\": [";
      const std::vector<hope::HorizontalPlane> surfaces = pipeline.mapSurfaces();
      for (std::size_t k = 0; k < surfaces.size(); ++k) {
        out << (k ? ",\n  " : "\n  ");
        hope::tools::writePlaneJson(out, surfaces[k]);
      }
      out << "\n]}\n";
    });
    map_file->commit();
  }
  if (extents_file) {
    hope::tools::writeText(*extents_file, [&](std::ostream& out) {
      out << hope::tools::formatMapExtents(extents->compare(pipeline.mapSurfaces()), 12);
    });
    extents_file->commit();
  }
  summary.print(std::cerr, "hope_extract");
  if (uncorrected > 0) {
    std::cerr << "hope_extract: warning: --level kept the given orientation of " << uncorrected
              << " frame(s) (the first: " << first_uncorrected << ")\n";
  }
  if (processed == 0) {
    throw std::runtime_error("none of the " + std::to_string(summary.skippedFrames()) +
                             " frame(s) of '" + seq.dir +
                             "' could be used (the reasons are in the warnings above)");
  }
  const double n = static_cast<double>(processed);
  std::printf(
      "%zu frame(s) of %s (%s, %s tracking): %.1f planes/frame, %zu distinct ids, extraction "
      "%.2f ms/frame, tracking %.3f ms/frame",
      processed, seq.dir.c_str(), listing.layout.c_str(), tracking.c_str(), total_planes / n,
      ids.size(), extract_ms / n, track_ms / n);
  if (plan.levelling != hope::SceneLevelling::kOff) {
    std::printf(", %s from the scene %.2f ms/frame",
                plan.levelling == hope::SceneLevelling::kEstimate ? "levelling" : "refinement",
                level_ms / n);
  }
  if (pipeline.options().identity == hope::Identity::kOdometry) {
    std::printf(", odometry %.2f ms/frame (%zu not aligned)", odometry_ms / n, odometry_untracked);
  }
  if (!objects_per_frame.empty()) {
    // The median and the most: a room's count is read per frame, and a mean hides one frame
    // that floods (docs/quality.md, objects a frame).
    std::printf(", objects/frame median %g (max %g)", hope::tools::median(objects_per_frame),
                *std::max_element(objects_per_frame.begin(), objects_per_frame.end()));
  }
  const std::size_t skipped = summary.skippedFrames();
  std::printf("%s\n", skipped ? (", " + std::to_string(skipped) + " skipped").c_str() : "");
  return 0;
}

int run(const Options& o) {
  for (const char* band : {"--obstacle-min-height", "--obstacle-max-height"}) {
    if (o.values.count(band) && !o.values.count("--obstacles") && !o.values.count("--floor-grid")) {
      throw std::invalid_argument(std::string(band) + " goes with --obstacles or --floor-grid");
    }
  }
  if (o.values.count("--grid-resolution") && !o.values.count("--floor-grid")) {
    throw std::invalid_argument("--grid-resolution goes with --floor-grid");
  }
  const std::string grid_path = o.values.count("--floor-grid") ? o.values.at("--floor-grid") : "";
  const std::string pgm = ".pgm";
  if (o.values.count("--floor-grid") &&
      (grid_path.size() <= pgm.size() ||
       grid_path.compare(grid_path.size() - pgm.size(), pgm.size(), pgm) != 0)) {
    throw std::invalid_argument(
        "--floor-grid wants a FILE.pgm (with FILE.yaml beside it, as "
        "map_server loads a map), got '" +
        grid_path + "'");
  }
  if (o.values.count("--sequence")) return runSequence(o);
  for (const char* sequence_only :
       {"--groundtruth", "--accelerometer", "--max-time-difference", "--tracking", "--jsonl",
        "--orientation-source", "--level-smoothing", "--level-hold", "--gravity-window",
        "--overlay-dir", "--strict", "--map", "--map-extents", "--map-forget", "--every"}) {
    if (o.values.count(sequence_only) || o.flag(sequence_only)) {
      throw std::invalid_argument(std::string(sequence_only) + " goes with --sequence");
    }
  }
  const bool has_input = o.values.count("--input") > 0;
  const bool has_depth = o.values.count("--depth") > 0;
  if (has_input == has_depth) {
    throw std::invalid_argument("give exactly one of --input, --depth or --sequence (see --help)");
  }
  if (!has_depth && (o.values.count("--rgb") || o.values.count("--intrinsics") ||
                     o.values.count("--depth-scale"))) {
    throw std::invalid_argument("--rgb, --intrinsics and --depth-scale go with --depth");
  }

  if (!o.flag("--level") && o.values.count("--level-bound")) {
    throw std::invalid_argument("--level-bound goes with --level");
  }
  const bool level = o.flag("--level");
  hope::PipelineOptions options = pipelineOptions(o);
  // --level: up estimated from the scene when no orientation is given, else the given one
  // refined by it.
  options.levelling = !level                ? hope::SceneLevelling::kOff
                      : orientationGiven(o) ? hope::SceneLevelling::kRefine
                                            : hope::SceneLevelling::kEstimate;
  hope::FramePipeline pipeline(options);  // validates before any file is read
  const std::optional<hope::PlacementQuery> place = placementQuery(o);
  const int repeat = wholeNumber(o, "--repeat", 1, 1, 100000);
  // A cloud levelled from the scene is taken to be in its sensor's frame, as a depth image is.
  const hope::Orientation pose = orientation(o, has_depth || level);
  const std::uint64_t max_points = maxPoints(o);
  const double depth_scale = number(o, "--depth-scale", 5000);
  const hope::PinholeIntrinsics k = intrinsics(o);
  // Every output is opened (as a temporary) after the arguments were checked and before the
  // work, so an unwritable one fails at once; all are renamed into place at the end, so a
  // failure leaves none of them behind.
  std::map<std::string, hope::tools::OutputFile> outputs;
  for (const char* key : {"--json", "--labels", "--overlay", "--obstacles", "--floor-grid"}) {
    if (o.values.count(key)) outputs.emplace(key, hope::tools::OutputFile(o.values.at(key)));
  }
  if (!grid_path.empty()) {
    outputs.emplace(
        "--floor-grid yaml",
        hope::tools::OutputFile(grid_path.substr(0, grid_path.size() - pgm.size()) + ".yaml"));
  }

  hope::tools::InputCloud input;
  if (has_input) {
    input = hope::tools::loadCloud(o.values.at("--input"), max_points);
  } else {
    const auto rgb = o.values.count("--rgb") ? o.values.at("--rgb") : std::string();
    input = hope::tools::loadDepth(o.values.at("--depth"), rgb, k, depth_scale, max_points);
  }

  // Per-point labels and objects only for the outputs that show them: 4 bytes a point and the
  // objects' time saved otherwise; the points kept for placements and the overlay.
  hope::FrameOutputs wanted;
  wanted.point_labels = outputs.count("--labels") || outputs.count("--overlay");
  wanted.objects =
      outputs.count("--json") || outputs.count("--labels") || outputs.count("--overlay") || place;
  wanted.keep_points = place || outputs.count("--overlay");
  wanted.obstacles = outputs.count("--obstacles") > 0;
  wanted.floor_grid = outputs.count("--floor-grid") > 0;
  hope::Frame frame = pipeline.processAlone(input.view(), pose, wanted);
  if (!frame.processed) throw hope::LevellingError(frame.skipped);
  const std::optional<hope::UpEstimate>& levelled = frame.levelling;
  if (levelled && !o.flag("--quiet")) {
    std::cerr << "hope_extract: " << (levelled->refinement ? "refined" : "levelled")
              << " from the scene in " << std::fixed << std::setprecision(2) << levelled->time_ms
              << " ms: " << levelled->describe() << "\n";
    std::cerr.unsetf(std::ios::floatfield);
  }
  if (levelled && levelled->refinement && !levelled->applied) {
    std::cerr << "hope_extract: warning: --level kept the given orientation: " << levelled->note
              << "\n";
  }
  const double cold_ms = frame.result.timings.total_ms;
  std::vector<double> steady_ms;
  for (int k = 1; k < repeat; ++k) {
    frame = pipeline.processAlone(input.view(), pose, wanted);
    steady_ms.push_back(frame.result.timings.total_ms);
  }
  hope::Result& result = frame.result;
  const bool objects_made = options.objects && wanted.objects;
  std::vector<hope::Placement> placements;
  if (place) {
    placements = pipeline.findPlacements(frame, *place);
  }
  if (!level && !orientationGiven(o)) {
    // Nothing said which way is up: the cloud was taken as z-up. Say so when it does not look it.
    for (const auto& warning :
         hope::unorientedCloudWarnings(input.view(), result.planes, pose.viewpoint().has_value())) {
      result.warnings.push_back(warning);
    }
  }
  for (const auto& warning : result.warnings)
    std::cerr << "hope_extract: warning: " << warning << "\n";
  if (!o.flag("--quiet")) hope::tools::printTable(std::cout, result);
  if (!o.flag("--quiet") && objects_made) {
    std::printf("%zu object(s) standing on the planes\n", result.objects.size());
  }
  if (!o.flag("--quiet") && place) printPlacements(*place, placements);
  if (!o.flag("--quiet") && !steady_ms.empty()) {
    std::nth_element(steady_ms.begin(), steady_ms.begin() + steady_ms.size() / 2, steady_ms.end());
    const double median = steady_ms[steady_ms.size() / 2];
    std::printf(
        "cold first call %.2f ms, steady state %.2f ms (median of %zu more calls), "
        "%.2fx\n",
        cold_ms, median, steady_ms.size(), cold_ms / median);
  }

  if (outputs.count("--json")) {
    hope::tools::writeText(outputs.at("--json"), [&](std::ostream& out) {
      hope::tools::writeJson(out, result, levelled ? &*levelled : nullptr,
                             place ? &placements : nullptr);
    });
  }
  if (outputs.count("--labels")) {
    std::vector<std::uint32_t> labels(result.point_labels.size());
    for (std::size_t i = 0; i < labels.size(); ++i) {
      const int index = result.point_labels[i];
      labels[i] = index < 0 ? 0u : static_cast<std::uint32_t>(result.planes[index].id + 1);
    }
    // 0 for no object (or none asked for), k for object k - 1, as the plane labels.
    std::vector<std::int32_t> objects(labels.size(), 0);
    for (std::size_t i = 0; i < result.point_objects.size(); ++i) {
      objects[i] = result.point_objects[i] + 1;
    }
    hope::tools::writeLabels(outputs.at("--labels"), input, labels, objects);
  }
  if (outputs.count("--obstacles")) {
    if (frame.floor_index < 0) {
      std::cerr << "hope_extract: warning: no floor in view (a level surface of 0.25 m² or more "
                   "seen from above): --obstacles holds no point\n";
    }
    hope::tools::writePoints(outputs.at("--obstacles"), input, frame.obstacles);
  }
  if (outputs.count("--floor-grid")) {
    if (frame.floor_index < 0) {
      // Nothing to draw a map around: both files are left out (their temporaries removed).
      std::cerr << "hope_extract: warning: no floor in view (a level surface of 0.25 m² or more "
                   "seen from above): --floor-grid writes no file\n";
      outputs.erase("--floor-grid");
      outputs.erase("--floor-grid yaml");
    } else {
      hope::tools::writeFloorGrid(outputs.at("--floor-grid"), outputs.at("--floor-grid yaml"),
                                  frame.floor_grid);
    }
  }
  if (outputs.count("--overlay")) {
    hope::tools::writeImage(
        outputs.at("--overlay"),
        hope::tools::renderOverlay(input, hope::AlignedPoints(frame.points), result, placements,
                                   place ? place->footprint : hope::Footprint()));
  }
  for (auto& output : outputs) output.second.commit();
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  return hope::tools::runTool("hope_extract", commandLine, run, argc, argv);
}
