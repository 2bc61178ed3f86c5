// What stands on hope's planes, and where a new object fits, as ROS messages: ~objects
// (hope/ObjectArray), the objects' boxes in ~markers, and ~find_placement (hope/FindPlacement).
#pragma once

#include <string>
#include <vector>

#include <std_msgs/Header.h>
#include <visualization_msgs/MarkerArray.h>

#include "hope/FindPlacement.h"
#include "hope/ObjectArray.h"
#include "hope/extractor.h"

namespace hope_ros {

// result.objects as a message with `header` (the reference frame and the cloud's stamp).
hope::ObjectArray toMessage(const std::vector<hope::StandingObject>& objects,
                            const std_msgs::Header& header);

// For RViz, appended to planeMarkers' (whose DELETEALL clears them too): per object its upright
// box as a CUBE in the colour of the plane it stands on, and its index as text above it. Marker
// ids are the object's index in the namespace "objects" and "object_ids".
void appendObjectMarkers(const std::vector<hope::StandingObject>& objects,
                         const std_msgs::Header& header, visualization_msgs::MarkerArray& markers);

// The query of a ~find_placement request on `planes` (the last frame's): plane_id -1 or the id
// of one of them (translated to its index), max_results 0 → 5. Returns an empty string, or why
// the request cannot be searched, naming the field (the footprint's values are checked by
// hope::validate(Footprint) when searched).
std::string placementQuery(const hope::FindPlacement::Request& request,
                           const std::vector<hope::HorizontalPlane>& planes,
                           hope::PlacementQuery& query);

// A placement as a message: the pose is at the footprint's centre, turned by its yaw about z.
hope::PlacementPose toMessage(const hope::Placement& placement);

}  // namespace hope_ros
