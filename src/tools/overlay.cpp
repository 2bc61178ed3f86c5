#include "hope/tools/overlay.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include <opencv2/imgproc.hpp>

namespace hope {
namespace tools {

cv::Vec3b vocColor(int index) {
  const Rgb c = hope::vocColor(index);
  return cv::Vec3b(c.b, c.g, c.r);
}

cv::Vec3b planeColor(int id) {
  const Rgb c = hope::planeColor(id);
  return cv::Vec3b(c.b, c.g, c.r);
}

namespace {

std::string planeText(const HorizontalPlane& plane) {
  char text[64];
  std::snprintf(text, sizeof(text), "%d: %.2fm", plane.id, plane.height);
  return text;
}

// A label: white text with a dark outline, readable on any background.
struct Label {
  std::string text;
  double scale;
  int thickness() const { return std::max(1, static_cast<int>(std::lround(scale * 1.5))); }
  // The text's box with its outline and a pixel to spare on each side.
  cv::Size box() const {
    int baseline = 0;
    const cv::Size size =
        cv::getTextSize(text, cv::FONT_HERSHEY_SIMPLEX, scale, thickness(), &baseline);
    const int spare = thickness() + 2;
    return cv::Size(size.width + 2 * spare, size.height + 2 * spare);
  }
};

// Writes `label` in `place` (a rectangle of its box()).
void drawLabel(cv::Mat& image, const Label& label, const cv::Rect& place) {
  int baseline = 0;
  const cv::Size size = cv::getTextSize(label.text, cv::FONT_HERSHEY_SIMPLEX, label.scale,
                                        label.thickness(), &baseline);
  const cv::Point origin(place.x + (place.width - size.width) / 2,
                         place.y + (place.height + size.height) / 2);
  cv::putText(image, label.text, origin, cv::FONT_HERSHEY_SIMPLEX, label.scale, cv::Scalar(0, 0, 0),
              label.thickness() + 2, cv::LINE_AA);
  cv::putText(image, label.text, origin, cv::FONT_HERSHEY_SIMPLEX, label.scale,
              cv::Scalar(255, 255, 255), label.thickness(), cv::LINE_AA);
}

// Places for a plane's label, best first: its pixels' centre, then steps of a label's height
// above and below it and of half its width beside it (a plane's pixels surround its centre,
// so a label moved a little still names the plane it is on).
std::vector<cv::Point> planeLabelPlaces(cv::Point centre, cv::Size box) {
  std::vector<cv::Point> places{centre};
  for (int step = 1; step <= 3; ++step) {
    for (const cv::Point& offset :
         {cv::Point(0, step * box.height), cv::Point(0, -step * box.height),
          cv::Point(step * box.width / 2, 0), cv::Point(-step * box.width / 2, 0)}) {
      places.push_back(centre + offset);
    }
  }
  return places;
}

// Places for an object's tag, best first: centred over its box, over its left or right end,
// inside its top corners, centred under it, inside its bottom corners.
std::vector<cv::Point> objectTagPlaces(const cv::Rect& object, cv::Size box) {
  const int left = object.x + box.width / 2, right = object.x + object.width - box.width / 2;
  const int middle = object.x + object.width / 2;
  const int over = object.y - box.height / 2, under = object.y + object.height + box.height / 2;
  const int inside_top = object.y + box.height / 2 + 2;
  const int inside_bottom = object.y + object.height - box.height / 2 - 2;
  return {cv::Point(middle, over),        cv::Point(left, over),          cv::Point(right, over),
          cv::Point(left, inside_top),    cv::Point(right, inside_top),   cv::Point(middle, under),
          cv::Point(left, inside_bottom), cv::Point(right, inside_bottom)};
}

cv::Vec3b tint(const cv::Vec3b& base, const cv::Vec3b& color) {
  return cv::Vec3b(static_cast<uchar>((base[0] + 2 * color[0]) / 3),
                   static_cast<uchar>((base[1] + 2 * color[1]) / 3),
                   static_cast<uchar>((base[2] + 2 * color[2]) / 3));
}

// Whether reference-frame point (x, y) lies on placement p's footprint.
bool onFootprint(const Placement& p, const Footprint& f, double x, double y) {
  const double dx = x - p.centre.x(), dy = y - p.centre.y();
  const double along = dx * std::cos(p.yaw) + dy * std::sin(p.yaw);
  const double across = -dx * std::sin(p.yaw) + dy * std::cos(p.yaw);
  return std::fabs(along) <= f.width / 2 && std::fabs(across) <= f.depth / 2;
}

const cv::Scalar kObjectColour(0, 220, 255);    // amber boxes around objects
const cv::Vec3b kPlacementColour(80, 255, 80);  // green footprints where a new object fits

cv::Mat imageOverlay(const InputCloud& cloud, const AlignedPoints& aligned, const Result& result,
                     const std::vector<Placement>& placements, const Footprint& footprint) {
  const int w = static_cast<int>(cloud.width), h = static_cast<int>(cloud.height);
  cv::Mat image(h, w, CV_8UC3, cv::Scalar(0, 0, 0));
  float near = HUGE_VALF, far = 0;
  const bool has_color = cloud.hasColor();
  if (!has_color) {
    for (const Eigen::Vector3f& p : cloud.points) {
      if (std::isfinite(p.z())) {
        near = std::min(near, p.z());
        far = std::max(far, p.z());
      }
    }
  }
  std::vector<Eigen::Vector2d> pixel_sum(result.planes.size(), Eigen::Vector2d::Zero());
  std::vector<std::size_t> pixel_count(result.planes.size(), 0);
  for (int r = 0; r < h; ++r) {
    for (int c = 0; c < w; ++c) {
      const std::size_t i = static_cast<std::size_t>(r) * w + c;
      const float z = cloud.points[i].z();
      cv::Vec3b base(0, 0, 0);
      if (has_color) {
        const std::uint32_t rgb = cloud.rgb[i];
        base = cv::Vec3b(static_cast<uchar>(rgb), static_cast<uchar>(rgb >> 8),
                         static_cast<uchar>(rgb >> 16));
      } else if (std::isfinite(z) && far > near) {
        const auto grey = static_cast<uchar>(230 - 180 * (z - near) / (far - near));
        base = cv::Vec3b(grey, grey, grey);
      }
      const int label = result.point_labels[i];
      if (label >= 0) {
        base = tint(base, planeColor(result.planes[label].id));
        pixel_sum[label] += Eigen::Vector2d(c, r);
        ++pixel_count[label];
        // The placements' footprints, painted on the plane's own pixels they cover.
        for (const Placement& p : placements) {
          if (p.plane_index != label) continue;
          const Eigen::Vector3f q = aligned[i];
          if (onFootprint(p, footprint, q.x() + result.local_origin.x(),
                          q.y() + result.local_origin.y())) {
            base = tint(base, kPlacementColour);
          }
        }
      }
      image.at<cv::Vec3b>(r, c) = base;
    }
  }
  // Each object's pixels boxed and numbered.
  std::vector<cv::Rect> object_box(result.objects.size());
  std::vector<bool> object_seen(result.objects.size(), false);
  for (std::size_t i = 0; i < result.point_objects.size() && i < cloud.size(); ++i) {
    const int o = result.point_objects[i];
    if (o < 0) continue;
    const cv::Rect pixel(static_cast<int>(i % w), static_cast<int>(i / w), 1, 1);
    object_box[o] = object_seen[o] ? (object_box[o] | pixel) : pixel;
    object_seen[o] = true;
  }
  const double scale = std::max(0.4, w / 1100.0);
  for (std::size_t o = 0; o < object_box.size(); ++o) {
    if (object_seen[o]) cv::rectangle(image, object_box[o], kObjectColour, 2, cv::LINE_AA);
  }
  // The planes' labels first (they name the larger things), then the objects' tags, each where
  // it covers no label written before it.
  std::vector<Label> labels;
  std::vector<LabelRequest> requests;
  for (std::size_t k = 0; k < result.planes.size(); ++k) {
    if (pixel_count[k] == 0) continue;
    const Eigen::Vector2d at = pixel_sum[k] / static_cast<double>(pixel_count[k]);
    labels.push_back({planeText(result.planes[k]), scale});
    const cv::Size box = labels.back().box();
    requests.push_back(
        {box,
         planeLabelPlaces(cv::Point(static_cast<int>(at.x()), static_cast<int>(at.y())), box)});
  }
  for (std::size_t o = 0; o < object_box.size(); ++o) {
    if (!object_seen[o]) continue;
    labels.push_back({"o" + std::to_string(o), scale * 0.8});
    const cv::Size box = labels.back().box();
    requests.push_back({box, objectTagPlaces(object_box[o], box)});
  }
  const std::vector<cv::Rect> places = layoutLabels(image.size(), requests);
  for (std::size_t k = 0; k < labels.size(); ++k) drawLabel(image, labels[k], places[k]);
  return image;
}

cv::Mat topDownOverlay(const AlignedPoints& aligned, const Result& result,
                       const std::vector<Placement>& placements, const Footprint& footprint) {
  Eigen::Vector3f lo = Eigen::Vector3f::Constant(HUGE_VALF), hi = -lo;
  for (std::size_t i = 0; i < aligned.size(); ++i) {
    const Eigen::Vector3f p = aligned[i];
    if (!p.allFinite()) continue;
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  const int max_side = 1000, margin = 20;
  if (!(hi.x() >= lo.x())) return cv::Mat(max_side / 2, max_side / 2, CV_8UC3, cv::Scalar(0, 0, 0));
  const float span = std::max({hi.x() - lo.x(), hi.y() - lo.y(), 1e-3f});
  const float pixels_per_metre = (max_side - 2 * margin) / span;
  const int w = static_cast<int>((hi.x() - lo.x()) * pixels_per_metre) + 2 * margin + 1;
  const int h = static_cast<int>((hi.y() - lo.y()) * pixels_per_metre) + 2 * margin + 1;
  auto toPixel = [&](double x, double y) {  // north up: +y towards the top of the image
    return cv::Point(margin + static_cast<int>((x - lo.x()) * pixels_per_metre),
                     h - 1 - margin - static_cast<int>((y - lo.y()) * pixels_per_metre));
  };
  cv::Mat image(h, w, CV_8UC3, cv::Scalar(0, 0, 0));
  cv::Mat top_z(h, w, CV_32FC1, cv::Scalar(-HUGE_VALF));
  const float z_span = std::max(hi.z() - lo.z(), 1e-3f);
  for (std::size_t i = 0; i < aligned.size(); ++i) {
    const Eigen::Vector3f p = aligned[i];
    if (!p.allFinite()) continue;
    const cv::Point px = toPixel(p.x(), p.y());
    float& z = top_z.at<float>(px);
    if (p.z() < z) continue;  // keep what is visible from above
    z = p.z();
    const auto grey = static_cast<uchar>(60 + 170 * (p.z() - lo.z()) / z_span);
    cv::Vec3b color(grey, grey, grey);
    const int label = result.point_labels[i];
    if (label >= 0) color = tint(color, planeColor(result.planes[label].id));
    image.at<cv::Vec3b>(px) = color;
  }
  // Plane fields are absolute; the aligned points are relative to the local origin.
  const Eigen::Vector3d& o = result.local_origin;
  for (const HorizontalPlane& plane : result.planes) {
    const cv::Vec3b c = planeColor(plane.id);
    for (const auto& ring : plane.outline) {  // the true shape, holes included
      std::vector<cv::Point> polygon;
      for (const auto& v : ring) polygon.push_back(toPixel(v.x() - o.x(), v.y() - o.y()));
      cv::polylines(image, polygon, true, cv::Scalar(c[0], c[1], c[2]), 2, cv::LINE_AA);
    }
  }
  // The planes' labels where none covers another (written last, over the outlines).
  std::vector<Label> labels;
  std::vector<LabelRequest> requests;
  for (const HorizontalPlane& plane : result.planes) {
    labels.push_back({planeText(plane), 0.6});
    const cv::Size box = labels.back().box();
    requests.push_back(
        {box,
         planeLabelPlaces(toPixel(plane.centroid.x() - o.x(), plane.centroid.y() - o.y()), box)});
  }
  // Each object's footprint outlined and tagged as in the image overlay (oN, N its index).
  for (std::size_t k = 0; k < result.objects.size(); ++k) {
    std::vector<cv::Point> polygon;
    for (const auto& v : result.objects[k].footprint) {
      polygon.push_back(toPixel(v.x() - o.x(), v.y() - o.y()));
    }
    if (polygon.empty()) continue;
    cv::polylines(image, polygon, true, kObjectColour, 2, cv::LINE_AA);
    labels.push_back({"o" + std::to_string(result.objects[k].index), 0.5});
    const cv::Size box = labels.back().box();
    requests.push_back({box, objectTagPlaces(cv::boundingRect(polygon), box)});
  }
  for (const Placement& p : placements) {
    const double c = std::cos(p.yaw), s = std::sin(p.yaw);
    std::vector<cv::Point> corners;
    for (const auto& corner : {std::make_pair(-1, -1), std::make_pair(1, -1), std::make_pair(1, 1),
                               std::make_pair(-1, 1)}) {
      const double u = corner.first * footprint.width / 2, v = corner.second * footprint.depth / 2;
      corners.push_back(
          toPixel(p.centre.x() + c * u - s * v - o.x(), p.centre.y() + s * u + c * v - o.y()));
    }
    cv::fillConvexPoly(image, corners,
                       cv::Scalar(kPlacementColour[0], kPlacementColour[1], kPlacementColour[2]),
                       cv::LINE_AA);
  }
  const std::vector<cv::Rect> places = layoutLabels(image.size(), requests);
  for (std::size_t k = 0; k < labels.size(); ++k) drawLabel(image, labels[k], places[k]);
  return image;
}

}  // namespace

std::vector<cv::Rect> layoutLabels(const cv::Size& image, const std::vector<LabelRequest>& labels) {
  std::vector<cv::Rect> placed;
  placed.reserve(labels.size());
  for (const LabelRequest& label : labels) {
    // A place's rectangle, moved inside the image where the image is large enough for it.
    const auto rectAt = [&](const cv::Point& centre) {
      cv::Rect r(centre.x - label.size.width / 2, centre.y - label.size.height / 2,
                 label.size.width, label.size.height);
      r.x = std::clamp(r.x, 0, std::max(0, image.width - r.width));
      r.y = std::clamp(r.y, 0, std::max(0, image.height - r.height));
      return r;
    };
    cv::Rect best;
    long best_overlap = -1;
    for (const cv::Point& centre : label.places) {
      const cv::Rect r = rectAt(centre);
      long overlap = 0;
      for (const cv::Rect& other : placed) overlap += (r & other).area();
      if (best_overlap < 0 || overlap < best_overlap) best = r, best_overlap = overlap;
      if (overlap == 0) break;
    }
    if (best_overlap < 0) best = rectAt(cv::Point(image.width / 2, image.height / 2));
    placed.push_back(best);
  }
  return placed;
}

cv::Mat renderOverlay(const InputCloud& cloud, const AlignedPoints& aligned, const Result& result,
                      const std::vector<Placement>& placements, const Footprint& footprint) {
  // A camera's image is at most a few times wider than high; a spinning LiDAR's rings x azimuth
  // layout (16-128 rows, 1000-4000 columns) reads better from above.
  const bool image_like = cloud.height > 1 && cloud.width <= 4 * cloud.height;
  if (image_like && std::uint64_t{cloud.width} * cloud.height == cloud.size()) {
    return imageOverlay(cloud, aligned, result, placements, footprint);
  }
  return topDownOverlay(aligned, result, placements, footprint);
}

cv::Mat renderLabelsTopDown(const std::vector<Eigen::Vector3f>& points,
                            const std::vector<int>& labels, double x0, double y0, double x1,
                            double y1, int size) {
  cv::Mat image(size, size, CV_8UC3, cv::Scalar(255, 255, 255));
  // Higher points are drawn last, so a view from above shows what is on top.
  std::vector<std::size_t> order;
  for (std::size_t i = 0; i < points.size() && i < labels.size(); ++i) {
    if (points[i].allFinite()) order.push_back(i);
  }
  std::sort(order.begin(), order.end(),
            [&](std::size_t a, std::size_t b) { return points[a].z() < points[b].z(); });
  for (std::size_t i : order) {
    const int col = static_cast<int>((points[i].x() - x0) / (x1 - x0) * size);
    const int row = static_cast<int>((y1 - points[i].y()) / (y1 - y0) * size);
    if (col < 0 || row < 0 || col >= size || row >= size) continue;
    image.at<cv::Vec3b>(row, col) =
        labels[i] >= 0 ? planeColor(labels[i]) : cv::Vec3b(170, 170, 170);
  }
  return image;
}

}  // namespace tools
}  // namespace hope
