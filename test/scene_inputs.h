// Inputs shared by the whole-pipeline tests (test_threads, test_reference_pipeline): the pose
// of a rendered camera as an Orientation, and the shared TUM frame with its ground-truth pose.
#pragma once

#include <fstream>
#include <optional>
#include <sstream>
#include <string>

#include <opencv2/imgcodecs.hpp>

#include "helpers.h"
#include "hope/depth_image.h"
#include "hope/gravity_alignment.h"

namespace hope {
namespace test {

inline Orientation poseOf(const Eigen::Isometry3d& pose) {
  const Eigen::Quaterniond q(pose.linear());
  const Eigen::Vector3d t = pose.translation();
  return Orientation::fromPose(t.x(), t.y(), t.z(), q.x(), q.y(), q.z(), q.w());
}

struct TumFrame {
  pcl::PointCloud<pcl::PointXYZ> cloud;
  Orientation orientation;
};

// The TUM fr1_desk depth frame of ../shared/data with the ground truth's last pose, as the
// benchmark takes them; nothing when the data is absent.
inline std::optional<TumFrame> tumFrameWithLastPose() {
  const std::string dir = sharedData("tum_fr1_desk");
  const cv::Mat depth = cv::imread(dir + "/1305031459.274941.png", cv::IMREAD_ANYDEPTH);
  std::ifstream groundtruth(dir + "/groundtruth.txt");
  if (depth.empty() || !groundtruth) return std::nullopt;
  std::string line;
  double stamp, tx, ty, tz, qx, qy, qz, qw;
  while (std::getline(groundtruth, line)) {
    if (!line.empty() && line[0] != '#') {
      std::istringstream(line) >> stamp >> tx >> ty >> tz >> qx >> qy >> qz >> qw;
    }
  }
  return TumFrame{depthToCloud(depth, PinholeIntrinsics::tumFreiburg1(), 5000),
                  Orientation::fromPose(tx, ty, tz, qx, qy, qz, qw)};
}

}  // namespace test
}  // namespace hope
