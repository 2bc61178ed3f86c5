#include "hope/evaluation/table_scenes.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <stdexcept>

#include <pcl/io/pcd_io.h>
#include <Eigen/Eigenvalues>

namespace hope {
namespace evaluation {

LabelledTableScene loadLabelledTableScene(const std::string& path) {
  pcl::PointCloud<pcl::PointXYZL> labelled;
  if (pcl::io::loadPCDFile(path, labelled) != 0) {
    throw std::runtime_error("cannot read the labelled scene '" + path + "'");
  }
  LabelledTableScene scene;
  scene.name = std::filesystem::path(path).stem().string();
  scene.cloud.width = labelled.width;
  scene.cloud.height = labelled.height;
  scene.cloud.is_dense = labelled.is_dense;
  scene.cloud.resize(labelled.size());
  scene.is_table.assign(labelled.size(), 0);
  scene.labels.assign(labelled.size(), 0);
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  Eigen::Matrix3d outer = Eigen::Matrix3d::Zero();
  std::size_t count = 0;
  for (std::size_t i = 0; i < labelled.size(); ++i) {
    const pcl::PointXYZL& p = labelled[i];
    scene.cloud[i].getVector3fMap() = p.getVector3fMap();
    scene.labels[i] = p.label;
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) continue;
    if (p.label >= 1 && p.label <= 9) {
      scene.is_table[i] = 1;
      const Eigen::Vector3d q = p.getVector3fMap().cast<double>();
      sum += q;
      outer += q * q.transpose();
      ++count;
    }
  }
  if (count < 3) throw std::runtime_error("'" + path + "' has fewer than 3 table-top points");
  const Eigen::Vector3d mean = sum / static_cast<double>(count);
  const Eigen::Matrix3d covariance = outer / static_cast<double>(count) - mean * mean.transpose();
  Eigen::Vector3d up =
      Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(covariance).eigenvectors().col(0);
  if (up.dot(-mean) < 0) up = -up;  // toward the camera at the origin
  scene.orientation = Orientation::fromGravity(up.x(), up.y(), up.z());
  return scene;
}

double bestPlaneIoU(const std::vector<int>& labels, const std::vector<std::uint8_t>& truth) {
  if (labels.size() != truth.size()) {
    throw std::invalid_argument("bestPlaneIoU: labels and truth differ in size");
  }
  std::size_t truth_count = 0;
  std::map<int, std::size_t> plane_count, overlap;
  for (std::size_t i = 0; i < labels.size(); ++i) {
    truth_count += truth[i];
    if (labels[i] < 0) continue;
    ++plane_count[labels[i]];
    if (truth[i]) ++overlap[labels[i]];
  }
  double best = 0;
  for (const auto& [plane, both] : overlap) {
    const double uni = static_cast<double>(plane_count[plane] + truth_count - both);
    best = std::max(best, static_cast<double>(both) / uni);
  }
  return best;
}

}  // namespace evaluation
}  // namespace hope
