// Pictures a person can judge at a glance.
#pragma once

#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "hope/extractor.h"
#include "hope/placement.h"
#include "hope/plane_colors.h"
#include "hope/tools/cloud_file.h"

namespace hope {
namespace tools {

// hope::vocColor / hope::planeColor (plane_colors.h) as OpenCV's BGR.
cv::Vec3b vocColor(int index);
cv::Vec3b planeColor(int id);

// For an organized cloud shaped like an image (at most 4 times wider than high): the image
// (its colour, or a grey depth rendering) with every plane's pixels tinted by its id and
// "id: height" written on it. Otherwise (unorganized, or a LiDAR's rings x azimuth): a
// top-down view of the aligned points, planes tinted, outlines drawn and labelled.
// Objects (Result::objects) are boxed in amber, and `placements` of `footprint` painted green.
cv::Mat renderOverlay(const InputCloud& cloud, const AlignedPoints& aligned, const Result& result,
                      const std::vector<Placement>& placements = {},
                      const Footprint& footprint = Footprint());

// A label to write on a picture: its text's box and the places it may go (the box's centre),
// best first.
struct LabelRequest {
  cv::Size size;
  std::vector<cv::Point> places;
};

// Where each label goes, as the rectangle its box covers, in the order given: the first of
// its places (its box moved inside the image) that covers no label placed before it, or, with
// none free, the one that covers the least of them (a crowded picture still names everything).
// A label with no places goes to the image's centre.
std::vector<cv::Rect> layoutLabels(const cv::Size& image, const std::vector<LabelRequest>& labels);

// A top-down view of `points` over [x0, x1] × [y0, y1] on a `size`-pixel square, each point
// coloured by its label (VOC colour label + 1; label -1 grey, shaded by height).
cv::Mat renderLabelsTopDown(const std::vector<Eigen::Vector3f>& points,
                            const std::vector<int>& labels, double x0, double y0, double x1,
                            double y1, int size);

}  // namespace tools
}  // namespace hope
