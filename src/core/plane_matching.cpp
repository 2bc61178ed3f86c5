#include "hope/plane_matching.h"

#include <cmath>

#include <opencv2/flann.hpp>

namespace hope {

PlaneFeatures planeFeatures(const HorizontalPlane& plane) {
  PlaneFeatures f;
  f << plane.height, plane.bbox[0], plane.bbox[1], plane.bbox[2], plane.bbox[3];
  return f;
}

void normalizeJointly(std::vector<PlaneFeatures>& previous, std::vector<PlaneFeatures>& current) {
  const double count = static_cast<double>(previous.size() + current.size());
  if (count == 0) return;
  PlaneFeatures mean = PlaneFeatures::Zero();  // Eq 11
  for (const auto& f : previous) mean += f;
  for (const auto& f : current) mean += f;
  mean /= count;
  PlaneFeatures variance = PlaneFeatures::Zero();  // Eq 12, before the square root
  for (const auto& f : previous) variance += (f - mean).cwiseAbs2();
  for (const auto& f : current) variance += (f - mean).cwiseAbs2();
  variance /= count;
  PlaneFeatures inverse_std;
  for (int k = 0; k < 5; ++k) {
    const double std_dev = std::sqrt(variance[k]);
    // Spread below a nanometre is rounding noise: the feature tells the planes nothing apart.
    inverse_std[k] = std_dev > 1e-9 ? 1.0 / std_dev : 0.0;
  }
  for (auto& f : previous) f = (f - mean).cwiseProduct(inverse_std);  // Eq 13
  for (auto& f : current) f = (f - mean).cwiseProduct(inverse_std);   // Eq 14
}

std::vector<NearestNeighborMatch> matchNearestNeighbors(
    const std::vector<HorizontalPlane>& previous, const std::vector<HorizontalPlane>& current) {
  std::vector<NearestNeighborMatch> matches(current.size());
  if (previous.empty() || current.empty()) return matches;

  std::vector<PlaneFeatures> prev_features, curr_features;
  for (const auto& p : previous) prev_features.push_back(planeFeatures(p));
  for (const auto& p : current) curr_features.push_back(planeFeatures(p));
  normalizeJointly(prev_features, curr_features);

  cv::Mat prev_rows(static_cast<int>(previous.size()), 5, CV_32F);
  cv::Mat curr_rows(static_cast<int>(current.size()), 5, CV_32F);
  for (int i = 0; i < prev_rows.rows; ++i)
    for (int k = 0; k < 5; ++k) prev_rows.at<float>(i, k) = static_cast<float>(prev_features[i][k]);
  for (int j = 0; j < curr_rows.rows; ++j)
    for (int k = 0; k < 5; ++k) curr_rows.at<float>(j, k) = static_cast<float>(curr_features[j][k]);

  // An exact search: with tens of planes a linear scan is what FLANN's own autotuning picks,
  // and approximate trees would make the matching depend on random seeds.
  cv::flann::Index index(prev_rows, cv::flann::LinearIndexParams(), cvflann::FLANN_DIST_L2);
  cv::Mat nearest, squared_distances;
  index.knnSearch(curr_rows, nearest, squared_distances, 1, cv::flann::SearchParams());

  std::vector<int> winner(previous.size(), -1);
  for (int j = 0; j < curr_rows.rows; ++j) {
    const int i = nearest.at<int>(j, 0);
    matches[j].previous = i;
    matches[j].distance = std::sqrt(static_cast<double>(squared_distances.at<float>(j, 0)));
    if (winner[i] < 0 || matches[j].distance < matches[winner[i]].distance) winner[i] = j;
  }
  for (int j = 0; j < curr_rows.rows; ++j) {
    if (winner[matches[j].previous] != j) matches[j].previous = -1;
  }
  return matches;
}

}  // namespace hope
