#include "hope_ros/frame_gaps.h"

#include <algorithm>
#include <cmath>
#include <vector>

namespace hope_ros {

double FrameGapCounter::period() const {
  std::vector<double> sorted(intervals_.begin(), intervals_.end());
  std::nth_element(sorted.begin(), sorted.begin() + sorted.size() / 2, sorted.end());
  return sorted[sorted.size() / 2];
}

std::size_t FrameGapCounter::arrive(std::uint32_t seq, double stamp) {
  std::size_t missing = 0;
  if (have_last_) {
    const double interval = stamp - last_stamp_;
    if (seq > last_seq_) {
      missing = seq - last_seq_ - 1;
    } else if (intervals_.size() >= 3 && interval > 0) {
      const double p = period();
      // Over 1.5 periods: late frames arrive within a fraction of a period.
      if (p > 0 && interval > 1.5 * p) {
        const double frames = std::round(interval / p) - 1;
        // Bounded before the conversion: stamps can be anything.
        missing = static_cast<std::size_t>(std::min(frames, 1e9));
      }
    }
    if (interval > 0 && std::isfinite(interval)) {
      intervals_.push_back(interval);
      if (intervals_.size() > kPeriodWindow) intervals_.pop_front();
    }
  }
  have_last_ = true;
  last_seq_ = seq;
  last_stamp_ = stamp;
  dropped_ += missing;
  return missing;
}

bool RepeatedClouds::repeat(const std::string& frame_id, double stamp) {
  if (have_last_ && stamp == last_stamp_ && frame_id == last_frame_id_) {
    ++count_;
    return true;
  }
  have_last_ = true;
  last_frame_id_ = frame_id;
  last_stamp_ = stamp;
  return false;
}

void FrameGapCounter::restart() {
  have_last_ = false;
  intervals_.clear();
}

}  // namespace hope_ros
