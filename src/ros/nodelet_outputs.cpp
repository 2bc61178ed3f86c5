// The hope nodelet's outputs beyond the per-frame messages: the frames it broadcasts, the
// surface map, and its services.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>

#include <tf2_eigen/tf2_eigen.h>

#include "hope_ros/cloud_conversion.h"
#include "hope_ros/object_conversion.h"
#include "plane_extractor_nodelet.h"

namespace hope_ros {

void PlaneExtractorNodelet::broadcastReference(const std_msgs::Header& cloud_header,
                                               const hope::Orientation& orientation) {
  geometry_msgs::TransformStamped t =
      tf2::eigenToTransform(orientation.sensorToReference().inverse());
  t.header.stamp = cloud_header.stamp;
  t.header.frame_id = frameId(cloud_header.frame_id);
  t.child_frame_id = settings_.reference_frame;
  {
    std::lock_guard<std::mutex> lock(stats_mutex_);
    broadcast_parent_ = t.header.frame_id;
  }
  tf_broadcaster_->sendTransform(t);
}

void PlaneExtractorNodelet::broadcastOdometry(const hope::Frame& frame,
                                              const std_msgs::Header& header) {
  // tf's transform is the child's pose in its parent: the world's origin and axes seen from
  // this frame.
  geometry_msgs::TransformStamped t =
      tf2::eigenToTransform(frame.odometry->world_from_frame.inverse());
  t.header = header;
  t.child_frame_id = settings_.odometry_frame;
  tf_broadcaster_->sendTransform(t);
}

std::string PlaneExtractorNodelet::mapFrame() const {
  return pipeline_->options().identity == hope::Identity::kOdometry ? settings_.odometry_frame
                                                                    : settings_.reference_frame;
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
  t.child_frame_id = settings_.view_frame;
  t.transform.translation.x = view_centre_->x();
  t.transform.translation.y = view_centre_->y();
  t.transform.translation.z = view_centre_->z();
  t.transform.rotation.w = 1.0;
  tf_broadcaster_->sendTransform(t);
}

void PlaneExtractorNodelet::broadcastThings(const hope::Result& result,
                                            const std_msgs::Header& header) {
  std::vector<geometry_msgs::TransformStamped> frames;
  frames.reserve(result.planes.size() + result.objects.size());
  auto add = [&](const std::string& name, const Eigen::Vector3d& at, double yaw) {
    geometry_msgs::TransformStamped t;
    t.header = header;
    t.child_frame_id = ownFrame(getName(), name.c_str());
    t.transform.translation.x = at.x();
    t.transform.translation.y = at.y();
    t.transform.translation.z = at.z();
    t.transform.rotation.z = std::sin(0.5 * yaw);
    t.transform.rotation.w = std::cos(0.5 * yaw);
    frames.push_back(t);
  };
  for (const hope::HorizontalPlane& p : result.planes) {
    // On the plane at its centroid, level (whatever the fit's tilt): z up, as the frame's.
    add("plane_" + std::to_string(p.id), Eigen::Vector3d(p.centroid.x(), p.centroid.y(), p.height),
        0.0);
  }
  for (const hope::StandingObject& o : result.objects) {
    add("object_" + std::to_string(o.index), o.box_centre, o.yaw);
  }
  if (!frames.empty()) tf_broadcaster_->sendTransform(frames);
}

bool PlaneExtractorNodelet::segment(hope::Segment::Request& request,
                                    hope::Segment::Response& response) {
  response.success = false;
  response.message = checkSegmentRequest(request);
  if (!response.message.empty()) return true;
  PendingSegment pending;
  pending.request = request;
  pending.after = ros::Time::now();
  const double seconds = segmentTimeout(request);
  {
    std::lock_guard<std::mutex> lock(segment_mutex_);
    if (shutting_down_) {
      response.message = "hope is shutting down";
      return true;
    }
    segments_.push_back(&pending);
    ++segments_waiting_;
  }
  connectionChanged();  // lazy: subscribes to the cloud while the request waits
  bool shutting_down = false;
  {
    std::unique_lock<std::mutex> lock(segment_mutex_);
    segment_cv_.wait_for(lock, std::chrono::duration<double>(seconds),
                         [&] { return pending.done || shutting_down_; });
    segments_.erase(std::find(segments_.begin(), segments_.end(), &pending));
    --segments_waiting_;
    shutting_down = shutting_down_;
    if (pending.done) {
      response = std::move(pending.response);
    } else {
      response.message = shutting_down ? "hope is shutting down" : whyNoSegment(pending, seconds);
    }
  }
  if (!shutting_down) connectionChanged();  // lazy: unsubscribes when nothing else listens
  return true;
}

void PlaneExtractorNodelet::answerSegments(const hope::Frame& frame,
                                           const std_msgs::Header& header) {
  std::lock_guard<std::mutex> lock(segment_mutex_);
  bool answered = false;
  for (PendingSegment* pending : segments_) {
    if (pending->done) continue;
    // The stream started over since the request (a looping bag, a reset clock: the pipeline
    // saw the stamp go back): this cloud came after the request whatever its stamp, and one
    // stamped after the request may never come (a bag that ends before it loops back).
    if (frame.time_jump) pending->after = std::min(pending->after, header.stamp);
    if (header.stamp < pending->after) {
      ++pending->earlier;
      pending->latest_earlier = header.stamp;
      continue;
    }
    try {
      pending->response = segmentAnswer(pending->request, frame, header);
    } catch (const std::exception& e) {
      pending->response = hope::Segment::Response();
      pending->response.header = header;
      pending->response.message = e.what();
    }
    pending->done = answered = true;
  }
  if (answered) segment_cv_.notify_all();
}

std::string PlaneExtractorNodelet::whyNoSegment(const PendingSegment& pending,
                                                double seconds) const {
  char text[160];
  std::snprintf(text, sizeof(text),
                "no cloud stamped after the request (%.3f s) was processed "
                "within %g s: ",
                pending.after.toSec(), seconds);
  std::string why = text;
  if (pending.earlier > 0) {
    const double before = (pending.after - pending.latest_earlier).toSec();
    // More than a second before it is no sensor's latency.
    std::snprintf(text, sizeof(text),
                  before > 1.0 ? "%zu were, all stamped before it (the newest %.3f s before): the "
                                 "cloud's stamps are not on the ROS clock (a replay without "
                                 "--clock and use_sim_time?)"
                               : "%zu were, stamped before it (the newest %.3f s before), and none "
                                 "after it: did the sensor stop?",
                  pending.earlier, before);
    return why + text;
  }
  if (!pending.problem.empty()) return why + "the last cloud was skipped: " + pending.problem;
  why += "none arrived on " + cloud_topic_;
  if (settings_.source == "imu") {
    why += " paired with an IMU message on " + getPrivateNodeHandle().resolveName("imu") +
           " (orientation_source imu)";
  } else if (settings_.source == "tf") {
    why += " with a transform to " + settings_.reference_frame + " (orientation_source tf)";
  }
  return why;
}

bool PlaneExtractorNodelet::findPlacement(hope::FindPlacement::Request& request,
                                          hope::FindPlacement::Response& response) {
  std::lock_guard<std::mutex> lock(processing_mutex_);  // the pipeline and the last frame
  response.success = false;
  if (!switches_.placements) {
    response.message = "placements are switched off (~placements false)";
    return true;
  }
  if (!last_frame_.processed) {
    response.message =
        std::string("no cloud processed yet") +
        (settings_.lazy && !subscribed_ ? " (lazy: hope subscribes to " + cloud_topic_ +
                                              " only while an output has a listener)"
                                        : " since the start or the last reconfiguration");
    return true;
  }
  response.header = last_header_;
  hope::PlacementQuery query;
  response.message = placementQuery(request, last_frame_.result.planes, query);
  if (!response.message.empty()) return true;
  try {
    for (const hope::Placement& p : pipeline_->findPlacements(last_frame_, query)) {
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
  entries.planes = pipeline_->mapSurfaces();
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
  response.removed = static_cast<std::uint32_t>(pipeline_->mapSize());
  pipeline_->resetMap();
  std_msgs::Header header;
  header.stamp = last_header_.stamp;
  header.frame_id = mapFrame();
  publishMap(header);
  NODELET_INFO("hope: surface map reset (%u surfaces forgotten)", response.removed);
  return true;
}

}  // namespace hope_ros
