// The reference pipelines for objects on a table (PCL's classic tabletop pipeline and LCCP,
// src/evaluation/object_baselines.cpp) behind hope_extract's interface, so that one scorer
// (../shared/tools/objects_score.py, scripts/score_objects.sh) judges hope and them alike:
// the same --input, --gravity, --labels (an int32 `object` field) and --json (the sensor's
// orientation and the method's time). They propose no placements: --place is accepted and
// answered with none.
#include <cstdio>
#include <iostream>

#include "hope/evaluation/object_baselines.h"
#include "hope/gravity_alignment.h"
#include "hope/tools/cli.h"
#include "hope/tools/io.h"
#include "hope/tools/output_file.h"
#include "hope/tools/report.h"

namespace {

using hope::tools::ParsedArgs;

hope::tools::CommandLine commandLine() {
  hope::tools::CommandLine cl(
      "hope_object_baselines",
      {"--input FILE --gravity \"X Y Z\" --method tabletop|lccp [options]"},
      "Runs a reference pipeline for the objects standing on a table (PCL's classic tabletop "
      "pipeline, or LCCP on its prism points) with hope_extract's inputs and outputs, for "
      "scripts/score_objects.sh.");
  cl.section("input")
      .value("--input", "FILE", "point cloud, .pcd or .ply, in the sensor frame")
      .value("--gravity", "\"X Y Z\"",
             "accelerometer at rest in the sensor frame (points UP), as hope_extract's")
      .value("--method", "NAME", "tabletop or lccp")
      .value("--repeat", "N", "run N times and report the last run's time (default 1)");
  cl.section("output")
      .value("--labels", "FILE.pcd", "x y z, label (0) and object (int32: 0 none, k object k)")
      .value("--json", "FILE", "sensor_to_reference, no placements, the method's time")
      .value("--place", "\"W D [C]\"", "accepted for the scorer; these methods propose none")
      .flag("--quiet", "print nothing");
  return cl;
}

int run(const ParsedArgs& args) {
  for (const char* required : {"--input", "--gravity", "--method"}) {
    if (!args.values.count(required)) {
      throw std::invalid_argument(std::string(required) + " is required (see --help)");
    }
  }
  const std::string method = args.values.at("--method");
  if (method != "tabletop" && method != "lccp") {
    throw std::invalid_argument("--method '" + method + "' is not tabletop or lccp");
  }
  const std::vector<double> g =
      hope::tools::parseNumbers(args.values.at("--gravity"), 3, "--gravity");
  const hope::Orientation orientation = hope::Orientation::fromGravity(g[0], g[1], g[2]);
  const Eigen::Vector3d up = Eigen::Vector3d(g[0], g[1], g[2]).normalized();
  const int repeat = args.values.count("--repeat")
                         ? hope::tools::leadingInt("--repeat", args.values.at("--repeat"))
                         : 1;
  if (repeat < 1 || repeat > 1000) throw std::invalid_argument("--repeat must be in [1, 1000]");
  const hope::tools::InputCloud cloud = hope::tools::loadCloud(args.values.at("--input"));

  hope::evaluation::ObjectBaselineResult result;
  for (int k = 0; k < repeat; ++k) {
    result = method == "tabletop" ? hope::evaluation::tabletopObjects(cloud.points, up)
                                  : hope::evaluation::lccpObjects(cloud.points, cloud.rgb, up);
  }
  if (args.values.count("--labels")) {
    hope::tools::OutputFile labels(args.values.at("--labels"));
    hope::tools::writeLabels(labels, cloud, std::vector<std::uint32_t>(cloud.size(), 0u),
                             result.point_objects);
    labels.commit();
  }
  if (args.values.count("--json")) {
    hope::tools::OutputFile json(args.values.at("--json"));
    hope::tools::writeText(json, [&](std::ostream& out) {
      out << "{\n  \"method\": \"" << method << "\",\n  "
          << hope::tools::orientationJson(orientation.sensorToReference())
          << ",\n  \"objects\": " << result.num_objects << ",\n  \"placements\": [],\n"
          << "  \"timings_ms\": {\"objects\": " << result.ms << "}\n}\n";
    });
    json.commit();
  }
  if (!args.flag("--quiet")) {
    std::printf("%s: %d objects in %.1f ms\n", method.c_str(), result.num_objects, result.ms);
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  return hope::tools::runTool("hope_object_baselines", commandLine, run, argc, argv);
}
