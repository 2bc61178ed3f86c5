// The hope nodelet's diagnostics: what it processed, rejected and why, how up from the scene
// fares, and problems with the frames it broadcasts. Keys hold no commas, so that
// `rostopic echo -p /diagnostics` gives a CSV that reads.
#include "plane_extractor_nodelet.h"

namespace hope_ros {

void PlaneExtractorNodelet::startDiagnostics(ros::NodeHandle& nh, ros::NodeHandle& pnh) {
  diagnostics_ = std::make_unique<diagnostic_updater::Updater>(nh, pnh, getName());
  diagnostics_->setHardwareID("none");
  diagnostics_->add("processing", this, &PlaneExtractorNodelet::diagnose);
  // On wall time, and forced: Updater::update() waits for ROS time to pass its next report,
  // which never comes once a looping bag sends sim time back.
  diagnostics_timer_ = nh.createWallTimer(
      ros::WallDuration(1.0), [this](const ros::WallTimerEvent&) { diagnostics_->force_update(); });
}

void PlaneExtractorNodelet::reject(const std::string& problem) {
  {
    std::lock_guard<std::mutex> lock(stats_mutex_);
    ++rejected_;
    ++rejected_since_update_;
    last_problem_ = problem;
  }
  {
    // A ~segment request waiting meanwhile says why it got no cloud.
    std::lock_guard<std::mutex> lock(segment_mutex_);
    for (PendingSegment* pending : segments_) pending->problem = problem;
  }
  NODELET_WARN_THROTTLE(5.0, "hope: skipping a cloud: %s", problem.c_str());
}

void PlaneExtractorNodelet::noteFrame(const hope::Frame& frame) {
  if (frame.time_jump) {
    NODELET_WARN_THROTTLE(10.0,
                          "hope: time went back (a looping bag?): plane tracks, the gravity "
                          "average and the running up start afresh");
  }
  if (frame.level_held) {
    NODELET_WARN_THROTTLE(10.0, "hope: %s: keeping the last up", frame.skipped.c_str());
  }
  std::lock_guard<std::mutex> lock(stats_mutex_);
  if (frame.time_jump) gaps_.restart();
  counters_ = pipeline_->counters();
  smoothed_up_ = pipeline_->smoothedUp();
  if (frame.levelling) last_levelling_ = frame.levelling->describe();
  if (!frame.skipped.empty()) last_level_problem_ = frame.skipped;
  if (frame.odometry) {
    ++odometry_frames_;
    odometry_not_aligned_ += !frame.odometry->tracked && !frame.odometry->started ? 1 : 0;
    odometry_overlap_ = frame.odometry->overlap;
  }
}

void PlaneExtractorNodelet::noteTime(double ms) {
  std::lock_guard<std::mutex> lock(stats_mutex_);
  last_ms_ = ms;
  sum_ms_ += ms;
  max_ms_ = std::max(max_ms_, ms);
}

void PlaneExtractorNodelet::onCloudWithoutTransform(const sensor_msgs::PointCloud2ConstPtr& cloud,
                                                    tf2_ros::FilterFailureReason reason) {
  const char* why = reason == tf2_ros::filter_failure_reasons::OutTheBack
                        ? "older than the tf buffer"
                    : reason == tf2_ros::filter_failure_reasons::EmptyFrameID
                        ? "an empty frame_id"
                        : "no transform before the queue overflowed";
  reject("no transform from '" + frameId(cloud->header.frame_id) + "' to '" +
         settings_.reference_frame + "': " + why);
}

void PlaneExtractorNodelet::onTf(const ros::MessageEvent<tf2_msgs::TFMessage const>& event) {
  std::string parent;
  {
    std::lock_guard<std::mutex> lock(stats_mutex_);
    parent = broadcast_parent_;
  }
  if (parent.empty()) return;
  const std::string& ours = settings_.reference_frame;
  for (const auto& t : event.getMessage()->transforms) {
    if (frameId(t.child_frame_id) != ours || frameId(t.header.frame_id) == parent) continue;
    NODELET_WARN_THROTTLE(10.0,
                          "hope: '%s' publishes our reference frame '%s' as a child of '%s'; "
                          "hope broadcasts it under '%s'. Give each hope nodelet its own "
                          "~reference_frame.",
                          event.getPublisherName().c_str(), ours.c_str(), t.header.frame_id.c_str(),
                          parent.c_str());
    std::lock_guard<std::mutex> lock(stats_mutex_);
    last_problem_ =
        "another node publishes '" + ours + "' under '" + frameId(t.header.frame_id) + "'";
  }
}

void PlaneExtractorNodelet::diagnose(diagnostic_updater::DiagnosticStatusWrapper& status) {
  std::lock_guard<std::mutex> lock(stats_mutex_);
  const hope::PipelineCounters& c = counters_;
  if (c.frames == 0) {
    status.summary(diagnostic_msgs::DiagnosticStatus::WARN,
                   rejected_ ? "no frame processed; last problem: " + last_problem_
                   : subscribed_
                       ? "waiting for clouds on " + cloud_topic_
                       : "idle: lazy and no one listens to planes or labeled_cloud or markers "
                         "or objects (set lazy: false to process every cloud regardless)");
  } else if (rejected_since_update_ > 0) {
    status.summary(diagnostic_msgs::DiagnosticStatus::WARN,
                   std::to_string(rejected_since_update_) +
                       " cloud(s) rejected since the last report; last problem: " + last_problem_);
  } else {
    status.summary(diagnostic_msgs::DiagnosticStatus::OK, "processing");
  }
  rejected_since_update_ = 0;
  status.add("frames processed", c.frames);
  status.add("frames rejected", rejected_);
  status.add("frames dropped (gaps in seq or in the stamps)", gaps_.dropped());
  status.add("clouds delivered twice (skipped)", repeated_.count());
  status.add("time jumps back (tracks restarted)", c.time_jumps);
  status.add("last processing ms", last_ms_);
  status.add("mean processing ms", c.frames ? sum_ms_ / c.frames : 0.0);
  status.add("max processing ms", max_ms_);
  status.add("orientation source", settings_.source + (settings_.refine ? " refined" : ""));
  if (settings_.source == "scene" || settings_.refine) {
    status.add("up from the scene: frames levelled", c.levelled);
    if (settings_.source == "scene") {
      status.add("up from the scene: frames refused and last up kept", c.level_held);
      status.add("up from the scene: frames refused and skipped", c.skipped);
    } else {
      status.add("up from the scene: frames left uncorrected", c.uncorrected);
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
  status.add("reference frame", settings_.reference_frame);
  if (odometry_frames_ > 0) {
    status.add("odometry: frames followed", odometry_frames_);
    status.add("odometry: frames not aligned with the last", odometry_not_aligned_);
    status.add("odometry: last overlap", odometry_overlap_);
    status.add("odometry: frame", settings_.odometry_frame);
  }
}

}  // namespace hope_ros
