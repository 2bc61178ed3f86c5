#include "hope/tools/overlay.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

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

// White text with a dark outline, readable on any background, centred on `at`.
void drawLabel(cv::Mat& image, const std::string& text, cv::Point at, double scale) {
  int baseline = 0;
  const int thickness = std::max(1, static_cast<int>(std::lround(scale * 1.5)));
  const cv::Size size =
      cv::getTextSize(text, cv::FONT_HERSHEY_SIMPLEX, scale, thickness, &baseline);
  cv::Point origin(at.x - size.width / 2, at.y + size.height / 2);
  origin.x = std::clamp(origin.x, 2, std::max(2, image.cols - size.width - 2));
  origin.y = std::clamp(origin.y, size.height + 2, std::max(size.height + 2, image.rows - 2));
  cv::putText(image, text, origin, cv::FONT_HERSHEY_SIMPLEX, scale, cv::Scalar(0, 0, 0),
              thickness + 2, cv::LINE_AA);
  cv::putText(image, text, origin, cv::FONT_HERSHEY_SIMPLEX, scale, cv::Scalar(255, 255, 255),
              thickness, cv::LINE_AA);
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
    if (!object_seen[o]) continue;
    cv::rectangle(image, object_box[o], kObjectColour, 2, cv::LINE_AA);
    drawLabel(image, "o" + std::to_string(o),
              cv::Point(object_box[o].x + object_box[o].width / 2, object_box[o].y - 8),
              scale * 0.8);
  }
  for (std::size_t k = 0; k < result.planes.size(); ++k) {
    if (pixel_count[k] == 0) continue;
    const Eigen::Vector2d at = pixel_sum[k] / static_cast<double>(pixel_count[k]);
    drawLabel(image, planeText(result.planes[k]),
              cv::Point(static_cast<int>(at.x()), static_cast<int>(at.y())), scale);
  }
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
    drawLabel(image, planeText(plane),
              toPixel(plane.centroid.x() - o.x(), plane.centroid.y() - o.y()), 0.6);
  }
  for (const StandingObject& object : result.objects) {
    std::vector<cv::Point> polygon;
    for (const auto& v : object.footprint) polygon.push_back(toPixel(v.x() - o.x(), v.y() - o.y()));
    cv::polylines(image, polygon, true, kObjectColour, 2, cv::LINE_AA);
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
  return image;
}

}  // namespace

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
