// The hope nodelet's parameters: those fixed at start-up, read from the parameter server and
// checked here (a bad value is said and replaced by its default, never taken), and the
// live-tunable ones of dynamic_reconfigure (cfg/Hope.cfg) turned into the core pipeline's
// options (frame_pipeline.h) and back.
#pragma once

#include <string>
#include <vector>

#include <ros/node_handle.h>

#include "hope/HopeConfig.h"
#include "hope/frame_pipeline.h"
#include "hope/gravity_alignment.h"

namespace hope_ros {

// tf2 frame ids have no leading slash; ROS 1 bags recorded with tf1 (the TUM bags) do.
std::string frameId(const std::string& frame);

// A frame of this nodelet's own: "<node name>_<suffix>" with the namespace's slashes as
// underscores: /hope → hope_gravity, hope_view; /camera/hope → camera_hope_gravity.
std::string ownFrame(const std::string& node_name, const char* suffix);

struct StartupSettings {
  std::string source = "imu";   // orientation_source: imu, tf, fixed, scene or none
  std::string reference_frame;  // output frame (tf: looked up; imu/fixed/scene: broadcast)
  bool refine = false;          // refine_orientation: the source's orientation corrected
  std::string view_frame;       // empty: not broadcast
  // tracking_mode odometry: the odometry's world, broadcast as a child of the reference frame.
  std::string odometry_frame;
  bool lazy = true;
  int tf_queue = 5;
  int cloud_queue = 3;
  hope::Orientation fixed = hope::Orientation::identity();
  // The pipeline's start-up part: levelling, its smoothing and hold, the gravity window.
  hope::PipelineOptions pipeline;
  // surface_map (the old name of tracking_mode map) was asked for.
  bool surface_map = false;
  // What tracking_mode auto resolves with: poses in a fixed frame for orientation_source tf
  // into a frame REP 105 names fixed in the world (map, odom, world, earth), else an
  // orientation alone (hope cannot tell whether another frame moves with the robot).
  hope::PoseInput pose_input = hope::PoseInput::kOrientation;
  // With tf into another frame and tracking_mode auto: what auto took and why, for the log.
  std::string auto_tracking;
};

// Reads and checks the start-up parameters of the nodelet `node_name` from `pnh`. Each problem
// (a value out of range, a source that cannot work) is appended to `problems`, with what is
// used instead; `notes` get the parameters that are no longer used.
StartupSettings loadStartupSettings(ros::NodeHandle& pnh, const std::string& node_name,
                                    std::vector<std::string>& problems,
                                    std::vector<std::string>& notes);

// The live-tunable part of `config` over `options` (start-up parts kept). Each part is checked
// on its own: a bad value keeps the previous one of its part and appends a problem. `map_allowed`:
// tracking_mode map needs tf and a fixed reference frame (odometry needs neither: it keeps the
// map in a world of its own, ~odometry_frame). tracking_mode auto is resolved with `input`.
hope::PipelineOptions withConfig(const hope::PipelineOptions& options,
                                 const hope::HopeConfig& config, bool map_allowed,
                                 hope::PoseInput input, std::vector<std::string>& problems);
// What is in effect, written back into `config` so that the parameter server and the reported
// config never show a value that was refused.
void writeConfig(const hope::PipelineOptions& options, hope::HopeConfig& config);
// One line naming every live-tunable value in effect, for the log.
std::string describe(const hope::PipelineOptions& options);

}  // namespace hope_ros
