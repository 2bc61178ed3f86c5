// The hope nodelet's class (not installed): its inputs (plane_extractor_nodelet.cpp), outputs
// and services (nodelet_outputs.cpp) and diagnostics (nodelet_status.cpp). Every frame's policy
// is the core's FramePipeline.
#pragma once

#include <atomic>
#include <condition_variable>
#include <memory>
#include <mutex>
#include <optional>
#include <string>

#include <diagnostic_updater/diagnostic_updater.h>
#include <dynamic_reconfigure/server.h>
#include <message_filters/subscriber.h>
#include <message_filters/sync_policies/approximate_time.h>
#include <message_filters/synchronizer.h>
#include <nodelet/nodelet.h>
#include <ros/callback_queue.h>
#include <ros/ros.h>
#include <sensor_msgs/Imu.h>
#include <sensor_msgs/PointCloud2.h>
#include <tf2_msgs/TFMessage.h>
#include <tf2_ros/buffer.h>
#include <tf2_ros/message_filter.h>
#include <tf2_ros/transform_broadcaster.h>
#include <tf2_ros/transform_listener.h>
#include <boost/thread/recursive_mutex.hpp>

#include "hope/FindPlacement.h"
#include "hope/HopeConfig.h"
#include "hope/ResetMap.h"
#include "hope/Segment.h"
#include "hope/frame_pipeline.h"
#include "hope_ros/frame_gaps.h"
#include "nodelet_settings.h"

namespace hope_ros {

using CloudImuPolicy =
    message_filters::sync_policies::ApproximateTime<sensor_msgs::PointCloud2, sensor_msgs::Imu>;
using CloudSubscriber = message_filters::Subscriber<sensor_msgs::PointCloud2>;

class PlaneExtractorNodelet : public nodelet::Nodelet {
 public:
  ~PlaneExtractorNodelet() override;

 private:
  // A frame's orientation as its source gives it, or an accelerometer's sample for the
  // pipeline to average.
  struct FrameOrientation {
    hope::Orientation given;
    std::optional<Eigen::Vector3d> specific_force;
  };
  // The nodelet's own live parameters (cfg/Hope.cfg), beyond the pipeline's.
  struct OutputSwitches {
    bool placements = true;      // answer ~find_placement (keeps every frame's points)
    bool object_points = false;  // ~objects carry each object's points
    bool publish_tf = false;     // a tf frame per plane and per object
  };
  // A ~segment request waiting for its cloud (under segment_mutex_).
  struct PendingSegment {
    hope::Segment::Request request;
    ros::Time after;  // the answer's cloud is stamped at or after this
    bool done = false;
    hope::Segment::Response response;
    std::size_t earlier = 0;   // clouds processed meanwhile, stamped before `after`
    ros::Time latest_earlier;  // the newest of them
    std::string problem;       // the last reason a cloud was not processed meanwhile
  };

  void onInit() override;
  void connectionChanged();
  // Every input subscription ended (connection_mutex_ held).
  void unsubscribe();
  void onCloud(const sensor_msgs::PointCloud2ConstPtr& cloud);
  void onCloudAndImu(const sensor_msgs::PointCloud2ConstPtr& cloud,
                     const sensor_msgs::ImuConstPtr& imu);
  FrameOrientation orientationFromImu(const sensor_msgs::Imu& imu, const std::string& cloud_frame);
  // One cloud through the pipeline and out; the reference frame broadcast when `broadcast`.
  void process(const sensor_msgs::PointCloud2ConstPtr& cloud, const FrameOrientation& orientation,
               const std::string& reference_frame, bool broadcast);
  void takePendingOptions();
  void reconfigure(hope::HopeConfig& config, uint32_t level);

  // Outputs and services (nodelet_outputs.cpp).
  // Publishes the gravity-aligned reference frame as a child of the cloud's frame (a frame
  // has one parent in tf; the cloud's frame usually has its own already).
  void broadcastReference(const std_msgs::Header& cloud_header,
                          const hope::Orientation& orientation);
  // tracking_mode odometry: the odometry's world (~odometry_frame) as a child of the reference
  // frame at the frame's stamp (`header`), where the scene odometry placed this frame in it.
  void broadcastOdometry(const hope::Frame& frame, const std_msgs::Header& header);
  // The frame the surface map's entries lie in: the odometry's world or the reference frame.
  std::string mapFrame() const;
  // Broadcasts the view frame (level, under the reference frame) at the middle of what the
  // planes cover, eased from frame to frame: rviz/hope.rviz orbits it, so RViz frames any scene.
  void broadcastView(const hope::Result& result, const std_msgs::Header& header);
  // ~find_placement: searches the last frame processed; a refusal comes back with success
  // false and the reason, never as a failed call (a client would see no reason then).
  bool findPlacement(hope::FindPlacement::Request& request,
                     hope::FindPlacement::Response& response);
  // ~segment: waits (on a queue and a thread of its own, so that clouds go on arriving on the
  // manager's threads) for the next frame stamped at or after the request, which process()
  // answers.
  bool segment(hope::Segment::Request& request, hope::Segment::Response& response);
  // Answers every waiting ~segment request that `frame` (stamped header.stamp) can answer.
  void answerSegments(const hope::Frame& frame, const std_msgs::Header& header);
  // Why a ~segment request got no cloud in `seconds`.
  std::string whyNoSegment(const PendingSegment& pending, double seconds) const;
  // publish_tf: each plane's frame (at its centroid, level) and each object's (its box's pose).
  void broadcastThings(const hope::Result& result, const std_msgs::Header& header);
  // ~reset_map: forgets the surface map's entries and publishes the empty map.
  bool resetMap(hope::ResetMap::Request& request, hope::ResetMap::Response& response);
  // The map's entries on the latched ~map and ~map_markers.
  void publishMap(const std_msgs::Header& header);

  // Diagnostics (nodelet_status.cpp).
  void startDiagnostics(ros::NodeHandle& nh, ros::NodeHandle& pnh);
  void diagnose(diagnostic_updater::DiagnosticStatusWrapper& status);
  // A cloud not processed: counted, its reason kept for /diagnostics and logged (throttled).
  void reject(const std::string& problem);
  // The pipeline's counters after a frame, and a time jump said.
  void noteFrame(const hope::Frame& frame);
  void noteTime(double ms);
  // tf: a cloud the message filter could not transform in time.
  void onCloudWithoutTransform(const sensor_msgs::PointCloud2ConstPtr& cloud,
                               tf2_ros::FilterFailureReason reason);
  // Warns when another publisher puts our reference frame under another parent.
  void onTf(const ros::MessageEvent<tf2_msgs::TFMessage const>& event);

  StartupSettings settings_;
  // Declared before everything that uses it: members are destroyed in reverse order, and the
  // tf message filter below reads this buffer until it is gone.
  std::unique_ptr<tf2_ros::Buffer> tf_buffer_;
  std::unique_ptr<tf2_ros::TransformListener> tf_listener_;
  std::unique_ptr<tf2_ros::TransformBroadcaster> tf_broadcaster_;

  std::mutex processing_mutex_;  // one frame at a time; guards the pipeline and the last frame
  std::unique_ptr<hope::FramePipeline> pipeline_;
  OutputSwitches switches_;
  hope::Frame last_frame_;  // for ~find_placement (with its points), when placements are on
  std_msgs::Header last_header_;
  std::optional<Eigen::Vector3d> view_centre_;
  boost::shared_ptr<sensor_msgs::PointCloud2> labeled_cloud_;  // the last one published
  ros::WallTime last_map_publish_;

  // dynamic_reconfigure writes the pending options; the processing thread swaps them in at the
  // start of the next frame.
  boost::recursive_mutex reconfigure_mutex_;
  std::unique_ptr<dynamic_reconfigure::Server<hope::HopeConfig>> reconfigure_server_;
  std::mutex pending_mutex_;
  hope::PipelineOptions pending_options_;
  OutputSwitches pending_switches_;
  bool pending_ = false;

  ros::Publisher planes_pub_, cloud_pub_, markers_pub_, objects_pub_, obstacles_pub_,
      floor_grid_pub_, map_pub_, map_markers_pub_;
  ros::ServiceServer placement_srv_, reset_map_srv_, segment_srv_;

  // ~segment's waiting requests; process() answers them, the destructor wakes them. The service
  // has its own queue and thread: a request blocked on a manager thread could hold up the very
  // cloud it waits for (the manager gives a nodelet's queue to a thread and keeps it there).
  ros::CallbackQueue segment_queue_;
  std::unique_ptr<ros::AsyncSpinner> segment_spinner_;
  std::mutex segment_mutex_;
  std::condition_variable segment_cv_;
  std::vector<PendingSegment*> segments_;
  std::atomic<int> segments_waiting_{0};  // read by connectionChanged() and process()
  bool shutting_down_ = false;

  // Diagnostics, under stats_mutex_.
  std::unique_ptr<diagnostic_updater::Updater> diagnostics_;
  ros::WallTimer diagnostics_timer_;
  std::mutex stats_mutex_;
  std::size_t rejected_ = 0, rejected_since_update_ = 0;
  double last_ms_ = 0, max_ms_ = 0, sum_ms_ = 0;
  hope_ros::FrameGapCounter gaps_;     // frames that never reached hope
  hope_ros::RepeatedClouds repeated_;  // clouds delivered twice, skipped
  hope::PipelineCounters counters_;
  std::optional<Eigen::Vector3d> smoothed_up_;
  std::string last_levelling_, last_level_problem_, last_problem_;
  std::string broadcast_parent_;  // the frame our reference frame hangs from
  // tracking_mode odometry: frames it followed, frames after a world's first it could not align
  // (the map's gates then keep what it misplaces from taking an id), and the last overlap.
  std::size_t odometry_frames_ = 0, odometry_not_aligned_ = 0;
  double odometry_overlap_ = 0;

  // Inputs last: destroyed first (the destructor also shuts them down before anything else).
  std::mutex connection_mutex_;
  std::atomic<bool> subscribed_{false};  // read by the diagnostics without the mutex
  std::string cloud_topic_;              // resolved, for messages
  ros::Subscriber cloud_sub_, tf_watch_sub_;
  std::unique_ptr<CloudSubscriber> tf_cloud_sub_;
  std::unique_ptr<tf2_ros::MessageFilter<sensor_msgs::PointCloud2>> tf_filter_;
  std::unique_ptr<CloudSubscriber> sync_cloud_sub_;
  std::unique_ptr<message_filters::Subscriber<sensor_msgs::Imu>> sync_imu_sub_;
  std::unique_ptr<message_filters::Synchronizer<CloudImuPolicy>> sync_;
};

}  // namespace hope_ros
