#include "nodelet_settings.h"

#include <algorithm>
#include <cstdio>
#include <stdexcept>

namespace hope_ros {

std::string frameId(const std::string& frame) {
  return !frame.empty() && frame[0] == '/' ? frame.substr(1) : frame;
}

std::string ownFrame(const std::string& node_name, const char* suffix) {
  std::string frame = frameId(node_name);
  for (char& c : frame) c = c == '/' ? '_' : c;
  return (frame.empty() ? std::string("hope") : frame) + "_" + suffix;
}

namespace {

std::string number(double value) {
  char text[32];
  std::snprintf(text, sizeof(text), "%g", value);
  return text;
}

// A parameter that gave way to another: said, and converted when it still means something.
void replaced(ros::NodeHandle& pnh, const char* old_name, const char* new_name, double per_unit,
              double& value, std::vector<std::string>& notes) {
  double old_value = 0;
  if (!pnh.getParam(old_name, old_value)) return;
  if (pnh.hasParam(new_name)) {
    notes.push_back(std::string("~") + old_name + " is no longer used (~" + new_name + " is set)");
    return;
  }
  value = old_value * per_unit;
  notes.push_back(std::string("~") + old_name + " is replaced by ~" + new_name + ": " +
                  number(old_value) + " at 30 Hz is " + number(value) + " s");
}

}  // namespace

StartupSettings loadStartupSettings(ros::NodeHandle& pnh, const std::string& node_name,
                                    std::vector<std::string>& problems,
                                    std::vector<std::string>& notes) {
  StartupSettings s;
  hope::PipelineOptions& p = s.pipeline;
  pnh.param<std::string>("orientation_source", s.source, "imu");
  pnh.param<std::string>("reference_frame", s.reference_frame, "");
  s.reference_frame = frameId(s.reference_frame);
  if (pnh.hasParam("tf_timeout")) {
    notes.push_back(
        "~tf_timeout is no longer used: clouds wait for their transform in a queue of "
        "~tf_queue clouds, without blocking");
  }
  pnh.param("tf_queue", s.tf_queue, 5);
  s.tf_queue = std::max(1, std::min(s.tf_queue, 100));
  pnh.param("cloud_queue", s.cloud_queue, 3);
  s.cloud_queue = std::max(1, std::min(s.cloud_queue, 100));
  pnh.param("lazy", s.lazy, true);
  pnh.param<std::string>("view_frame", s.view_frame, "");
  s.view_frame = s.view_frame.empty()     ? ownFrame(node_name, "view")
                 : s.view_frame == "none" ? std::string()
                                          : frameId(s.view_frame);
  pnh.param<std::string>("odometry_frame", s.odometry_frame, "");
  s.odometry_frame = frameId(s.odometry_frame);
  if (!s.odometry_frame.empty() && s.odometry_frame == s.reference_frame) {
    problems.push_back("~odometry_frame '" + s.odometry_frame +
                       "' is the reference frame (a frame cannot be its own child); using " +
                       ownFrame(node_name, "odometry"));
    s.odometry_frame.clear();
  }
  if (s.odometry_frame.empty()) s.odometry_frame = ownFrame(node_name, "odometry");
  if (s.source != "imu" && s.source != "tf" && s.source != "fixed" && s.source != "scene" &&
      s.source != "none") {
    problems.push_back("orientation_source '" + s.source +
                       "' is not one of imu, tf, fixed, scene, none; using none");
    s.source = "none";
  }
  pnh.param("refine_orientation", s.refine, false);
  pnh.param("level_bound", p.level_bound_deg, p.level_bound_deg);
  pnh.param("level_smoothing", p.level_smoothing, p.level_smoothing);
  replaced(pnh, "level_hold_frames", "level_hold_s", 1.0 / 30, p.level_hold_s, notes);
  pnh.param("level_hold_s", p.level_hold_s, p.level_hold_s);
  replaced(pnh, "gravity_window", "gravity_window_s", 1.0 / 30, p.gravity_window_s, notes);
  pnh.param("gravity_window_s", p.gravity_window_s, p.gravity_window_s);
  if (pnh.hasParam("map_forget_s")) {
    notes.push_back("~map_forget_s is replaced by ~map_forget_frames (frames, not seconds)");
  }
  pnh.param("map_forget_frames", p.map_forget_frames, p.map_forget_frames);
  // Each start-up value checked on its own against the pipeline's ranges: a bad one is said and
  // its default used.
  auto checked = [&](const char* name, auto field) {  // a pointer to PipelineOptions' member
    hope::PipelineOptions alone;
    alone.*field = p.*field;
    try {
      hope::validate(alone);
    } catch (const std::exception& e) {
      p.*field = hope::PipelineOptions().*field;
      problems.push_back("~" + std::string(name) + ": " + e.what() + "; using " + number(p.*field));
    }
  };
  checked("level_bound", &hope::PipelineOptions::level_bound_deg);
  checked("level_smoothing", &hope::PipelineOptions::level_smoothing);
  checked("level_hold_s", &hope::PipelineOptions::level_hold_s);
  checked("gravity_window_s", &hope::PipelineOptions::gravity_window_s);
  checked("map_forget_frames", &hope::PipelineOptions::map_forget_frames);
  if (s.refine && (s.source == "scene" || s.source == "none")) {
    notes.push_back("~refine_orientation applies to imu, tf and fixed; ignored with " + s.source);
    s.refine = false;
  }
  p.levelling = s.source == "scene" ? hope::SceneLevelling::kEstimate
                : s.refine          ? hope::SceneLevelling::kRefine
                                    : hope::SceneLevelling::kOff;
  pnh.param("surface_map", s.surface_map, false);
  if (s.source == "tf" && s.reference_frame.empty()) {
    problems.push_back(
        "orientation_source tf needs ~reference_frame (e.g. base_link or odom); using none");
    s.source = "none";
  }
  if (s.surface_map && s.source != "tf") {
    problems.push_back(
        "~surface_map needs orientation_source tf and a fixed ~reference_frame (odom, map): "
        "with " +
        s.source + " the planes' frame moves with the sensor; using the tracker");
    s.surface_map = false;
  }
  if (s.source == "tf" && (s.reference_frame == "map" || s.reference_frame == "odom" ||
                           s.reference_frame == "world" || s.reference_frame == "earth")) {
    s.pose_input = hope::PoseInput::kFixedFramePoses;
  } else if (s.source == "tf" && !s.surface_map &&
             pnh.param<std::string>("tracking_mode", "auto") == "auto") {
    s.auto_tracking = "tracking_mode auto: odometry, since reference_frame '" + s.reference_frame +
                      "' is not one REP 105 names fixed in the world (map, odom, world, earth); "
                      "set tracking_mode map if it is fixed";
  }
  p.identity = hope::defaultIdentity(s.pose_input);
  if ((s.source == "imu" || s.source == "fixed" || s.source == "scene") &&
      s.reference_frame.empty()) {
    // Broadcast: z up, origin at the sensor. Named after this nodelet, so two hope nodelets
    // never broadcast one frame under two parents ("hope" → hope_gravity).
    s.reference_frame = ownFrame(node_name, "gravity");
  }
  if (s.source == "fixed") {
    std::vector<double> q, rpy;
    try {
      if (pnh.getParam("fixed_quaternion", q) && q.size() == 4) {
        s.fixed = hope::Orientation::fromQuaternion(q[0], q[1], q[2], q[3]);
      } else if (pnh.getParam("fixed_rpy", rpy) && rpy.size() == 3) {
        s.fixed = hope::Orientation::fromRollPitchYaw(rpy[0], rpy[1], rpy[2]);
      } else {
        problems.push_back(
            "orientation_source fixed needs ~fixed_quaternion [x, y, z, w] or ~fixed_rpy "
            "[roll, pitch, yaw]; using identity");
      }
    } catch (const std::exception& e) {
      problems.push_back(std::string("bad fixed orientation: ") + e.what() + "; using identity");
    }
  }
  return s;
}

hope::PipelineOptions withConfig(const hope::PipelineOptions& options,
                                 const hope::HopeConfig& config, bool map_allowed,
                                 hope::PoseInput input, std::vector<std::string>& problems) {
  hope::PipelineOptions result = options;
  hope::Params params;
  params.r_xy = config.r_xy;
  params.r_z = config.r_z;
  params.min_height = config.min_height <= -1000.0 ? hope::Params().min_height : config.min_height;
  params.max_height = config.max_height >= 1000.0 ? hope::Params().max_height : config.max_height;
  params.min_area = config.min_area;
  params.merge_fragments = config.merge_fragments;
  params.max_merge_gap = config.max_merge_gap;
  params.bridge_scan_gaps = config.bridge_scan_gaps;
  params.threads = config.threads;
  try {
    hope::validate(params);
    result.extraction = params;
  } catch (const std::exception& e) {
    problems.push_back(std::string("keeping the previous extraction parameters: ") + e.what());
  }
  try {
    const hope::Identity identity =
        hope::resolveIdentity(hope::identityFromString(config.tracking_mode), input);
    if (identity == hope::Identity::kMap && !map_allowed) {
      throw std::invalid_argument(
          "the surface map needs orientation_source tf and a fixed reference_frame");
    }
    result.identity = identity;
  } catch (const std::exception& e) {
    problems.push_back(std::string("keeping tracking mode ") + hope::toString(result.identity) +
                       ": " + e.what());
  }
  hope::ObjectParams object_params = result.object_params;
  object_params.max_height = config.object_max_height;
  try {
    hope::validate(object_params);
    result.object_params = object_params;
  } catch (const std::exception& e) {
    problems.push_back("keeping object_max_height " + number(result.object_params.max_height) +
                       ": " + e.what());
  }
  result.objects = config.objects;
  // The slider ranges lie within what the pipeline accepts ([0, 1] and (1, 100] m).
  result.obstacle_min_height = config.obstacle_min_height;
  result.obstacle_max_height = config.obstacle_max_height;
  result.grid_resolution = config.grid_resolution;
  return result;
}

void writeConfig(const hope::PipelineOptions& options, hope::HopeConfig& config) {
  const hope::Params& p = options.extraction;
  config.r_xy = p.r_xy;
  config.r_z = p.r_z;
  config.min_height = std::max(p.min_height, -1000.0);
  config.max_height = std::min(p.max_height, 1000.0);
  config.min_area = p.min_area;
  config.merge_fragments = p.merge_fragments;
  config.max_merge_gap = p.max_merge_gap;
  config.bridge_scan_gaps = p.bridge_scan_gaps;
  config.threads = p.threads;
  config.tracking_mode = hope::toString(options.identity);
  config.object_max_height = options.object_params.max_height;
  config.objects = options.objects;
  config.obstacle_min_height = options.obstacle_min_height;
  config.obstacle_max_height = options.obstacle_max_height;
  config.grid_resolution = options.grid_resolution;
}

std::string describe(const hope::PipelineOptions& options) {
  const hope::Params& p = options.extraction;
  char text[512];
  std::snprintf(text, sizeof(text),
                "r_xy %.3f, r_z %.3f, height band [%g, %g], min_area %g, fragment merge %s (gap "
                "<= %g m), scan-gap bridging %s, tracking %s, %d thread(s), objects %s (up to "
                "%g m), obstacles %g-%g m above the floor, grid cells %g m",
                p.r_xy, p.r_z, p.min_height, p.max_height, p.min_area,
                p.merge_fragments ? "on" : "off", p.max_merge_gap,
                p.bridge_scan_gaps ? "on" : "off", hope::toString(options.identity), p.threads,
                options.objects ? "on" : "off", options.object_params.max_height,
                options.obstacle_min_height, options.obstacle_max_height, options.grid_resolution);
  return text;
}

}  // namespace hope_ros
