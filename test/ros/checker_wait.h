// What every rostest checker does while the bag plays: wait, on wall time, until what it
// received under its lock says it is enough.
#pragma once

#include <mutex>

#include <ros/ros.h>

namespace hope_test {

// Waits until `done()` (called under `mutex`) or `timeout` seconds; false on timeout.
template <class Done>
bool waitFor(std::mutex& mutex, Done done, double timeout) {
  const ros::WallTime until = ros::WallTime::now() + ros::WallDuration(timeout);
  while (ros::ok() && ros::WallTime::now() < until) {
    {
      std::lock_guard<std::mutex> lock(mutex);
      if (done()) return true;
    }
    ros::WallDuration(0.05).sleep();
  }
  return false;
}

}  // namespace hope_test
