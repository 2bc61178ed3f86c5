#include "hope/tools/sequence.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "hope/tools/cloud_file.h"
#include "hope/tools/io.h"

namespace hope {
namespace tools {

namespace fs = std::filesystem;

namespace {

// Calls `parse(fields)` for every non-empty, non-comment line of the list file `path`, read as
// sequence.h says (a regular file, bounded sizes). `parse` returns false for a line that does
// not have the form `expected`, or throws with the reason (e.g. a zero quaternion); either way
// the problem names the file and line and is thrown, or recorded in *bad_lines and skipped.
template <class Parse>
void forEachDataLine(const std::string& path, const char* expected,
                     std::vector<std::string>* bad_lines, Parse parse) {
  const std::uint64_t bytes = requireRegularFile(path);
  if (bytes > kMaxListFileBytes) {
    throw std::runtime_error("'" + path + "' has " + std::to_string(bytes) +
                             " bytes, more than a list of " + expected + " lines could (" +
                             std::to_string(kMaxListFileBytes) + " at most)");
  }
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error("cannot read '" + path + "'");
  auto problem = [&](int number, const std::string& why) {
    const std::string text = path + ":" + std::to_string(number) + ": " + why;
    if (!bad_lines) throw std::runtime_error(text);
    bad_lines->push_back(text);
  };
  std::string line;
  int number = 0;
  while (true) {
    line.clear();
    // Read one line, but never more than kMaxListLineBytes of it: a file with no newline (a
    // binary file, a 64 MB line) is refused after that much, not read whole.
    char c;
    bool got_any = false, too_long = false;
    while (in.get(c)) {
      got_any = true;
      if (c == '\n') break;
      if (line.size() >= kMaxListLineBytes) {
        too_long = true;
        break;
      }
      line += c;
    }
    if (!got_any) break;
    ++number;
    if (too_long) {
      problem(number, "line longer than " + std::to_string(kMaxListLineBytes) +
                          " bytes: not a list of \"" + expected + "\" lines ('" +
                          printableExcerpt(line.substr(0, 60)) + "...')");
      in.ignore(std::numeric_limits<std::streamsize>::max(), '\n');
      continue;
    }
    const auto first = line.find_first_not_of(" \t\r");
    if (first == std::string::npos || line[first] == '#') continue;
    std::istringstream fields(line);
    try {
      if (!parse(fields)) {
        problem(number, "expected \"" + std::string(expected) + "\", found '" +
                            printableExcerpt(line) + "'");
      }
    } catch (const std::exception& e) {  // e.g. a zero quaternion: say where it is
      problem(number, e.what());
    }
  }
}

// The rest of a line after its first fields, without surrounding blanks: a file name may hold
// spaces.
std::string restOfLine(std::istringstream& fields) {
  std::string rest;
  std::getline(fields, rest);
  const auto first = rest.find_first_not_of(" \t");
  const auto last = rest.find_last_not_of(" \t\r");
  return first == std::string::npos ? std::string() : rest.substr(first, last - first + 1);
}

// The pose at `stamp`, whose nearest pose is poses[k]: interpolated between the two poses around
// it (the rotation along the shorter arc), as tf2 does, so that a frame 4 ms from a 30 Hz pose
// gets the pose of its own time; the nearest one at either end of the poses.
Eigen::Isometry3d poseAt(const std::vector<StampedPose>& poses, int k, double stamp) {
  const int other = poses[k].stamp <= stamp ? k + 1 : k - 1;
  if (poses[k].stamp == stamp || other < 0 || other >= static_cast<int>(poses.size())) {
    return poses[k].pose;
  }
  const StampedPose& a = poses[std::min(k, other)];
  const StampedPose& b = poses[std::max(k, other)];
  const double span = b.stamp - a.stamp;
  if (!(span > 0)) return poses[k].pose;
  const double t = (stamp - a.stamp) / span;
  const Eigen::Quaterniond qa(a.pose.linear()), qb(b.pose.linear());
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() = qa.slerp(t, qb).normalized().toRotationMatrix();
  pose.translation() = (1 - t) * a.pose.translation() + t * b.pose.translation();
  return pose;
}

template <class Stamped>
void sortByStamp(std::vector<Stamped>& entries) {
  std::stable_sort(entries.begin(), entries.end(),
                   [](const Stamped& a, const Stamped& b) { return a.stamp < b.stamp; });
}

}  // namespace

std::vector<StampedFile> readFileList(const std::string& list_path, const std::string& base_dir,
                                      std::vector<std::string>* bad_lines) {
  std::vector<StampedFile> files;
  forEachDataLine(list_path, "timestamp filename", bad_lines, [&](std::istringstream& fields) {
    StampedFile f;
    if (!(fields >> f.stamp) || !std::isfinite(f.stamp)) return false;
    f.path = restOfLine(fields);
    if (f.path.empty()) return false;
    f.path = (fs::path(base_dir) / f.path).string();
    files.push_back(f);
    return true;
  });
  sortByStamp(files);
  return files;
}

PinholeIntrinsics readIntrinsics(const std::string& path) {
  std::vector<PinholeIntrinsics> found;
  forEachDataLine(path, "fx fy cx cy", nullptr, [&](std::istringstream& fields) {
    PinholeIntrinsics k;
    std::string extra;
    if (!(fields >> k.fx >> k.fy >> k.cx >> k.cy) || (fields >> extra)) return false;
    k.validate();  // finite, positive focal lengths; the file:line is added on failure
    found.push_back(k);
    return true;
  });
  if (found.size() != 1) {
    throw std::runtime_error(path + ": expected one line \"fx fy cx cy\", found " +
                             std::to_string(found.size()));
  }
  return found.front();
}

std::vector<StampedPose> readGroundTruth(const std::string& path,
                                         std::vector<std::string>* bad_lines) {
  std::vector<StampedPose> poses;
  forEachDataLine(
      path, "timestamp tx ty tz qx qy qz qw", bad_lines, [&](std::istringstream& fields) {
        double t, tx, ty, tz, qx, qy, qz, qw;
        if (!(fields >> t >> tx >> ty >> tz >> qx >> qy >> qz >> qw) || !std::isfinite(t)) {
          return false;
        }
        StampedPose p;
        p.stamp = t;
        // Validates (finite, non-zero) and normalizes the quaternion.
        p.pose = Orientation::fromPose(tx, ty, tz, qx, qy, qz, qw).sensorToReference();
        poses.push_back(p);
        return true;
      });
  sortByStamp(poses);
  return poses;
}

std::vector<StampedVector> readAccelerometer(const std::string& path,
                                             std::vector<std::string>* bad_lines) {
  std::vector<StampedVector> samples;
  forEachDataLine(path, "timestamp ax ay az", bad_lines, [&](std::istringstream& fields) {
    StampedVector s;
    if (!(fields >> s.stamp >> s.value.x() >> s.value.y() >> s.value.z())) return false;
    if (!std::isfinite(s.stamp)) return false;
    // A zero or non-finite vector is refused here, with its line, not when a frame uses it.
    Orientation::fromGravity(s.value.x(), s.value.y(), s.value.z());
    samples.push_back(s);
    return true;
  });
  sortByStamp(samples);
  return samples;
}

template <class Stamped>
int nearestInTime(const std::vector<Stamped>& entries, double stamp, double max_difference) {
  const auto after = std::lower_bound(entries.begin(), entries.end(), stamp,
                                      [](const Stamped& e, double t) { return e.stamp < t; });
  int best = -1;
  double best_difference = max_difference;
  for (auto it : {after - (after != entries.begin() ? 1 : 0), after}) {
    if (it == entries.end()) continue;
    const double difference = std::fabs(it->stamp - stamp);
    if (difference <= best_difference) {
      best_difference = difference;
      best = static_cast<int>(it - entries.begin());
    }
  }
  return best;
}

template int nearestInTime(const std::vector<StampedFile>&, double, double);
template int nearestInTime(const std::vector<StampedPose>&, double, double);
template int nearestInTime(const std::vector<StampedVector>&, double, double);

SequenceListing listSequence(const SequenceOptions& options) {
  const fs::path dir(options.dir);
  if (!fs::is_directory(dir)) throw std::runtime_error("'" + options.dir + "' is not a folder");
  if (!(options.max_time_difference >= 0)) {
    throw std::invalid_argument("the largest time difference must be >= 0 seconds");
  }
  SequenceListing listing;
  std::vector<std::string>* bad_lines = options.strict ? nullptr : &listing.bad_lines;
  // A name that is there at all, a dangling link included: its reader then says what is wrong
  // with it instead of the folder being taken for another layout.
  auto present = [](const fs::path& p) { return fs::exists(fs::symlink_status(p)); };
  std::vector<StampedFile> inputs, colour;
  const bool tum = present(dir / "depth.txt");
  if (tum) {
    listing.layout = "TUM RGB-D";
    inputs = readFileList((dir / "depth.txt").string(), options.dir, bad_lines);
    if (present(dir / "rgb.txt"))
      colour = readFileList((dir / "rgb.txt").string(), options.dir, bad_lines);
    if (present(dir / "intrinsics.txt"))
      listing.intrinsics_file = (dir / "intrinsics.txt").string();
  } else {
    listing.layout = "PCD folder";
    std::vector<fs::path> clouds;
    for (const auto& entry : fs::directory_iterator(dir)) {
      if (entry.path().extension() == ".pcd") clouds.push_back(entry.path());
    }
    std::sort(clouds.begin(), clouds.end());
    for (std::size_t i = 0; i < clouds.size(); ++i) {
      StampedFile f{static_cast<double>(i), clouds[i].string()};
      try {
        std::size_t used = 0;
        const std::string stem = clouds[i].stem().string();
        const double stamp = std::stod(stem, &used);
        if (used == stem.size() && std::isfinite(stamp)) f.stamp = stamp;
      } catch (const std::exception&) {
        // Not a number: the position in the sorted listing is the stamp.
      }
      inputs.push_back(f);
    }
    sortByStamp(inputs);
  }
  // The first skipped line, to be said with a failure it explains.
  auto firstBadLine = [&] {
    return listing.bad_lines.empty()
               ? std::string()
               : "; " + std::to_string(listing.bad_lines.size()) +
                     " line(s) could not be read, the first: " + listing.bad_lines.front();
  };
  if (inputs.empty()) {
    throw std::runtime_error("no frames in '" + options.dir + "' (" +
                             (tum ? "depth.txt lists none" + firstBadLine()
                                  : "expected depth.txt of the TUM layout, or .pcd files") +
                             ")");
  }

  std::vector<StampedPose> poses;
  std::vector<StampedVector> gravity;
  std::string orientation_file = options.orientation_file;
  if (options.source == OrientationSource::kGroundTruth) {
    if (orientation_file.empty()) orientation_file = (dir / "groundtruth.txt").string();
    poses = readGroundTruth(orientation_file, bad_lines);
  } else if (options.source == OrientationSource::kAccelerometer) {
    if (orientation_file.empty()) orientation_file = (dir / "accelerometer.txt").string();
    gravity = readAccelerometer(orientation_file, bad_lines);
  }

  for (const StampedFile& input : inputs) {
    SequenceFrame frame;
    frame.stamp = input.stamp;
    (tum ? frame.depth : frame.cloud) = input.path;
    if (options.source == OrientationSource::kGroundTruth) {
      const int k = nearestInTime(poses, input.stamp, options.max_time_difference);
      if (k < 0) {
        ++listing.skipped_without_orientation;
        listing.without_orientation.push_back(input);
        continue;
      }
      frame.orientation = Orientation::fromTransform(poseAt(poses, k, input.stamp));
    } else if (options.source == OrientationSource::kAccelerometer) {
      const int k = nearestInTime(gravity, input.stamp, options.max_time_difference);
      if (k < 0) {
        ++listing.skipped_without_orientation;
        listing.without_orientation.push_back(input);
        continue;
      }
      const Eigen::Vector3d& g = gravity[k].value;
      frame.orientation = Orientation::fromGravity(g.x(), g.y(), g.z());
      frame.specific_force = g;
    }
    const int c = nearestInTime(colour, input.stamp, options.max_time_difference);
    if (c >= 0) frame.rgb = colour[c].path;
    listing.frames.push_back(frame);
  }
  if (listing.frames.empty()) {
    std::ostringstream msg;
    msg << "no frame of '" << options.dir << "' has an orientation within "
        << options.max_time_difference << " s in '" << orientation_file << "'" << firstBadLine();
    throw std::runtime_error(msg.str());
  }
  return listing;
}

}  // namespace tools
}  // namespace hope
