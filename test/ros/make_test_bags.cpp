// Writes the bags the rostests replay, from scenes with known answers: the synthetic demo room
// seen by a moving depth camera (with tf, an IMU with orientation, and an accelerometer-only
// IMU), the demo room seen by a camera turning in place (with tf) beside the map the same room
// seen at once gives, and the TUM freiburg1_desk frame from ../shared/data with its
// ground-truth pose as tf and as IMU orientation (skipped when the data is absent).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include <geometry_msgs/TransformStamped.h>
#include <rosbag/bag.h>
#include <sensor_msgs/Imu.h>
#include <sensor_msgs/PointCloud2.h>
#include <tf2_eigen/tf2_eigen.h>
#include <tf2_msgs/TFMessage.h>
#include <opencv2/imgcodecs.hpp>

#include "hope/depth_image.h"
#include "hope/extractor.h"
#include "hope/gravity_alignment.h"
#include "hope/surface_map.h"
#include "hope/synthetic/scene.h"
#include "hope_ros/cloud_conversion.h"

namespace {

const char* kCameraFrame = "camera_depth_optical_frame";
const char* kImuFrame = "imu_link";

sensor_msgs::PointCloud2 toMessage(const pcl::PointCloud<pcl::PointXYZ>& cloud, ros::Time stamp,
                                   const std::string& frame) {
  std_msgs::Header header;
  header.stamp = stamp;
  header.frame_id = frame;
  return hope_ros::cloudMessage(cloud, header);
}

geometry_msgs::TransformStamped transform(const Eigen::Isometry3d& parent_from_child,
                                          const std::string& parent, const std::string& child,
                                          ros::Time stamp) {
  geometry_msgs::TransformStamped t = tf2::eigenToTransform(parent_from_child);
  t.header.stamp = stamp;
  t.header.frame_id = parent;
  t.child_frame_id = child;
  return t;
}

// The IMU is mounted with x forward (optical z), y left (optical −x), z up (optical −y).
Eigen::Isometry3d cameraFromImu() {
  Eigen::Matrix3d r;
  r.col(0) = Eigen::Vector3d(0, 0, 1);
  r.col(1) = Eigen::Vector3d(-1, 0, 0);
  r.col(2) = Eigen::Vector3d(0, -1, 0);
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.linear() = r;
  return t;
}

// One frame: the cloud, its pose as tf, the IMU with orientation and without.
void writeFrame(rosbag::Bag& bag, const pcl::PointCloud<pcl::PointXYZ>& cloud,
                const Eigen::Isometry3d& world_from_camera, const std::string& world,
                ros::Time stamp) {
  bag.write("/camera/depth/points", stamp, toMessage(cloud, stamp, kCameraFrame));
  tf2_msgs::TFMessage tf;
  tf.transforms.push_back(transform(world_from_camera, world, kCameraFrame, stamp));
  bag.write("/tf", stamp, tf);
  const Eigen::Matrix3d world_from_imu = world_from_camera.rotation() * cameraFromImu().rotation();
  sensor_msgs::Imu imu;
  imu.header.stamp = stamp;
  imu.header.frame_id = kImuFrame;
  const Eigen::Quaterniond q(world_from_imu);
  imu.orientation.x = q.x();
  imu.orientation.y = q.y();
  imu.orientation.z = q.z();
  imu.orientation.w = q.w();
  const Eigen::Vector3d up = world_from_imu.transpose() * Eigen::Vector3d(0, 0, 9.81);
  imu.linear_acceleration.x = up.x();
  imu.linear_acceleration.y = up.y();
  imu.linear_acceleration.z = up.z();
  bag.write("/imu", stamp, imu);
  sensor_msgs::Imu accel_only = imu;
  accel_only.orientation = geometry_msgs::Quaternion();
  accel_only.orientation_covariance[0] = -1.0;  // "no orientation" by the sensor_msgs convention
  bag.write("/imu_accel_only", stamp, accel_only);
}

void writeStatic(rosbag::Bag& bag, ros::Time stamp) {
  tf2_msgs::TFMessage tf;
  tf.transforms.push_back(transform(cameraFromImu(), kCameraFrame, kImuFrame, stamp));
  bag.write("/tf_static", stamp, tf);
}

// The ground truth of one rendered frame, one line: "stamp height:pixels ..." for every plane
// label seen, its height the median world z of its pixels (noise included).
std::string truthLine(double stamp, const hope::synthetic::RenderedFrame& frame,
                      const pcl::PointCloud<pcl::PointXYZ>& cloud, const Eigen::Isometry3d& pose) {
  std::map<int, std::vector<double>> heights;
  for (int r = 0; r < frame.labels.rows; ++r) {
    for (int c = 0; c < frame.labels.cols; ++c) {
      const int label = frame.labels.at<int>(r, c);
      const pcl::PointXYZ& p = cloud.at(c, r);
      if (label == hope::synthetic::kNoPlane || !std::isfinite(p.z)) continue;
      heights[label].push_back((pose * Eigen::Vector3d(p.x, p.y, p.z)).z());
    }
  }
  std::ostringstream line;
  line.precision(9);
  line << stamp;
  for (auto& entry : heights) {
    std::vector<double>& z = entry.second;
    std::nth_element(z.begin(), z.begin() + z.size() / 2, z.end());
    line << " " << z[z.size() / 2] << ":" << z.size();
  }
  return line.str();
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 3) {
    std::fprintf(stderr, "usage: hope_make_test_bags OUT_DIR SHARED_DATA_DIR\n");
    return 2;
  }
  const std::string out = argv[1], shared = argv[2];
  ros::Time::init();
  {
    // Demo room: 5 frames at 5 Hz, the camera sliding 2 cm sideways per frame.
    rosbag::Bag bag(out + "/synthetic.bag", rosbag::bagmode::Write);
    std::ofstream truth(out + "/synthetic_truth.txt");
    truth << "# stamp, then height:pixels (world z, metres) of every surface the frame shows\n";
    const hope::synthetic::Scene room = hope::synthetic::demoRoom();
    writeStatic(bag, ros::Time(100.0));
    for (int f = 0; f < 5; ++f) {
      hope::synthetic::Camera camera = hope::synthetic::demoCamera();
      camera.pose.translation().y() += 0.02 * f;
      hope::synthetic::SensorNoise noise;
      noise.seed = f + 1;
      const auto frame = room.render(camera, noise);
      const auto cloud = hope::depthToCloud(frame.depth, camera.intrinsics, 1.0);
      writeFrame(bag, cloud, camera.pose, "odom", ros::Time(100.2 + 0.2 * f));
      truth << truthLine(100.2 + 0.2 * f, frame, cloud, camera.pose) << "\n";
    }
    bag.close();
  }
  {
    // The demo room seen by a robot turning in place: the camera yawing from -40° to +40° in
    // 10° steps at 5 Hz, its pose as tf into odom. Beside it, the map the same room seen at
    // once gives (every view's points in odom in one cloud, one extraction with the default
    // parameters, one map update): "height x_min y_min x_max y_max" per entry of 0.1 m² or
    // more, which the rostest's map must reproduce.
    rosbag::Bag bag(out + "/turning.bag", rosbag::bagmode::Write);
    const hope::synthetic::Scene room = hope::synthetic::demoRoom();
    writeStatic(bag, ros::Time(100.0));
    pcl::PointCloud<pcl::PointXYZ> at_once;
    int frame = 0;
    for (int degrees = -40; degrees <= 40; degrees += 10, ++frame) {
      const hope::synthetic::Camera camera =
          hope::synthetic::demoCameraTurned(degrees * M_PI / 180);
      hope::synthetic::SensorNoise noise;
      noise.seed = static_cast<std::uint32_t>(frame + 1);
      const auto cloud =
          hope::depthToCloud(room.render(camera, noise).depth, camera.intrinsics, 1.0);
      writeFrame(bag, cloud, camera.pose, "odom", ros::Time(100.2 + 0.2 * frame));
      for (const auto& p : cloud) {
        if (!std::isfinite(p.z)) continue;
        const Eigen::Vector3f w = (camera.pose * Eigen::Vector3d(p.x, p.y, p.z)).cast<float>();
        at_once.push_back(pcl::PointXYZ(w.x(), w.y(), w.z()));
      }
    }
    bag.close();
    const Eigen::Vector3d eye = hope::synthetic::demoCamera().pose.translation();
    hope::Extractor extractor;
    hope::Result whole =
        extractor.extract(at_once, hope::Orientation::identity().withViewpoint(eye));
    hope::SurfaceMap map(hope::surfaceMapOptionsFor(hope::Params()));
    map.update(whole.planes, 0.0, eye);
    std::ofstream expected(out + "/turning_map.txt");
    expected << "# the demo room seen at once: height x_min y_min x_max y_max (odom, metres) of "
                "each map entry of 0.1 m² or more\n";
    expected.precision(9);
    for (const auto& s : map.surfaces()) {
      if (s.area < 0.1) continue;
      expected << s.height << " " << s.bbox[0] << " " << s.bbox[1] << " " << s.bbox[2] << " "
               << s.bbox[3] << "\n";
    }
  }
  const std::string dir = shared + "/tum_fr1_desk";
  const cv::Mat depth = cv::imread(dir + "/1305031459.274941.png", cv::IMREAD_ANYDEPTH);
  std::ifstream gt(dir + "/groundtruth.txt");
  double t, tx, ty, tz, qx, qy, qz, qw;
  std::string line;
  bool have_pose = false;
  while (gt && std::getline(gt, line)) {
    if (line.empty() || line[0] == '#') continue;
    have_pose =
        static_cast<bool>(std::istringstream(line) >> t >> tx >> ty >> tz >> qx >> qy >> qz >> qw);
    break;
  }
  if (depth.empty() || !have_pose) {
    std::printf("hope_make_test_bags: no TUM frame under %s: tum.bag not written\n", dir.c_str());
    return 0;
  }
  rosbag::Bag bag(out + "/tum.bag", rosbag::bagmode::Write);
  const auto cloud = hope::depthToCloud(depth, hope::PinholeIntrinsics::tumFreiburg1(), 5000.0);
  const Eigen::Isometry3d pose =
      hope::Orientation::fromPose(tx, ty, tz, qx, qy, qz, qw).sensorToReference();
  writeStatic(bag, ros::Time(100.0));
  for (int f = 0; f < 4; ++f) writeFrame(bag, cloud, pose, "world", ros::Time(100.2 + 0.2 * f));
  bag.close();
  std::printf("hope_make_test_bags: wrote %s/synthetic.bag and %s/tum.bag\n", out.c_str(),
              out.c_str());
  return 0;
}
