// Between ROS messages and the ROS-free core: a PointCloud2 read in place as a hope::PointsView,
// and hope's results as messages.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <nav_msgs/OccupancyGrid.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>
#include <sensor_msgs/PointCloud2.h>
#include <visualization_msgs/MarkerArray.h>

#include "hope/PlaneArray.h"
#include "hope/extractor.h"
#include "hope/frame_pipeline.h"

namespace hope_ros {

// Reads the cloud's x, y, z in place (no copy). Returns an empty string, or why the cloud
// cannot be read: missing or non-float32 x/y/z fields, big-endian data, padded rows, a data
// buffer shorter than the header says.
std::string viewOf(const sensor_msgs::PointCloud2& cloud, hope::PointsView& view);

// A PCL cloud of PointXYZ as a PointCloud2 with float32 x y z and PCL's 16-byte point layout,
// organized layout kept (for bags and benchmarks).
sensor_msgs::PointCloud2 cloudMessage(const pcl::PointCloud<pcl::PointXYZ>& cloud,
                                      const std_msgs::Header& header);

// The points of `cloud` at `indices` (a cloud viewOf reads; indices below its size), in its own
// frame and stamp: float32 x y z, and rgb when the cloud has a 4-byte rgb or rgba field, one row
// (the ~obstacles cloud). 12 or 16 bytes a point.
sensor_msgs::PointCloud2 selectedPoints(const sensor_msgs::PointCloud2& cloud,
                                        const std::vector<std::uint32_t>& indices);

// The planes as a message with `header` (the reference frame and the cloud's stamp).
hope::PlaneArray toMessage(const hope::Result& result, const std_msgs::Header& header);

// The floor grid (~floor_grid) with `header` (the reference frame and the cloud's stamp): the
// same cells and values (-1 unseen, 0 free, 100 occupied); the origin's pose at the cell (0, 0)
// corner on the floor's height, unturned. An empty grid (no floor in view) has width 0.
nav_msgs::OccupancyGrid toMessage(const hope::FloorGrid& grid, const std_msgs::Header& header);

// Points in the reference frame with x y z (float32), rgb (float32, colour of the plane's id,
// grey for none), label (uint32: plane id + 1, 0 for none) and object (uint32: the index of
// the object it belongs to + 1, 0 for none or when the result has no objects), same layout as
// the input (width × height), kLabeledPointStep bytes a point.
constexpr std::uint32_t kLabeledPointStep = 24;
sensor_msgs::PointCloud2 labeledCloud(const hope::AlignedPoints& aligned,
                                      const hope::Result& result, const hope::PointsView& input,
                                      const std_msgs::Header& header);
// The same written into `out`, whose data buffer is reused when it already has the size: a
// node that keeps the message it published last, once no subscriber holds it any more, saves
// the allocation and the clearing of ~6 MB per VGA frame.
void fillLabeledCloud(const hope::AlignedPoints& aligned, const hope::Result& result,
                      const hope::PointsView& input, const std_msgs::Header& header,
                      sensor_msgs::PointCloud2& out);

// Where planeMarkers puts each plane's "id: height" label (same order as `planes`): above
// its centroid, or above a corner of it in the open when a higher plane covers the centroid
// (RViz hides text behind the fills and points in front of it: the floor under a table);
// high enough that the text stands clear of the plane's own fill; and raised further above
// any label placed before it (larger planes first) whose text it could overlap from some
// point of view, so that labels of crowded planes stack instead of covering each other.
std::vector<Eigen::Vector3d> labelPositions(const std::vector<hope::HorizontalPlane>& planes);
// The labels' text height in metres, and the width allowed per character.
constexpr double kLabelHeight = 0.12;
constexpr double kLabelCharWidth = 0.9 * kLabelHeight;  // RViz's font, spaces included

// The middle of what the planes cover (their boxes' union in x and y, halfway between the
// lowest and the highest plane in z), or nullopt without planes: where RViz's view should
// look (the nodelet broadcasts it as the frame `view_frame`, which rviz/hope.rviz orbits).
std::optional<Eigen::Vector3d> sceneCentre(const std::vector<hope::HorizontalPlane>& planes);

// For RViz: a DELETEALL first (no stale markers), then per plane its hull filled and outlined
// in its id's Pascal VOC colour and a text "id: height" (at labelPositions).
visualization_msgs::MarkerArray planeMarkers(const hope::Result& result,
                                             const std_msgs::Header& header);

}  // namespace hope_ros
