// The hope nodelet's outputs beyond the per-frame messages: the frames it broadcasts, the
// surface map, and its services.
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

bool PlaneExtractorNodelet::findPlacement(hope::FindPlacement::Request& request,
                                          hope::FindPlacement::Response& response) {
  std::lock_guard<std::mutex> lock(processing_mutex_);  // the pipeline and the last frame
  response.success = false;
  if (!placements_) {
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
  header.frame_id = settings_.reference_frame;
  publishMap(header);
  NODELET_INFO("hope: surface map reset (%u surfaces forgotten)", response.removed);
  return true;
}

}  // namespace hope_ros
