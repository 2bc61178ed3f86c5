#include "hope/tools/sequence.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace hope {
namespace tools {

namespace fs = std::filesystem;

namespace {

// Calls `parse(line_stream, line_number)` for every non-empty, non-comment line.
template <class Parse>
void forEachDataLine(const std::string& path, Parse parse) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error("cannot read '" + path + "'");
  std::string line;
  for (int number = 1; std::getline(in, line); ++number) {
    const auto first = line.find_first_not_of(" \t\r");
    if (first == std::string::npos || line[first] == '#') continue;
    std::istringstream fields(line);
    bool parsed = false;
    try {
      parsed = parse(fields);
    } catch (const std::exception& e) {  // e.g. a zero quaternion: say where it is
      throw std::runtime_error(path + ":" + std::to_string(number) + ": " + e.what());
    }
    if (!parsed) {
      throw std::runtime_error(path + ":" + std::to_string(number) + ": cannot parse '" + line +
                               "'");
    }
  }
}

template <class Stamped>
void sortByStamp(std::vector<Stamped>& entries) {
  std::stable_sort(entries.begin(), entries.end(),
                   [](const Stamped& a, const Stamped& b) { return a.stamp < b.stamp; });
}

}  // namespace

std::vector<StampedFile> readFileList(const std::string& list_path, const std::string& base_dir) {
  std::vector<StampedFile> files;
  forEachDataLine(list_path, [&](std::istringstream& fields) {
    StampedFile f;
    if (!(fields >> f.stamp >> f.path) || !std::isfinite(f.stamp)) return false;
    f.path = (fs::path(base_dir) / f.path).string();
    files.push_back(f);
    return true;
  });
  sortByStamp(files);
  return files;
}

PinholeIntrinsics readIntrinsics(const std::string& path) {
  std::vector<PinholeIntrinsics> found;
  forEachDataLine(path, [&](std::istringstream& fields) {
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

std::vector<StampedPose> readGroundTruth(const std::string& path) {
  std::vector<StampedPose> poses;
  forEachDataLine(path, [&](std::istringstream& fields) {
    double t, tx, ty, tz, qx, qy, qz, qw;
    if (!(fields >> t >> tx >> ty >> tz >> qx >> qy >> qz >> qw)) return false;
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

std::vector<StampedVector> readAccelerometer(const std::string& path) {
  std::vector<StampedVector> samples;
  forEachDataLine(path, [&](std::istringstream& fields) {
    StampedVector s;
    if (!(fields >> s.stamp >> s.value.x() >> s.value.y() >> s.value.z())) return false;
    if (!s.value.allFinite()) return false;
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
  std::vector<StampedFile> inputs, colour;
  const bool tum = fs::exists(dir / "depth.txt");
  if (tum) {
    listing.layout = "TUM RGB-D";
    inputs = readFileList((dir / "depth.txt").string(), options.dir);
    if (fs::exists(dir / "rgb.txt")) colour = readFileList((dir / "rgb.txt").string(), options.dir);
    if (fs::exists(dir / "intrinsics.txt"))
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
  if (inputs.empty()) {
    throw std::runtime_error("no frames in '" + options.dir +
                             "' (expected depth.txt of the TUM layout, or .pcd files)");
  }

  std::vector<StampedPose> poses;
  std::vector<StampedVector> gravity;
  std::string orientation_file = options.orientation_file;
  if (options.source == OrientationSource::kGroundTruth) {
    if (orientation_file.empty()) orientation_file = (dir / "groundtruth.txt").string();
    poses = readGroundTruth(orientation_file);
  } else if (options.source == OrientationSource::kAccelerometer) {
    if (orientation_file.empty()) orientation_file = (dir / "accelerometer.txt").string();
    gravity = readAccelerometer(orientation_file);
  }

  for (const StampedFile& input : inputs) {
    SequenceFrame frame;
    frame.stamp = input.stamp;
    (tum ? frame.depth : frame.cloud) = input.path;
    if (options.source == OrientationSource::kGroundTruth) {
      const int k = nearestInTime(poses, input.stamp, options.max_time_difference);
      if (k < 0) {
        ++listing.skipped_without_orientation;
        continue;
      }
      frame.orientation = Orientation::fromTransform(poses[k].pose);
    } else if (options.source == OrientationSource::kAccelerometer) {
      const int k = nearestInTime(gravity, input.stamp, options.max_time_difference);
      if (k < 0) {
        ++listing.skipped_without_orientation;
        continue;
      }
      const Eigen::Vector3d& g = gravity[k].value;
      frame.orientation = Orientation::fromGravity(g.x(), g.y(), g.z());
    }
    const int c = nearestInTime(colour, input.stamp, options.max_time_difference);
    if (c >= 0) frame.rgb = colour[c].path;
    listing.frames.push_back(frame);
  }
  if (listing.frames.empty()) {
    throw std::runtime_error("no frame of '" + options.dir + "' has an orientation within " +
                             std::to_string(options.max_time_difference) + " s in '" +
                             orientation_file + "'");
  }
  return listing;
}

}  // namespace tools
}  // namespace hope
