// Frames missing from a stream, counted where they show: in the header's seq when the
// publisher numbers its messages, in the stamps when it does not. Many drivers, rosbag
// conversions (scripts/tum_to_bag.py among them) and nodes that copy a header leave seq at 0,
// and a counter that reads only seq then reports "dropped 0" while frames go missing. ROS-free.
#pragma once

#include <cstddef>
#include <cstdint>
#include <deque>
#include <string>

namespace hope_ros {

class FrameGapCounter {
 public:
  // Notes a frame that arrived (its header's seq and stamp in seconds) and returns how many
  // frames are missing between the previous arrival and this one, also added to dropped():
  // - seq advanced since the last frame: the frames it skipped;
  // - seq did not advance (0 in every message, or copied): the gap in the stamps over the
  //   stream's frame period (the median of the last kPeriodWindow intervals): an interval of
  //   about k periods means k - 1 frames missing. Nothing is counted until three intervals
  //   have set the period, and an interval under 1.5 periods (a late frame) counts nothing.
  std::size_t arrive(std::uint32_t seq, double stamp);

  // The next frame starts afresh (after a pause in the subscription, or time going back):
  // what is missing across it was not dropped.
  void restart();

  std::size_t dropped() const { return dropped_; }

  static constexpr std::size_t kPeriodWindow = 16;

 private:
  double period() const;

  bool have_last_ = false;
  std::uint32_t last_seq_ = 0;
  double last_stamp_ = 0;
  std::deque<double> intervals_;
  std::size_t dropped_ = 0;
};

// One measurement, one frame: a cloud of the frame and stamp of the last one accepted is that
// cloud delivered again, not a new frame. A transport can deliver one message twice (seen on the
// replay rostest, about one run in fifty: each depth frame reached hope twice through one
// subscription, and hope published two PlaneArrays a frame); processed again, the tracker would
// age every id twice and a recorder see the frame twice. ROS-free.
class RepeatedClouds {
 public:
  // True when `frame_id` and `stamp` (seconds) are the last accepted cloud's: a repeat, counted
  // in count(). Otherwise the cloud is accepted and remembered.
  bool repeat(const std::string& frame_id, double stamp);
  std::size_t count() const { return count_; }

 private:
  bool have_last_ = false;
  std::string last_frame_id_;
  double last_stamp_ = 0;
  std::size_t count_ = 0;
};

}  // namespace hope_ros
