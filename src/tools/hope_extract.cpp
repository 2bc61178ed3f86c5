// hope_extract: horizontal planes of one point cloud or depth image, from the command line.
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <map>
#include <stdexcept>
#include <string>
#include <vector>

#include <opencv2/imgcodecs.hpp>

#include "hope/extractor.h"
#include "hope/tools/io.h"
#include "hope/tools/overlay.h"
#include "hope/tools/report.h"

namespace {

const char* kUsage =
    R"(usage: hope_extract (--input FILE.pcd|.ply | --depth FILE.png [--rgb FILE.png]) [options]

Finds the horizontal planes of one cloud (HoPE, Dong et al. 2018).

input
  --input FILE           point cloud, .pcd or .ply, fields x y z in metres (rgb optional)
  --depth FILE           depth image: 16-bit PNG (raw units) or 32-bit float (metres)
  --rgb FILE             colour image registered to the depth image (for the overlay)
  --intrinsics "fx fy cx cy"   pinhole intrinsics in pixels (default: TUM freiburg1,
                         517.3 516.5 318.6 255.3)
  --depth-scale S        raw depth units per metre (default 5000, TUM; OpenNI: 1000)

orientation of the sensor in the reference frame (z up); at most one, default: none
  --pose "tx ty tz qx qy qz qw"   full pose, e.g. a TUM ground-truth line (heights are real)
  --quaternion "qx qy qz qw"      rotation only (normalized; zero/NaN rejected)
  --rpy "roll pitch yaw"          radians, fixed axes x, y, z (R = Rz Ry Rx)
  --gravity "gx gy gz"            accelerometer at rest in the sensor frame (points UP)

parameters
  --r-xy M               grid resolution in xy, metres (default 0.05)
  --r-z M                grid resolution in z, metres (default 0.02); slopes steeper than
                         atan(r_z / r_xy) are rejected
  --min-height M, --max-height M  keep planes inside this height band
  --min-area M2          keep planes of at least this footprint

output
  --json FILE            every plane field as JSON
  --labels FILE.pcd      x y z label per input point, same order (0 = none, k = id + 1)
  --overlay FILE.png     picture: tinted image for image-like input, top-down view otherwise
  --quiet                no table on stdout
  --help
)";

struct Options {
  std::map<std::string, std::string> values;
  bool quiet = false;
};

Options parse(int argc, char** argv) {
  static const char* kValued[] = {
      "--input",      "--depth",    "--rgb",     "--intrinsics", "--depth-scale", "--pose",
      "--quaternion", "--rpy",      "--gravity", "--r-xy",       "--r-z",         "--min-height",
      "--max-height", "--min-area", "--json",    "--labels",     "--overlay"};
  Options options;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--help" || arg == "-h") {
      std::cout << kUsage;
      std::exit(0);
    }
    if (arg == "--quiet") {
      options.quiet = true;
      continue;
    }
    bool known = false;
    for (const char* name : kValued) known = known || arg == name;
    if (!known) throw std::invalid_argument("unknown option '" + arg + "' (see --help)");
    if (i + 1 >= argc) throw std::invalid_argument(arg + " needs a value");
    options.values[arg] = argv[++i];
  }
  return options;
}

double number(const Options& o, const std::string& key, double fallback) {
  const auto it = o.values.find(key);
  if (it == o.values.end()) return fallback;
  return hope::tools::parseNumbers(it->second, 1, key.c_str())[0];
}

hope::Orientation orientation(const Options& o) {
  using hope::tools::parseNumbers;
  int given = 0;
  for (const char* key : {"--pose", "--quaternion", "--rpy", "--gravity"}) {
    given += o.values.count(key) ? 1 : 0;
  }
  if (given > 1) {
    throw std::invalid_argument("give at most one of --pose, --quaternion, --rpy, --gravity");
  }
  if (o.values.count("--pose")) {
    const auto v = parseNumbers(o.values.at("--pose"), 7, "--pose");
    return hope::Orientation::fromPose(v[0], v[1], v[2], v[3], v[4], v[5], v[6]);
  }
  if (o.values.count("--quaternion")) {
    const auto v = parseNumbers(o.values.at("--quaternion"), 4, "--quaternion");
    return hope::Orientation::fromQuaternion(v[0], v[1], v[2], v[3]);
  }
  if (o.values.count("--rpy")) {
    const auto v = parseNumbers(o.values.at("--rpy"), 3, "--rpy");
    return hope::Orientation::fromRollPitchYaw(v[0], v[1], v[2]);
  }
  if (o.values.count("--gravity")) {
    const auto v = parseNumbers(o.values.at("--gravity"), 3, "--gravity");
    return hope::Orientation::fromGravity(v[0], v[1], v[2]);
  }
  return hope::Orientation::identity();
}

int run(int argc, char** argv) {
  const Options o = parse(argc, argv);
  const bool has_input = o.values.count("--input") > 0;
  const bool has_depth = o.values.count("--depth") > 0;
  if (has_input == has_depth) {
    throw std::invalid_argument("give exactly one of --input or --depth (see --help)");
  }
  if (!has_depth && (o.values.count("--rgb") || o.values.count("--intrinsics") ||
                     o.values.count("--depth-scale"))) {
    throw std::invalid_argument("--rgb, --intrinsics and --depth-scale go with --depth");
  }

  hope::Params params;
  params.r_xy = number(o, "--r-xy", params.r_xy);
  params.r_z = number(o, "--r-z", params.r_z);
  params.min_height = number(o, "--min-height", params.min_height);
  params.max_height = number(o, "--max-height", params.max_height);
  params.min_area = number(o, "--min-area", params.min_area);
  hope::Extractor extractor(params);  // validates before any file is read
  const hope::Orientation pose = orientation(o);

  hope::tools::InputCloud input;
  if (has_input) {
    input = hope::tools::loadCloud(o.values.at("--input"));
  } else {
    hope::PinholeIntrinsics k = hope::PinholeIntrinsics::tumFreiburg1();
    if (o.values.count("--intrinsics")) {
      const auto v = hope::tools::parseNumbers(o.values.at("--intrinsics"), 4, "--intrinsics");
      k = {v[0], v[1], v[2], v[3]};
    }
    const auto rgb = o.values.count("--rgb") ? o.values.at("--rgb") : std::string();
    input =
        hope::tools::loadDepth(o.values.at("--depth"), rgb, k, number(o, "--depth-scale", 5000));
  }

  const hope::Result result = extractor.extract(input.cloud, pose);
  for (const auto& warning : result.warnings)
    std::cerr << "hope_extract: warning: " << warning << "\n";
  if (!o.quiet) hope::tools::printTable(std::cout, result);

  if (o.values.count("--json")) {
    std::ofstream out(o.values.at("--json"));
    if (!out) throw std::runtime_error("cannot write '" + o.values.at("--json") + "'");
    hope::tools::writeJson(out, result);
  }
  if (o.values.count("--labels")) {
    std::vector<std::uint32_t> labels(result.point_labels.size());
    for (std::size_t i = 0; i < labels.size(); ++i) {
      const int index = result.point_labels[i];
      labels[i] = index < 0 ? 0u : static_cast<std::uint32_t>(result.planes[index].id + 1);
    }
    hope::tools::writeLabels(o.values.at("--labels"), input.cloud, labels);
  }
  if (o.values.count("--overlay")) {
    const cv::Mat image =
        hope::tools::renderOverlay(input.cloud, input.has_color, extractor.alignedPoints(), result);
    if (!cv::imwrite(o.values.at("--overlay"), image)) {
      throw std::runtime_error("cannot write '" + o.values.at("--overlay") + "'");
    }
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    return run(argc, argv);
  } catch (const std::invalid_argument& e) {
    std::cerr << "hope_extract: error: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "hope_extract: error: " << e.what() << "\n";
    return 1;
  }
}
