// The hope nodelet: a thin adapter between ROS topics and the ROS-free core. Point cloud (and
// IMU or tf) in; PlaneArray, labeled cloud and RViz markers out, in the reference frame.
#include <atomic>
#include <chrono>
#include <deque>
#include <memory>
#include <mutex>
#include <optional>

#include <diagnostic_updater/diagnostic_updater.h>
#include <dynamic_reconfigure/server.h>
#include <message_filters/subscriber.h>
#include <message_filters/sync_policies/approximate_time.h>
#include <message_filters/synchronizer.h>
#include <nodelet/nodelet.h>
#include <ros/ros.h>
#include <sensor_msgs/Imu.h>
#include <sensor_msgs/PointCloud2.h>
#include <tf2_eigen/tf2_eigen.h>
#include <tf2_msgs/TFMessage.h>
#include <tf2_ros/buffer.h>
#include <tf2_ros/message_filter.h>
#include <tf2_ros/transform_broadcaster.h>
#include <tf2_ros/transform_listener.h>
#include <visualization_msgs/MarkerArray.h>
#include <boost/thread/recursive_mutex.hpp>
#include <pluginlib/class_list_macros.hpp>

#include "hope/FindPlacement.h"
#include "hope/HopeConfig.h"
#include "hope/ObjectArray.h"
#include "hope/PlaneArray.h"
#include "hope/ResetMap.h"
#include "hope/extractor.h"
#include "hope/plane_tracker.h"
#include "hope/surface_map.h"
#include "hope/up_estimation.h"
#include "hope_ros/cloud_conversion.h"
#include "hope_ros/frame_gaps.h"
#include "hope_ros/object_conversion.h"

namespace hope_ros {

// tf2 frame ids have no leading slash; ROS 1 bags recorded with tf1 (the TUM bags) do.
std::string frameId(const std::string& frame) {
  return !frame.empty() && frame[0] == '/' ? frame.substr(1) : frame;
}

// A frame of this nodelet's own: "<node name>_<suffix>" with the namespace's slashes as
// underscores: /hope → hope_gravity, hope_view; /camera/hope → camera_hope_gravity.
std::string ownFrame(const std::string& node_name, const char* suffix) {
  std::string frame = frameId(node_name);
  for (char& c : frame) c = c == '/' ? '_' : c;
  return (frame.empty() ? std::string("hope") : frame) + "_" + suffix;
}

using CloudImuPolicy =
    message_filters::sync_policies::ApproximateTime<sensor_msgs::PointCloud2, sensor_msgs::Imu>;

class PlaneExtractorNodelet : public nodelet::Nodelet {
 private:
  void onInit() override;
  void connectionChanged();
  void onCloud(const sensor_msgs::PointCloud2ConstPtr& cloud);
  void onCloudAndImu(const sensor_msgs::PointCloud2ConstPtr& cloud,
                     const sensor_msgs::ImuConstPtr& imu);
  // `orientation` as the source gives it; levelled from the scene here (scene) or refined by it
  // (refine_orientation), and broadcast as reference_frame_ when `broadcast`.
  void process(const sensor_msgs::PointCloud2ConstPtr& cloud, hope::Orientation orientation,
               const std::string& reference_frame, bool broadcast);
  // Up from the scene (scene), or the given orientation refined by it; false when the frame
  // is to be skipped (nothing level in view and no earlier up to hold).
  bool levelFromScene(const hope::PointsView& view, hope::Orientation& orientation);
  hope::Orientation orientationFromImu(const sensor_msgs::Imu& imu, const std::string& cloud_frame);
  // Publishes the gravity-aligned reference frame as a child of the cloud's frame (a frame
  // has one parent in tf; the cloud's frame usually has its own already).
  void broadcastReference(const std_msgs::Header& cloud_header,
                          const hope::Orientation& orientation);
  // Broadcasts view_frame_ (level, under the reference frame) at the middle of what the planes
  // cover, eased from frame to frame: rviz/hope.rviz orbits it, so RViz frames any scene.
  void broadcastView(const hope::Result& result, const std_msgs::Header& header);
  // Counts sequence gaps (frames dropped before they reached hope) and notices time jumping
  // back (a looping bag): then the plane tracks and the gravity average start afresh.
  void noteArrival(const sensor_msgs::PointCloud2& cloud);
  // tf: a cloud the message filter could not transform in time.
  void onCloudWithoutTransform(const sensor_msgs::PointCloud2ConstPtr& cloud,
                               tf2_ros::FilterFailureReason reason);
  // Warns when another publisher puts our reference frame under another parent.
  void onTf(const ros::MessageEvent<tf2_msgs::TFMessage const>& event);
  void reject(const std::string& problem);
  // ~find_placement: searches the last frame processed; a refusal comes back with success
  // false and the reason, never as a failed call (a client would see no reason then).
  bool findPlacement(hope::FindPlacement::Request& request,
                     hope::FindPlacement::Response& response);
  // ~reset_map: forgets the surface map's entries and publishes the empty map.
  bool resetMap(hope::ResetMap::Request& request, hope::ResetMap::Response& response);
  // The map's entries on the latched ~map and ~map_markers.
  void publishMap(const std_msgs::Header& header);
  void reconfigure(hope::HopeConfig& config, uint32_t level);
  void diagnose(diagnostic_updater::DiagnosticStatusWrapper& status);

  // Parameters fixed at start-up.
  std::string source_;           // imu, tf, fixed, scene or none
  std::string reference_frame_;  // output frame (tf: looked up; imu/fixed: broadcast)
  bool lazy_ = true;
  std::string view_frame_;  // empty: not broadcast
  std::optional<Eigen::Vector3d> view_centre_;
  int gravity_window_ = 10;
  hope::Orientation fixed_ = hope::Orientation::identity();
  bool refine_ = false;  // refine_orientation: the source's orientation corrected by the scene
  hope::LevellingParams levelling_;
  // How many frames a scene source may hold the last up when a frame shows nothing level.
  int level_hold_frames_ = 30;

  ros::Publisher planes_pub_, cloud_pub_, markers_pub_, objects_pub_;
  ros::ServiceServer placement_srv_;
  // surface_map: with tf and a fixed reference frame, ids come from a map of the surfaces
  // (surface_map.h) instead of the tracker; the map is latched on ~map when it changes (an
  // entry added, merged or removed) and at most once a second as extents grow.
  bool use_map_ = false;
  std::unique_ptr<hope::SurfaceMap> surface_map_;
  ros::Publisher map_pub_, map_markers_pub_;
  ros::ServiceServer reset_map_srv_;
  ros::WallTime last_map_publish_;
  ros::Subscriber cloud_sub_;
  // tf: clouds wait in a bounded queue until their transform is there; the callback thread
  // never blocks in a lookup (a paused /clock would hold it forever).
  std::unique_ptr<message_filters::Subscriber<sensor_msgs::PointCloud2>> tf_cloud_sub_;
  std::unique_ptr<tf2_ros::MessageFilter<sensor_msgs::PointCloud2>> tf_filter_;
  int tf_queue_ = 5;
  // Clouds that may wait while one is processed (the subscriber's queue); beyond it the
  // oldest is dropped and counted. Three ride out a stall of two frames (another process
  // holding the CPU) and add no latency while hope keeps up.
  int cloud_queue_ = 3;
  ros::Subscriber tf_watch_sub_;
  std::string broadcast_parent_;  // the frame our reference frame hangs from
  ros::Time last_stamp_;
  std::unique_ptr<message_filters::Subscriber<sensor_msgs::PointCloud2>> sync_cloud_sub_;
  std::unique_ptr<message_filters::Subscriber<sensor_msgs::Imu>> sync_imu_sub_;
  std::unique_ptr<message_filters::Synchronizer<CloudImuPolicy>> sync_;
  std::mutex connection_mutex_;
  std::atomic<bool> subscribed_{false};  // read by the diagnostics without the mutex
  std::string cloud_topic_;              // resolved, for messages

  std::unique_ptr<tf2_ros::Buffer> tf_buffer_;
  std::unique_ptr<tf2_ros::TransformListener> tf_listener_;
  std::unique_ptr<tf2_ros::TransformBroadcaster> tf_broadcaster_;

  // Live-tunable state: dynamic_reconfigure writes pending_*, the processing thread swaps them
  // in at the start of the next frame, so a frame never sees half a change.
  boost::recursive_mutex reconfigure_mutex_;
  std::unique_ptr<dynamic_reconfigure::Server<hope::HopeConfig>> reconfigure_server_;
  std::mutex pending_mutex_;
  hope::Params pending_params_;
  hope::TrackerOptions pending_tracker_;
  bool pending_objects_ = true, pending_placements_ = true;
  hope::ObjectParams pending_object_params_;
  bool pending_ = false;

  std::mutex processing_mutex_;  // one frame at a time
  std::unique_ptr<hope::Extractor> extractor_;
  std::unique_ptr<hope::PlaneTracker> tracker_;
  std::deque<Eigen::Vector3d> recent_gravity_;
  std::unique_ptr<hope::UpEstimator> up_estimator_;
  // scene: up in the sensor frame; refinement: the scene's up in the given reference frame.
  hope::UpSmoother up_smoother_;
  int frames_since_level_ = 0;
  boost::shared_ptr<sensor_msgs::PointCloud2> labeled_cloud_;  // the last one published
  // What stands on the planes (~objects, boxes in ~markers, the labeled cloud's object field)
  // and ~find_placement, switched by dynamic_reconfigure like the extraction parameters.
  bool objects_ = true, placements_ = true;
  hope::ObjectParams object_params_;
  // The last frame processed, for ~find_placement: its result (with point labels) and the cloud
  // it came from, which the extractor's aligned points may still read (no copy is made when the
  // orientation is the identity). Cleared when the extractor is replaced.
  sensor_msgs::PointCloud2ConstPtr last_cloud_;
  hope::Result last_result_;
  std_msgs::Header last_header_;

  // Diagnostics.
  std::unique_ptr<diagnostic_updater::Updater> diagnostics_;
  std::mutex stats_mutex_;
  std::size_t frames_ = 0, rejected_ = 0, rejected_since_update_ = 0;
  std::size_t time_jumps_ = 0;
  double last_ms_ = 0, max_ms_ = 0, sum_ms_ = 0;
  hope_ros::FrameGapCounter gaps_;  // frames that never reached hope
  // Up from the scene: frames levelled, refused (held on the last up, or skipped), the last
  // estimate, and for a refinement the frames left uncorrected and the last correction.
  std::size_t levelled_ = 0, level_held_ = 0, level_skipped_ = 0, uncorrected_ = 0;
  std::string last_levelling_, last_level_problem_;
  // up_smoother_'s running up as the diagnostics thread reads it (the smoother itself belongs to
  // the processing thread).
  std::optional<Eigen::Vector3d> smoothed_up_;
  std::string last_problem_;
  ros::WallTimer diagnostics_timer_;
};

void PlaneExtractorNodelet::onInit() {
  ros::NodeHandle& nh = getNodeHandle();
  ros::NodeHandle& pnh = getPrivateNodeHandle();
  pnh.param<std::string>("orientation_source", source_, "imu");
  pnh.param<std::string>("reference_frame", reference_frame_, "");
  reference_frame_ = frameId(reference_frame_);
  if (pnh.hasParam("tf_timeout")) {
    NODELET_WARN(
        "hope: ~tf_timeout is no longer used: clouds wait for their transform in a "
        "queue of ~tf_queue clouds, without blocking");
  }
  pnh.param("tf_queue", tf_queue_, 5);
  tf_queue_ = std::max(1, std::min(tf_queue_, 100));
  pnh.param("cloud_queue", cloud_queue_, 3);
  cloud_queue_ = std::max(1, std::min(cloud_queue_, 100));
  pnh.param("lazy", lazy_, true);
  pnh.param<std::string>("view_frame", view_frame_, "");
  view_frame_ = view_frame_.empty()     ? ownFrame(getName(), "view")
                : view_frame_ == "none" ? std::string()
                                        : frameId(view_frame_);
  pnh.param("gravity_window", gravity_window_, 10);
  if (source_ != "imu" && source_ != "tf" && source_ != "fixed" && source_ != "scene" &&
      source_ != "none") {
    NODELET_ERROR("orientation_source '%s' is not one of imu, tf, fixed, scene, none; using none",
                  source_.c_str());
    source_ = "none";
  }
  pnh.param("refine_orientation", refine_, false);
  double smoothing = 0.3;
  pnh.param("level_bound", levelling_.max_correction_deg, levelling_.max_correction_deg);
  pnh.param("level_smoothing", smoothing, smoothing);
  pnh.param("level_hold_frames", level_hold_frames_, level_hold_frames_);
  try {
    hope::validate(levelling_);
  } catch (const std::exception& e) {
    NODELET_ERROR("hope: ~level_bound: %s; using %g", e.what(),
                  hope::LevellingParams().max_correction_deg);
    levelling_.max_correction_deg = hope::LevellingParams().max_correction_deg;
  }
  if (!(smoothing > 0 && smoothing <= 1)) {
    NODELET_ERROR("hope: ~level_smoothing must be in (0, 1] (got %g); using 0.3", smoothing);
    smoothing = 0.3;
  }
  up_smoother_ = hope::UpSmoother(smoothing);
  if (refine_ && (source_ == "scene" || source_ == "none")) {
    NODELET_WARN("hope: ~refine_orientation applies to imu, tf and fixed; ignored with %s",
                 source_.c_str());
    refine_ = false;
  }
  pnh.param("surface_map", use_map_, false);
  if (use_map_ && source_ != "tf") {
    NODELET_ERROR(
        "hope: ~surface_map needs orientation_source tf and a fixed ~reference_frame (odom, map): "
        "with %s the planes' frame moves with the sensor; using the tracker",
        source_.c_str());
    use_map_ = false;
  }
  if (source_ == "tf" && reference_frame_.empty()) {
    NODELET_ERROR(
        "orientation_source tf needs ~reference_frame (e.g. base_link or odom); "
        "using none");
    source_ = "none";
  }
  if ((source_ == "imu" || source_ == "fixed" || source_ == "scene") && reference_frame_.empty()) {
    // Broadcast: z up, origin at the sensor. Named after this nodelet, so two hope nodelets
    // never broadcast one frame under two parents ("hope" → hope_gravity).
    reference_frame_ = ownFrame(getName(), "gravity");
  }
  if (source_ == "fixed") {
    std::vector<double> q, rpy;
    try {
      if (pnh.getParam("fixed_quaternion", q) && q.size() == 4) {
        fixed_ = hope::Orientation::fromQuaternion(q[0], q[1], q[2], q[3]);
      } else if (pnh.getParam("fixed_rpy", rpy) && rpy.size() == 3) {
        fixed_ = hope::Orientation::fromRollPitchYaw(rpy[0], rpy[1], rpy[2]);
      } else {
        NODELET_ERROR(
            "orientation_source fixed needs ~fixed_quaternion [x, y, z, w] or "
            "~fixed_rpy [roll, pitch, yaw]; using identity");
      }
    } catch (const std::exception& e) {
      NODELET_ERROR("bad fixed orientation: %s; using identity", e.what());
    }
  }

  // The extraction parameters (r_xy, r_z, height band, min_area, tracking_mode) come through
  // dynamic_reconfigure, which reads them from the parameter server at start-up and calls
  // reconfigure() before the first frame.
  extractor_ = std::make_unique<hope::Extractor>();
  tracker_ = std::make_unique<hope::PlaneTracker>();
  surface_map_ = std::make_unique<hope::SurfaceMap>();

  tf_buffer_ = std::make_unique<tf2_ros::Buffer>();
  tf_listener_ = std::make_unique<tf2_ros::TransformListener>(*tf_buffer_, nh);
  tf_broadcaster_ = std::make_unique<tf2_ros::TransformBroadcaster>();

  reconfigure_server_ =
      std::make_unique<dynamic_reconfigure::Server<hope::HopeConfig>>(reconfigure_mutex_, pnh);
  reconfigure_server_->setCallback(boost::bind(&PlaneExtractorNodelet::reconfigure, this,
                                               boost::placeholders::_1, boost::placeholders::_2));

  diagnostics_ = std::make_unique<diagnostic_updater::Updater>(nh, pnh, getName());
  diagnostics_->setHardwareID("none");
  diagnostics_->add("processing", this, &PlaneExtractorNodelet::diagnose);
  // On wall time, and forced: Updater::update() waits for ROS time to pass its next report,
  // which never comes once a looping bag sends sim time back.
  diagnostics_timer_ = nh.createWallTimer(
      ros::WallDuration(1.0), [this](const ros::WallTimerEvent&) { diagnostics_->force_update(); });
  if (source_ == "imu" || source_ == "fixed" || source_ == "scene") {
    tf_watch_sub_ = nh.subscribe("/tf", 100, &PlaneExtractorNodelet::onTf, this);
  }

  cloud_topic_ = pnh.resolveName("cloud");
  const ros::SubscriberStatusCallback changed =
      boost::bind(&PlaneExtractorNodelet::connectionChanged, this);
  {
    // Held while advertising: a listener connecting now waits until the publishers exist.
    std::lock_guard<std::mutex> lock(connection_mutex_);
    // Queues of 10 (3 for the ~6 MB labeled clouds): a subscriber in another process that
    // falls behind for a moment (rosbag record on a busy machine) loses no frame; a queue of
    // 1 lost 5 of 8 frames of a recording while the compiler kept both cores busy.
    planes_pub_ = pnh.advertise<hope::PlaneArray>("planes", 10, changed, changed);
    cloud_pub_ = pnh.advertise<sensor_msgs::PointCloud2>("labeled_cloud", 3, changed, changed);
    markers_pub_ = pnh.advertise<visualization_msgs::MarkerArray>("markers", 10, changed, changed);
    objects_pub_ = pnh.advertise<hope::ObjectArray>("objects", 10, changed, changed);
  }
  placement_srv_ =
      pnh.advertiseService("find_placement", &PlaneExtractorNodelet::findPlacement, this);
  if (use_map_) {
    map_pub_ = pnh.advertise<hope::PlaneArray>("map", 1, true);
    map_markers_pub_ = pnh.advertise<visualization_msgs::MarkerArray>("map_markers", 1, true);
    reset_map_srv_ = pnh.advertiseService("reset_map", &PlaneExtractorNodelet::resetMap, this);
  }
  NODELET_INFO("hope: orientation from %s%s, reference frame '%s', %s", source_.c_str(),
               refine_ ? " refined by the scene" : "", reference_frame_.c_str(),
               lazy_ ? "lazy: subscribing to the cloud only while an output has a listener "
                       "(lazy: false processes every cloud)"
                     : "always subscribed");
  if (!lazy_) connectionChanged();
}

void PlaneExtractorNodelet::connectionChanged() {
  std::lock_guard<std::mutex> lock(connection_mutex_);
  const bool wanted = !lazy_ || planes_pub_.getNumSubscribers() > 0 ||
                      cloud_pub_.getNumSubscribers() > 0 || markers_pub_.getNumSubscribers() > 0 ||
                      objects_pub_.getNumSubscribers() > 0;
  if (wanted == subscribed_) return;
  ros::NodeHandle& pnh = getPrivateNodeHandle();
  if (wanted) {
    if (source_ == "imu") {
      sync_cloud_sub_ = std::make_unique<message_filters::Subscriber<sensor_msgs::PointCloud2>>(
          pnh, "cloud", cloud_queue_);
      sync_imu_sub_ =
          std::make_unique<message_filters::Subscriber<sensor_msgs::Imu>>(pnh, "imu", 50);
      sync_ = std::make_unique<message_filters::Synchronizer<CloudImuPolicy>>(
          CloudImuPolicy(10), *sync_cloud_sub_, *sync_imu_sub_);
      sync_->registerCallback(boost::bind(&PlaneExtractorNodelet::onCloudAndImu, this,
                                          boost::placeholders::_1, boost::placeholders::_2));
    } else if (source_ == "tf") {
      tf_cloud_sub_ = std::make_unique<message_filters::Subscriber<sensor_msgs::PointCloud2>>(
          pnh, "cloud", cloud_queue_);
      tf_filter_ = std::make_unique<tf2_ros::MessageFilter<sensor_msgs::PointCloud2>>(
          *tf_cloud_sub_, *tf_buffer_, reference_frame_, tf_queue_, pnh);
      tf_filter_->registerCallback(
          boost::bind(&PlaneExtractorNodelet::onCloud, this, boost::placeholders::_1));
      tf_filter_->registerFailureCallback(
          boost::bind(&PlaneExtractorNodelet::onCloudWithoutTransform, this,
                      boost::placeholders::_1, boost::placeholders::_2));
    } else {
      cloud_sub_ = pnh.subscribe("cloud", cloud_queue_, &PlaneExtractorNodelet::onCloud, this);
    }
  } else {
    tf_filter_.reset();
    tf_cloud_sub_.reset();
    sync_.reset();
    sync_cloud_sub_.reset();
    sync_imu_sub_.reset();
    cloud_sub_.shutdown();
    std::lock_guard<std::mutex> stats_lock(stats_mutex_);
    gaps_.restart();  // a pause is not a drop
  }
  subscribed_ = wanted;
  NODELET_INFO("hope: %s %s", wanted ? "subscribed to" : "unsubscribed from (no listener left)",
               cloud_topic_.c_str());
}

void PlaneExtractorNodelet::noteArrival(const sensor_msgs::PointCloud2& cloud) {
  {
    std::lock_guard<std::mutex> lock(stats_mutex_);
    gaps_.arrive(cloud.header.seq, cloud.header.stamp.toSec());
  }
  // A cloud older than the last one: a bag started over (or a clock was reset); one topic's
  // stamps never go back otherwise. Tracks and the gravity average belong to another time
  // (tf2's listener clears its own buffer); new ids continue from the last one.
  const ros::Time stamp = cloud.header.stamp;
  if (!last_stamp_.isZero() && stamp < last_stamp_) {
    NODELET_WARN_THROTTLE(10.0,
                          "hope: time went back %.2f s (a looping bag?): plane tracks and "
                          "gravity start afresh",
                          (last_stamp_ - stamp).toSec());
    std::lock_guard<std::mutex> lock(processing_mutex_);
    tracker_->reset();
    // The surface map stays: it holds places, not times (a looping bag replays the same room).
    view_centre_.reset();
    recent_gravity_.clear();
    up_smoother_.reset();
    std::lock_guard<std::mutex> stats_lock(stats_mutex_);
    smoothed_up_.reset();
    gaps_.restart();
    ++time_jumps_;
  }
  last_stamp_ = stamp;
}

void PlaneExtractorNodelet::onCloudWithoutTransform(const sensor_msgs::PointCloud2ConstPtr& cloud,
                                                    tf2_ros::FilterFailureReason reason) {
  const char* why = reason == tf2_ros::filter_failure_reasons::OutTheBack
                        ? "older than the tf buffer"
                    : reason == tf2_ros::filter_failure_reasons::EmptyFrameID
                        ? "an empty frame_id"
                        : "no transform before the queue overflowed";
  reject(std::string("no transform: ") + why);
  NODELET_WARN_THROTTLE(5.0, "hope: skipping a cloud: no transform from '%s' to '%s' at %.3f: %s",
                        frameId(cloud->header.frame_id).c_str(), reference_frame_.c_str(),
                        cloud->header.stamp.toSec(), why);
}

void PlaneExtractorNodelet::onTf(const ros::MessageEvent<tf2_msgs::TFMessage const>& event) {
  std::string parent;
  {
    std::lock_guard<std::mutex> lock(stats_mutex_);
    parent = broadcast_parent_;
  }
  if (parent.empty()) return;
  for (const auto& t : event.getMessage()->transforms) {
    if (frameId(t.child_frame_id) != reference_frame_ || frameId(t.header.frame_id) == parent) {
      continue;
    }
    NODELET_WARN_THROTTLE(10.0,
                          "hope: '%s' publishes our reference frame '%s' as a child of '%s'; "
                          "hope broadcasts it under '%s'. Give each hope nodelet its own "
                          "~reference_frame.",
                          event.getPublisherName().c_str(), reference_frame_.c_str(),
                          t.header.frame_id.c_str(), parent.c_str());
    std::lock_guard<std::mutex> lock(stats_mutex_);
    last_problem_ = "another node publishes '" + reference_frame_ + "' under '" +
                    frameId(t.header.frame_id) + "'";
  }
}

void PlaneExtractorNodelet::reject(const std::string& problem) {
  std::lock_guard<std::mutex> lock(stats_mutex_);
  ++rejected_;
  ++rejected_since_update_;
  last_problem_ = problem;
}

void PlaneExtractorNodelet::broadcastReference(const std_msgs::Header& cloud_header,
                                               const hope::Orientation& orientation) {
  geometry_msgs::TransformStamped t =
      tf2::eigenToTransform(orientation.sensorToReference().inverse());
  t.header.stamp = cloud_header.stamp;
  t.header.frame_id = frameId(cloud_header.frame_id);
  t.child_frame_id = reference_frame_;
  {
    std::lock_guard<std::mutex> lock(stats_mutex_);
    broadcast_parent_ = t.header.frame_id;
  }
  tf_broadcaster_->sendTransform(t);
}

void PlaneExtractorNodelet::broadcastView(const hope::Result& result,
                                          const std_msgs::Header& header) {
  const std::optional<Eigen::Vector3d> centre = sceneCentre(result.planes);
  if (!centre) return;  // nothing to look at: the view stays where it was
  // A fifth of the way per frame: the view follows a panning camera without shaking.
  view_centre_ =
      view_centre_ ? Eigen::Vector3d(*view_centre_ + 0.2 * (*centre - *view_centre_)) : *centre;
  geometry_msgs::TransformStamped t;
  t.header.stamp = header.stamp;
  t.header.frame_id = header.frame_id;
  t.child_frame_id = view_frame_;
  t.transform.translation.x = view_centre_->x();
  t.transform.translation.y = view_centre_->y();
  t.transform.translation.z = view_centre_->z();
  t.transform.rotation.w = 1.0;
  tf_broadcaster_->sendTransform(t);
}

void PlaneExtractorNodelet::onCloud(const sensor_msgs::PointCloud2ConstPtr& cloud) {
  noteArrival(*cloud);
  const std::string cloud_frame = frameId(cloud->header.frame_id);
  if (source_ == "none") {
    // A cloud already z-up in its own frame: the sensor is at that frame's origin.
    process(cloud, hope::Orientation::identity().withViewpoint(Eigen::Vector3d::Zero()),
            cloud_frame, false);
    return;
  }
  if (source_ == "fixed" || source_ == "scene") {
    // scene: process() finds up in the cloud itself; the sensor is at its frame's origin.
    process(cloud,
            source_ == "fixed"
                ? fixed_
                : hope::Orientation::identity().withViewpoint(Eigen::Vector3d::Zero()),
            reference_frame_, true);
    return;
  }
  // tf: the cloud's frame in the reference frame at the cloud's stamp, translation included.
  // The message filter let the cloud through once that transform was there: no waiting.
  try {
    const geometry_msgs::TransformStamped t =
        tf_buffer_->lookupTransform(reference_frame_, cloud_frame, cloud->header.stamp);
    process(cloud, hope::Orientation::fromTransform(tf2::transformToEigen(t)), reference_frame_,
            false);
  } catch (const std::exception& e) {
    reject(std::string("no transform: ") + e.what());
    NODELET_WARN_THROTTLE(
        5.0, "hope: skipping a cloud: no transform from '%s' to '%s' at %.3f (%s)",
        cloud_frame.c_str(), reference_frame_.c_str(), cloud->header.stamp.toSec(), e.what());
  }
}

hope::Orientation PlaneExtractorNodelet::orientationFromImu(const sensor_msgs::Imu& imu,
                                                            const std::string& cloud_frame) {
  // The fixed rotation from the cloud's frame into the IMU's frame (identity when they agree).
  Eigen::Matrix3d imu_from_cloud = Eigen::Matrix3d::Identity();
  const std::string imu_frame =
      imu.header.frame_id.empty() ? cloud_frame : frameId(imu.header.frame_id);
  if (imu_frame != cloud_frame) {
    // The latest mounting transform, without waiting (the callback thread must not block).
    const geometry_msgs::TransformStamped t =
        tf_buffer_->lookupTransform(imu_frame, cloud_frame, ros::Time(0));
    imu_from_cloud = tf2::transformToEigen(t).rotation();
  }
  const auto& q = imu.orientation;
  const bool has_orientation = imu.orientation_covariance[0] != -1.0;
  if (has_orientation) {
    const hope::Orientation world_from_imu = hope::Orientation::fromQuaternion(q.x, q.y, q.z, q.w);
    Eigen::Isometry3d world_from_cloud = Eigen::Isometry3d::Identity();
    world_from_cloud.linear() = world_from_imu.sensorToReference().rotation() * imu_from_cloud;
    return hope::Orientation::fromTransform(world_from_cloud);
  }
  // Gravity only: the specific force points up at rest; average recent samples so that the
  // camera's own accelerations do not tilt the reference frame from frame to frame.
  const Eigen::Vector3d a(imu.linear_acceleration.x, imu.linear_acceleration.y,
                          imu.linear_acceleration.z);
  if (!a.allFinite() || a.norm() < 1.0 || a.norm() > 30.0) {
    throw std::invalid_argument("IMU linear_acceleration (" + std::to_string(a.norm()) +
                                " m/s²) is not gravity; is it in m/s²?");
  }
  recent_gravity_.push_back(imu_from_cloud.transpose() * a);
  while (static_cast<int>(recent_gravity_.size()) > std::max(gravity_window_, 1)) {
    recent_gravity_.pop_front();
  }
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (const auto& g : recent_gravity_) mean += g;
  return hope::Orientation::fromGravity(mean.x(), mean.y(), mean.z());
}

void PlaneExtractorNodelet::onCloudAndImu(const sensor_msgs::PointCloud2ConstPtr& cloud,
                                          const sensor_msgs::ImuConstPtr& imu) {
  noteArrival(*cloud);
  hope::Orientation orientation = hope::Orientation::identity();
  try {
    std::lock_guard<std::mutex> lock(processing_mutex_);  // recent_gravity_
    orientation = orientationFromImu(*imu, frameId(cloud->header.frame_id));
  } catch (const std::exception& e) {
    reject(std::string("bad IMU message: ") + e.what());
    NODELET_WARN_THROTTLE(5.0, "hope: skipping a cloud: bad IMU message: %s", e.what());
    return;
  }
  // The gravity-aligned frame is broadcast so that RViz can show the outputs with the camera.
  process(cloud, orientation, reference_frame_, true);
}

bool PlaneExtractorNodelet::levelFromScene(const hope::PointsView& view,
                                           hope::Orientation& orientation) {
  const double cell = hope::LevellingParams::forExtraction(extractor_->params()).cell;
  if (!up_estimator_ || up_estimator_->params().cell != cell) {
    levelling_.cell = cell;  // follows r_xy as dynamic_reconfigure changes it
    up_estimator_ = std::make_unique<hope::UpEstimator>(levelling_);
  }
  if (source_ == "scene") {
    try {
      const hope::UpEstimate e = up_estimator_->estimate(view);
      const Eigen::Vector3d& up = up_smoother_.add(e.up_in_sensor);
      orientation = hope::levelledTo(orientation, up);
      frames_since_level_ = 0;
      std::lock_guard<std::mutex> stats_lock(stats_mutex_);
      ++levelled_;
      last_levelling_ = e.describe();
      smoothed_up_ = up;
      return true;
    } catch (const hope::LevellingError& error) {
      // A view with nothing level (the camera facing a wall): the last up holds for a while,
      // since a sensor rarely turns much between two frames; after that, frames are skipped.
      const bool hold = !up_smoother_.empty() && ++frames_since_level_ <= level_hold_frames_;
      {
        std::lock_guard<std::mutex> stats_lock(stats_mutex_);
        ++(hold ? level_held_ : level_skipped_);
        last_level_problem_ = error.what();
      }
      NODELET_WARN_THROTTLE(10.0, "hope: %s: %s", error.what(),
                            hold ? "keeping the last up" : "skipping the frame");
      if (!hold) return false;
      orientation = hope::levelledTo(orientation, up_smoother_.value());
      return true;
    }
  }
  // Refinement: the scene's up in the given reference frame (near +z) is what is smoothed, so
  // that a moving robot's orientation keeps coming from its source.
  const hope::UpEstimate e = up_estimator_->refine(view, orientation);
  const Eigen::Matrix3d& rotation = orientation.sensorToReference().linear();
  std::lock_guard<std::mutex> stats_lock(stats_mutex_);
  last_levelling_ = e.describe();
  if (!e.applied) {
    ++uncorrected_;
    if (up_smoother_.empty()) return true;
  } else {
    smoothed_up_ = up_smoother_.add(rotation * e.up_in_sensor);
    ++levelled_;
  }
  orientation = hope::levelledTo(orientation, rotation.transpose() * up_smoother_.value());
  return true;
}

void PlaneExtractorNodelet::process(const sensor_msgs::PointCloud2ConstPtr& cloud,
                                    hope::Orientation orientation,
                                    const std::string& reference_frame, bool broadcast) {
  std::lock_guard<std::mutex> lock(processing_mutex_);
  {
    std::lock_guard<std::mutex> pending_lock(pending_mutex_);
    if (pending_) {  // swap in the new parameters between frames
      extractor_ = std::make_unique<hope::Extractor>(pending_params_);
      if (pending_tracker_.mode != tracker_->options().mode) {
        tracker_ = std::make_unique<hope::PlaneTracker>(pending_tracker_);
      }
      // The map's cells are r_xy and its extension gate r_z: other values start it afresh
      // (ids go on, never given twice).
      const hope::SurfaceMapOptions map_options = hope::surfaceMapOptionsFor(pending_params_);
      if (map_options.cell != surface_map_->options().cell ||
          map_options.max_extension_height_change !=
              surface_map_->options().max_extension_height_change) {
        if (surface_map_->size() > 0) {
          NODELET_WARN(
              "hope: surface map restarted: its cells follow r_xy (%g -> %g m) and r_z; "
              "%zu surfaces forgotten",
              surface_map_->options().cell, map_options.cell, surface_map_->size());
        }
        surface_map_->reset(map_options);
      }
      objects_ = pending_objects_;
      placements_ = pending_placements_;
      object_params_ = pending_object_params_;
      last_cloud_.reset();  // the new extractor holds no frame to place on
      last_result_ = hope::Result();
      pending_ = false;
    }
  }
  const auto start = std::chrono::steady_clock::now();
  hope::PointsView view;
  const std::string problem = viewOf(*cloud, view);
  if (!problem.empty()) {
    reject(problem);
    NODELET_WARN_THROTTLE(5.0, "hope: skipping a cloud from '%s': %s",
                          cloud->header.frame_id.c_str(), problem.c_str());
    return;
  }
  if (source_ == "scene" || refine_) {
    try {
      if (!levelFromScene(view, orientation)) {
        reject("nothing level in view to find up from: " + last_level_problem_);
        return;
      }
    } catch (const std::exception& e) {
      reject(e.what());
      NODELET_WARN_THROTTLE(5.0, "hope: skipping a cloud from '%s': %s",
                            cloud->header.frame_id.c_str(), e.what());
      return;
    }
  }
  if (broadcast) broadcastReference(cloud->header, orientation);
  // Per-point labels feed the labeled cloud and ~find_placement, objects the labeled cloud,
  // ~objects and ~markers: each is left out while nothing needs it.
  const bool publish_cloud = cloud_pub_.getNumSubscribers() > 0;
  const bool publish_markers = markers_pub_.getNumSubscribers() > 0;
  const bool publish_objects = objects_ && objects_pub_.getNumSubscribers() > 0;
  hope::ExtractOutputs outputs;
  outputs.point_labels = publish_cloud || placements_;
  outputs.objects = objects_ && (publish_objects || publish_markers || publish_cloud);
  outputs.object_params = object_params_;
  hope::Result result;
  try {
    result = extractor_->extract(view, orientation, outputs);
  } catch (const std::exception& e) {
    reject(e.what());
    NODELET_WARN_THROTTLE(5.0, "hope: skipping a cloud from '%s': %s",
                          cloud->header.frame_id.c_str(), e.what());
    return;
  }
  for (const auto& w : result.warnings) NODELET_WARN_THROTTLE(30.0, "hope: %s", w.c_str());
  const std::vector<hope::TrackEvent> events =
      use_map_ ? surface_map_->update(result.planes, cloud->header.stamp.toSec(),
                                      orientation.viewpoint())
               : tracker_->update(result.planes, cloud->header.stamp.toSec());
  // The objects were found under the frame's own plane ids; the tracker has just given the
  // planes (in the same order) their persistent ones.
  for (hope::StandingObject& o : result.objects) o.plane_id = result.planes[o.plane_index].id;

  std_msgs::Header header = cloud->header;
  header.frame_id = reference_frame;
  if (planes_pub_.getNumSubscribers() > 0 || !lazy_) {
    planes_pub_.publish(boost::make_shared<hope::PlaneArray>(toMessage(result, header)));
  }
  if (publish_cloud) {
    // The message published last is refilled once nobody holds it (a subscriber's callback,
    // a queue waiting to serialize it): no 6 MB allocation and clearing per VGA frame.
    if (!labeled_cloud_ || labeled_cloud_.use_count() > 1) {
      labeled_cloud_ = boost::make_shared<sensor_msgs::PointCloud2>();
    }
    fillLabeledCloud(extractor_->alignedPoints(), result, view, header, *labeled_cloud_);
    cloud_pub_.publish(labeled_cloud_);
  }
  if (publish_objects) {
    objects_pub_.publish(boost::make_shared<hope::ObjectArray>(toMessage(result.objects, header)));
  }
  if (publish_markers) {
    auto markers =
        boost::make_shared<visualization_msgs::MarkerArray>(planeMarkers(result, header));
    appendObjectMarkers(result.objects, header, *markers);
    markers_pub_.publish(markers);
  }
  if (!view_frame_.empty()) broadcastView(result, header);
  if (use_map_ &&
      (!events.empty() || ros::WallTime::now() - last_map_publish_ > ros::WallDuration(1.0))) {
    publishMap(header);
  }
  if (placements_) {
    last_cloud_ = cloud;
    last_result_ = std::move(result);
    last_header_ = header;
  }
  const double ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  std::lock_guard<std::mutex> stats_lock(stats_mutex_);
  ++frames_;
  last_ms_ = ms;
  sum_ms_ += ms;
  max_ms_ = std::max(max_ms_, ms);
}

bool PlaneExtractorNodelet::findPlacement(hope::FindPlacement::Request& request,
                                          hope::FindPlacement::Response& response) {
  std::lock_guard<std::mutex> lock(processing_mutex_);  // the extractor and the last frame
  response.success = false;
  if (!placements_) {
    response.message = "placements are switched off (~placements false)";
    return true;
  }
  if (!last_cloud_) {
    response.message = std::string("no cloud processed yet") +
                       (lazy_ && !subscribed_ ? " (lazy: hope subscribes to " + cloud_topic_ +
                                                    " only while an output has a listener)"
                                              : " since the start or the last reconfiguration");
    return true;
  }
  response.header = last_header_;
  hope::PlacementQuery query;
  response.message = placementQuery(request, last_result_.planes, query);
  if (!response.message.empty()) return true;
  try {
    for (const hope::Placement& p : extractor_->findPlacements(last_result_, query)) {
      response.placements.push_back(toMessage(p));
    }
  } catch (const std::exception& e) {
    response.message = e.what();
    return true;
  }
  response.success = true;
  response.message = response.placements.empty()
                         ? "the footprint fits nowhere on the observed surface of " +
                               std::string(query.plane_index < 0 ? "any plane" : "that plane")
                         : "";
  return true;
}

void PlaneExtractorNodelet::publishMap(const std_msgs::Header& header) {
  hope::Result entries;
  entries.planes = surface_map_->surfaces();
  auto msg = boost::make_shared<hope::PlaneArray>(toMessage(entries, header));
  for (std::size_t k = 0; k < entries.planes.size(); ++k) {
    msg->planes[k].last_seen = ros::Time(std::max(0.0, entries.planes[k].last_seen));
  }
  map_pub_.publish(msg);
  visualization_msgs::MarkerArray markers = planeMarkers(entries, header);
  for (auto& m : markers.markers) m.ns = "map";
  map_markers_pub_.publish(markers);
  last_map_publish_ = ros::WallTime::now();
}

bool PlaneExtractorNodelet::resetMap(hope::ResetMap::Request& /*request*/,
                                     hope::ResetMap::Response& response) {
  std::lock_guard<std::mutex> lock(processing_mutex_);
  response.removed = static_cast<std::uint32_t>(surface_map_->size());
  surface_map_->reset();
  std_msgs::Header header;
  header.stamp = last_header_.stamp;
  header.frame_id = reference_frame_;
  publishMap(header);
  NODELET_INFO("hope: surface map reset (%u surfaces forgotten)", response.removed);
  return true;
}

void PlaneExtractorNodelet::reconfigure(hope::HopeConfig& config, uint32_t /*level*/) {
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
  // Each part is checked on its own: a bad value keeps the last good one of its part only.
  std::lock_guard<std::mutex> lock(pending_mutex_);
  try {
    hope::validate(params);
    pending_params_ = params;
  } catch (const std::exception& e) {
    NODELET_WARN("hope: keeping the previous extraction parameters: %s", e.what());
  }
  try {
    pending_tracker_.mode = hope::trackingModeFromString(config.tracking_mode);
  } catch (const std::exception& e) {
    NODELET_WARN("hope: keeping tracking mode %s: %s", hope::toString(pending_tracker_.mode),
                 e.what());
  }
  hope::ObjectParams object_params;
  object_params.max_height = config.object_max_height;
  try {
    hope::validate(object_params);
    pending_object_params_ = object_params;
  } catch (const std::exception& e) {
    NODELET_WARN("hope: keeping object_max_height %g: %s", pending_object_params_.max_height,
                 e.what());
  }
  pending_objects_ = config.objects;
  pending_placements_ = config.placements;
  pending_ = true;
  const hope::Params& p = pending_params_;
  // What is in effect goes back into the config, so the parameter server and the reported
  // config never show a value that was refused.
  config.r_xy = p.r_xy;
  config.r_z = p.r_z;
  config.min_height = std::max(p.min_height, -1000.0);
  config.max_height = std::min(p.max_height, 1000.0);
  config.min_area = p.min_area;
  config.merge_fragments = p.merge_fragments;
  config.max_merge_gap = p.max_merge_gap;
  config.bridge_scan_gaps = p.bridge_scan_gaps;
  config.threads = p.threads;
  config.tracking_mode = hope::toString(pending_tracker_.mode);
  config.object_max_height = pending_object_params_.max_height;
  NODELET_INFO(
      "hope: parameters: r_xy %.3f, r_z %.3f, height band [%g, %g], min_area %g, fragment "
      "merge %s (gap <= %g m), scan-gap bridging %s, tracking %s, %d thread(s), objects %s "
      "(up to %g m), placements %s",
      p.r_xy, p.r_z, p.min_height, p.max_height, p.min_area, p.merge_fragments ? "on" : "off",
      p.max_merge_gap, p.bridge_scan_gaps ? "on" : "off", hope::toString(pending_tracker_.mode),
      p.threads, pending_objects_ ? "on" : "off", pending_object_params_.max_height,
      pending_placements_ ? "on" : "off");
}

void PlaneExtractorNodelet::diagnose(diagnostic_updater::DiagnosticStatusWrapper& status) {
  std::lock_guard<std::mutex> lock(stats_mutex_);
  if (frames_ == 0) {
    status.summary(diagnostic_msgs::DiagnosticStatus::WARN,
                   rejected_ ? "no frame processed; last problem: " + last_problem_
                   : subscribed_
                       ? "waiting for clouds on " + cloud_topic_
                       : "idle: lazy, and no one listens to planes, labeled_cloud, markers or "
                         "objects "
                         "(set lazy: false to process every cloud regardless)");
  } else if (rejected_since_update_ > 0) {
    status.summary(diagnostic_msgs::DiagnosticStatus::WARN,
                   std::to_string(rejected_since_update_) +
                       " cloud(s) rejected since the last report; last problem: " + last_problem_);
  } else {
    status.summary(diagnostic_msgs::DiagnosticStatus::OK, "processing");
  }
  rejected_since_update_ = 0;
  status.add("frames processed", frames_);
  status.add("frames rejected", rejected_);
  status.add("frames dropped (gaps in seq, or in the stamps)", gaps_.dropped());
  status.add("time jumps back (tracks restarted)", time_jumps_);
  status.add("last processing ms", last_ms_);
  status.add("mean processing ms", frames_ ? sum_ms_ / frames_ : 0.0);
  status.add("max processing ms", max_ms_);
  status.add("orientation source", source_ + (refine_ ? ", refined by the scene" : ""));
  if (source_ == "scene" || refine_) {
    status.add("up from the scene: frames levelled", levelled_);
    if (source_ == "scene") {
      status.add("up from the scene: frames refused, last up kept", level_held_);
      status.add("up from the scene: frames refused and skipped", level_skipped_);
    } else {
      status.add("up from the scene: frames left uncorrected", uncorrected_);
    }
    status.add("up from the scene: last", last_levelling_);
    if (!last_level_problem_.empty()) {
      status.add("up from the scene: last refusal", last_level_problem_);
    }
    status.add("up from the scene: smoothed up", !smoothed_up_
                                                     ? std::string("none yet")
                                                     : std::to_string(smoothed_up_->x()) + " " +
                                                           std::to_string(smoothed_up_->y()) + " " +
                                                           std::to_string(smoothed_up_->z()));
  }
  status.add("reference frame", reference_frame_);
}

}  // namespace hope_ros

PLUGINLIB_EXPORT_CLASS(hope_ros::PlaneExtractorNodelet, nodelet::Nodelet)
