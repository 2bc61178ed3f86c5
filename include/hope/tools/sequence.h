// Reading sequences in the TUM RGB-D folder layout (depth.txt, rgb.txt, groundtruth.txt,
// accelerometer.txt and the images), or folders of PCD files, frame by frame with the
// orientation nearest in time.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "hope/depth_image.h"
#include "hope/gravity_alignment.h"

namespace hope {
namespace tools {

struct StampedFile {
  double stamp = 0;
  std::string path;  // as found (absolute, or relative to the working directory)
};

// Every reader below opens its file as the frames are opened: a regular file only (a FIFO,
// directory or device such as /dev/zero is refused, never read or waited on), at most
// kMaxListFileBytes, lines of at most kMaxListLineBytes. A line that cannot be used is an
// error naming the file, the line, the form expected and (escaped, cut) what was found:
// thrown as std::runtime_error when `bad_lines` is null, otherwise appended to *bad_lines and
// skipped, so that one corrupt line does not lose a recording.
constexpr std::uint64_t kMaxListFileBytes = 256ull << 20;
constexpr std::size_t kMaxListLineBytes = 4096;

// A TUM list file (rgb.txt, depth.txt): "timestamp filename" per line, '#' comments. The
// filename is the rest of the line (it may hold spaces), relative to `base_dir`.
std::vector<StampedFile> readFileList(const std::string& list_path, const std::string& base_dir,
                                      std::vector<std::string>* bad_lines = nullptr);

struct StampedPose {
  double stamp = 0;
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
};
// TUM groundtruth.txt: "timestamp tx ty tz qx qy qz qw" (pose of the optical frame in the
// world, z up). A frame takes the pose of its own time, interpolated between the two around it
// (as tf does), when the nearest is within the largest time difference. Quaternions are normalized;
// a zero or non-finite one is an error.
std::vector<StampedPose> readGroundTruth(const std::string& path,
                                         std::vector<std::string>* bad_lines = nullptr);

struct StampedVector {
  double stamp = 0;
  Eigen::Vector3d value = Eigen::Vector3d::Zero();
};
// TUM accelerometer.txt: "timestamp ax ay az" in m/s², read as the specific force in the
// camera optical frame (pointing up at rest). A zero or non-finite vector is a bad line.
std::vector<StampedVector> readAccelerometer(const std::string& path,
                                             std::vector<std::string>* bad_lines = nullptr);

// A folder's own camera: "fx fy cx cy" in pixels on one data line ('#' comments), the
// intrinsics.txt that hope_synth --sequence writes and recorded folders carry beside
// depth.txt. Throws std::runtime_error naming the file (and line) when it cannot be read,
// holds no such line or more than one, or the values are not valid intrinsics.
PinholeIntrinsics readIntrinsics(const std::string& path);

// Index of the entry nearest in time to `stamp` (entries sorted by stamp), or -1 when the
// nearest is further than `max_difference` seconds.
template <class Stamped>
int nearestInTime(const std::vector<Stamped>& entries, double stamp, double max_difference);

struct SequenceFrame {
  double stamp = 0;
  std::string depth;  // depth image, or
  std::string cloud;  // point cloud file
  std::string rgb;    // colour image nearest in time (TUM layout), may be empty
  Orientation orientation = Orientation::identity();
  // The accelerometer's sample (m/s², pointing up at rest) with OrientationSource::kAccelerometer.
  Eigen::Vector3d specific_force = Eigen::Vector3d::Zero();
};

enum class OrientationSource { kNone, kGroundTruth, kAccelerometer };

struct SequenceOptions {
  std::string dir;
  OrientationSource source = OrientationSource::kGroundTruth;
  std::string orientation_file;  // default: DIR/groundtruth.txt or DIR/accelerometer.txt
  // Largest time difference between a frame and its orientation or colour image. TUM's own
  // association tool uses 0.02 s.
  double max_time_difference = 0.02;
  // Stop at the first bad line of a list or orientation file instead of skipping it.
  bool strict = false;
};

struct SequenceListing {
  std::vector<SequenceFrame> frames;  // the frames with an orientation, by stamp
  std::size_t skipped_without_orientation = 0;
  std::vector<StampedFile> without_orientation;  // the frames skipped for it, by stamp
  std::string layout;                            // "TUM RGB-D" or "PCD folder"
  // DIR/intrinsics.txt when the TUM layout has one, else empty.
  std::string intrinsics_file;
  // Lines of the list and orientation files skipped (not strict): "file:line: reason".
  std::vector<std::string> bad_lines;
};

// Lists the frames of DIR: the TUM layout when DIR/depth.txt exists, otherwise the .pcd files
// in DIR sorted by name, stamped by their numeric file name (or their position when the name
// is not a number). Frames with no orientation within max_time_difference are skipped and
// counted. Throws std::runtime_error for a missing folder, no frames, unreadable files, or
// (strict) a bad line.
SequenceListing listSequence(const SequenceOptions& options);

}  // namespace tools
}  // namespace hope
