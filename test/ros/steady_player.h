// A camera that never stops: the soak check's input. Plays a bag's point clouds and their tf
// frame after frame at a fixed rate on wall time, for as long as asked, every cloud stamped
// "now" with a rising sequence number, as a real sensor driver does. `rosbag play -l` of a
// short bag is no soak: its clock jumps back at every loop, tf2 then clears its buffer and
// the first clouds after each jump wait for transforms that have not come yet, so clouds go
// unanswered for reasons that have nothing to do with hope keeping up.
#pragma once

#include <atomic>
#include <cstdint>
#include <mutex>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include <geometry_msgs/TransformStamped.h>
#include <ros/ros.h>
#include <rosbag/bag.h>
#include <rosbag/view.h>
#include <sensor_msgs/PointCloud2.h>
#include <tf2_msgs/TFMessage.h>
#include <tf2_ros/static_transform_broadcaster.h>
#include <tf2_ros/transform_broadcaster.h>

namespace soak {

class SteadyPlayer {
 public:
  // Reads every PointCloud2 on `cloud_topic` of the bag, with the /tf transforms recorded at
  // its stamp (the camera's pose for that frame), and the bag's /tf_static. Throws
  // std::runtime_error when the bag has no cloud on the topic.
  SteadyPlayer(const std::string& bag_path, const std::string& cloud_topic) {
    rosbag::Bag bag(bag_path, rosbag::bagmode::Read);
    std::vector<tf2_msgs::TFMessage> tf_messages;
    for (const rosbag::MessageInstance& m :
         rosbag::View(bag, rosbag::TopicQuery({cloud_topic, "/tf", "/tf_static"}))) {
      if (auto cloud = m.instantiate<sensor_msgs::PointCloud2>()) {
        frames_.push_back({*cloud, {}});
      } else if (auto tf = m.instantiate<tf2_msgs::TFMessage>()) {
        auto& into = m.getTopic() == "/tf_static" ? static_transforms_
                                                  : tf_messages.emplace_back().transforms;
        into.insert(into.end(), tf->transforms.begin(), tf->transforms.end());
      }
    }
    if (frames_.empty())
      throw std::runtime_error("no PointCloud2 on " + cloud_topic + " in " + bag_path);
    for (Frame& f : frames_) {
      for (const auto& message : tf_messages) {
        for (const auto& t : message.transforms) {
          if (t.header.stamp == f.cloud.header.stamp) f.transforms.push_back(t);
        }
      }
      if (f.transforms.empty()) {
        ROS_WARN("soak player: no /tf in %s at the stamp of a cloud (%.3f): it goes out alone",
                 bag_path.c_str(), f.cloud.header.stamp.toSec());
      }
    }
    topic_ = cloud_topic;
  }
  ~SteadyPlayer() { stop(); }

  // Starts publishing at `rate_hz` on a thread of its own (once).
  void start(ros::NodeHandle& nh, double rate_hz) {
    if (thread_.joinable()) throw std::logic_error("SteadyPlayer::start called twice");
    // A deep queue: a cloud the publisher dropped while the socket was busy would reach hope
    // as a sequence gap, counted as hope's own drop.
    publisher_ = nh.advertise<sensor_msgs::PointCloud2>(topic_, 10);
    static_broadcaster_.sendTransform(static_transforms_);
    running_ = true;
    thread_ = std::thread([this, rate_hz] {
      ros::WallRate rate(rate_hz);
      for (std::uint32_t seq = 1; running_ && ros::ok(); ++seq) {
        Frame& f = frames_[seq % frames_.size()];
        const ros::Time now = ros::Time::now();
        for (auto& t : f.transforms) t.header.stamp = now;
        broadcaster_.sendTransform(f.transforms);
        f.cloud.header.stamp = now;
        f.cloud.header.seq = seq;
        publisher_.publish(f.cloud);
        {
          std::lock_guard<std::mutex> lock(progress_mutex_);
          ++progress_.published;
          progress_.last_stamp = now;
        }
        rate.sleep();
      }
    });
  }
  void stop() {
    running_ = false;
    if (thread_.joinable()) thread_.join();
  }
  // How many clouds went out so far and the stamp of the last, read together.
  struct Progress {
    std::size_t published = 0;
    ros::Time last_stamp;
  };
  Progress progress() const {
    std::lock_guard<std::mutex> lock(progress_mutex_);
    return progress_;
  }
  std::size_t numFrames() const { return frames_.size(); }

 private:
  struct Frame {
    sensor_msgs::PointCloud2 cloud;
    std::vector<geometry_msgs::TransformStamped> transforms;
  };
  std::vector<Frame> frames_;
  std::vector<geometry_msgs::TransformStamped> static_transforms_;
  std::string topic_;
  ros::Publisher publisher_;
  tf2_ros::TransformBroadcaster broadcaster_;
  tf2_ros::StaticTransformBroadcaster static_broadcaster_;
  std::atomic<bool> running_{false};
  mutable std::mutex progress_mutex_;
  Progress progress_;
  std::thread thread_;
};

}  // namespace soak
