// Real tabletop scenes with labelled table tops (the mOSD scenes in ../shared/data/mosd_dev):
// the measure of the fragment merge on real clutter. A robot wants the whole table top as one
// plane, so a scene is scored by the best single plane's overlap with every table-top point.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include "hope/gravity_alignment.h"

namespace hope {
namespace evaluation {

struct LabelledTableScene {
  std::string name;                      // file name without extension
  pcl::PointCloud<pcl::PointXYZ> cloud;  // camera optical frame, organized, as recorded
  std::vector<std::uint8_t> is_table;    // per point: labelled 1–9 (one physical table top)
  // Per point, the dataset's label: 0 none, 1–9 the table top, 10 and above a part of an object
  // (mOSD: 20–29 the first object's parts, 30–39 the second's, ...).
  std::vector<std::uint32_t> labels;
  // Up = the unit normal of a least-squares plane through the table points, oriented toward
  // the camera (the dataset records no orientation, and the table top is level). Rotation
  // only: the viewpoint is the camera at the origin.
  Orientation orientation = Orientation::identity();
};

// Reads a PCD with fields `label x y z` (label 1–9: table top, 10 and above: objects). Throws
// std::runtime_error when the file cannot be read or has fewer than 3 table points.
LabelledTableScene loadLabelledTableScene(const std::string& path);

// The largest intersection-over-union of one plane's points with the true points, counted
// over finite points; labels[i] is the plane of point i or -1.
double bestPlaneIoU(const std::vector<int>& labels, const std::vector<std::uint8_t>& truth);

}  // namespace evaluation
}  // namespace hope
