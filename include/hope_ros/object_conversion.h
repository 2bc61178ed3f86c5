// What stands on hope's planes, and where a new object fits, as ROS messages: ~objects
// (hope/ObjectArray), the objects' boxes in ~markers, and ~find_placement (hope/FindPlacement)
// in object_conversion.cpp; ~segment's answer (hope/Segment) and the objects' points
// (object_points) in segment_conversion.cpp.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <sensor_msgs/PointCloud2.h>
#include <std_msgs/Header.h>
#include <visualization_msgs/MarkerArray.h>

#include "hope/FindPlacement.h"
#include "hope/ObjectArray.h"
#include "hope/Segment.h"
#include "hope/extractor.h"
#include "hope/frame_pipeline.h"

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

// ~segment and object_points (segment_conversion.cpp): a frame's planes and objects with their
// points (the nodelet's waiting for the cloud is its own).

// The points at `indices` of a frame's kept points (Frame::points, relative to `local_origin`),
// x y z (float32) in the reference frame, one row, with `header`.
sensor_msgs::PointCloud2 referencePoints(const std::vector<Eigen::Vector3f>& points,
                                         const Eigen::Vector3d& local_origin,
                                         const std::vector<std::uint32_t>& indices,
                                         const std_msgs::Header& header);

// The input indices of each object's points (Result::point_objects grouped), in input order.
std::vector<std::vector<std::uint32_t>> pointsOfObjects(const hope::Result& result);

// Fills each object's `points` in `objects` (toMessage of the frame's objects, same order)
// from the frame's kept points (FrameOutputs::keep_points). Throws std::invalid_argument when
// the frame kept no points or the objects are not the frame's.
void attachObjectPoints(const hope::Frame& frame, hope::ObjectArray& objects);

// An empty string, or why the request cannot be answered, naming the field: a timeout that is
// negative, not finite or over 300 s; a band or a box whose minimum is above its maximum or not
// finite.
std::string checkSegmentRequest(const hope::Segment::Request& request);

// The seconds a request waits: its timeout, 0 meaning 5.
double segmentTimeout(const hope::Segment::Request& request);

// The answer from `frame` (processed with points kept, labels and objects) with `header` (the
// reference frame, the cloud's stamp): the planes in the band and the box, each with its points,
// and the objects standing on them (in the box), each with its points. success false, naming
// the heights or the box and the planes the frame had, when no plane is in them.
hope::Segment::Response segmentAnswer(const hope::Segment::Request& request,
                                      const hope::Frame& frame, const std_msgs::Header& header);

}  // namespace hope_ros
