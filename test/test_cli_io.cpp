// The command-line tools as a user runs them: files in, files and exit codes out, and the command
// line every tool shares (tools/cli.h).
#include <sys/wait.h>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iomanip>
#include <limits>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <pcl/io/pcd_io.h>
#include <pcl/io/ply_io.h>
#include <opencv2/imgcodecs.hpp>

#include "cli_helpers.h"
#include "helpers.h"
#include "hope/tools/io.h"
#include "hope/tools/overlay.h"

namespace hope {
namespace test {

TEST(Tools, VocColorTableMatchesPascal) {
  // BGR of VOC entries 1 (128,0,0), 2 (0,128,0), 3 (128,128,0), 15 (192,128,128).
  EXPECT_EQ(tools::vocColor(1), cv::Vec3b(0, 0, 128));
  EXPECT_EQ(tools::vocColor(2), cv::Vec3b(0, 128, 0));
  EXPECT_EQ(tools::vocColor(3), cv::Vec3b(0, 128, 128));
  EXPECT_EQ(tools::vocColor(15), cv::Vec3b(128, 128, 192));
}

// A file's width × height is the image shape only when it accounts for every point: a PCL
// cloud and a read file (InputCloud) give the same view, one row when the header disagrees.
TEST(Tools, CloudViewsKeepTheImageShapeOnlyWhenItCountsEveryPoint) {
  pcl::PointCloud<pcl::PointXYZ> pcl_cloud;
  pcl_cloud.resize(6);
  tools::InputCloud input;
  input.points.resize(6);
  for (const auto& [width, height, expect_width, expect_height] :
       std::vector<std::array<std::uint32_t, 4>>{
           {3, 2, 3, 2}, {6, 1, 6, 1}, {4, 2, 6, 1}, {0, 0, 6, 1}, {2, 2, 6, 1}}) {
    pcl_cloud.width = width;
    pcl_cloud.height = height;
    input.width = width;
    input.height = height;
    for (const PointsView& view : {PointsView::of(pcl_cloud), input.view()}) {
      EXPECT_EQ(view.count, 6u);
      EXPECT_EQ(view.width, expect_width) << width << " x " << height;
      EXPECT_EQ(view.height, expect_height) << width << " x " << height;
    }
  }
  EXPECT_EQ(packRgb({0x12, 0x34, 0x56}), 0x123456u);
}

TEST(Tools, ParseNumbersSaysWhatIsWrong) {
  EXPECT_EQ(tools::parseNumbers("1 2.5 -3", 3, "x"), (std::vector<double>{1, 2.5, -3}));
  EXPECT_THROW(tools::parseNumbers("1 2", 3, "x"), std::invalid_argument);
  EXPECT_THROW(tools::parseNumbers("1 two 3", 3, "x"), std::invalid_argument);
}

TEST_F(Cli, CloudFilesReadAsPclWritesThemInEveryEncoding) {
  // hope reads PCD and PLY itself (PCL's readers trust their headers): every encoding PCL
  // writes must come back point for point, organized shape, NaNs and colours included.
  pcl::PointCloud<pcl::PointXYZRGB> cloud;
  cloud.width = 8;
  cloud.height = 5;
  cloud.resize(40);
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    pcl::PointXYZRGB& p = cloud[i];
    p.x = 0.1f * static_cast<float>(i % 8) - 0.3f;
    p.y = 0.07f * static_cast<float>(i / 8);
    p.z = i == 13 ? std::numeric_limits<float>::quiet_NaN() : 0.75f + 0.001f * i;
    p.r = static_cast<std::uint8_t>(6 * i);
    p.g = static_cast<std::uint8_t>(255 - 6 * i);
    p.b = 77;
  }
  const std::string base = dir_ + "/c";
  ASSERT_EQ(pcl::io::savePCDFileASCII(base + "_ascii.pcd", cloud), 0);
  ASSERT_EQ(pcl::io::savePCDFileBinary(base + "_binary.pcd", cloud), 0);
  ASSERT_EQ(pcl::io::savePCDFileBinaryCompressed(base + "_compressed.pcd", cloud), 0);
  ASSERT_EQ(pcl::io::savePLYFileASCII(base + "_ascii.ply", cloud), 0);
  ASSERT_EQ(pcl::io::savePLYFileBinary(base + "_binary.ply", cloud), 0);
  for (const char* name :
       {"_ascii.pcd", "_binary.pcd", "_compressed.pcd", "_ascii.ply", "_binary.ply"}) {
    const tools::InputCloud in = tools::loadCloud(base + name);
    const bool ply = std::string(name).find("ply") != std::string::npos;
    ASSERT_EQ(in.size(), cloud.size()) << name;
    if (!ply) {  // PCL's PLY writer drops the organized shape; PCD keeps it
      EXPECT_EQ(in.width, 8u) << name;
      EXPECT_EQ(in.height, 5u) << name;
    }
    ASSERT_TRUE(in.hasColor()) << name;
    for (std::size_t i = 0; i < cloud.size(); ++i) {
      const Eigen::Vector3f& a = in.points[i];
      const pcl::PointXYZRGB& b = cloud[i];
      EXPECT_FLOAT_EQ(a.x(), b.x) << name << " point " << i;
      EXPECT_FLOAT_EQ(a.y(), b.y) << name << " point " << i;
      if (std::isnan(b.z)) {
        EXPECT_TRUE(std::isnan(a.z())) << name;
      } else {
        EXPECT_FLOAT_EQ(a.z(), b.z) << name << " point " << i;
      }
      EXPECT_EQ(int(in.rgb[i] >> 16), int(b.r)) << name << " point " << i;
      EXPECT_EQ(int((in.rgb[i] >> 8) & 0xFF), int(b.g)) << name << " point " << i;
      EXPECT_EQ(int(in.rgb[i] & 0xFF), int(b.b)) << name << " point " << i;
    }
  }
  // A big-endian binary PLY with a face element after the vertices (ignored).
  {
    std::ofstream out(base + "_be.ply", std::ios::binary);
    out << "ply\nformat binary_big_endian 1.0\ncomment by hand\nelement vertex 2\n"
           "property float x\nproperty float y\nproperty double z\nelement face 1\n"
           "property list uchar int vertex_indices\nend_header\n";
    auto bigEndian = [&](const void* value, int size) {
      const char* bytes = static_cast<const char*>(value);
      for (int b = size - 1; b >= 0; --b) out.put(bytes[b]);
    };
    for (int v = 0; v < 2; ++v) {
      const float x = 1.5f + v, y = -2.25f;
      const double z = 0.125 * v;
      bigEndian(&x, 4);
      bigEndian(&y, 4);
      bigEndian(&z, 8);
    }
  }
  const tools::InputCloud be = tools::loadCloud(base + "_be.ply");
  ASSERT_EQ(be.size(), 2u);
  EXPECT_FALSE(be.hasColor());
  EXPECT_FLOAT_EQ(be.points[1].x(), 2.5f);
  EXPECT_FLOAT_EQ(be.points[1].y(), -2.25f);
  EXPECT_FLOAT_EQ(be.points[1].z(), 0.125f);
}

TEST_F(Cli, SynthThenExtractFindsThePlanesWritesJsonLabelsAndOverlay) {
  ASSERT_EQ(std::system((std::string(HOPE_SYNTH_BIN) + " --out " + dir_ + " >/dev/null").c_str()),
            0);
  const std::string pose = slurp(dir_ + "/pose.txt");
  const CliRun r = run("--depth " + dir_ + "/depth.png --rgb " + dir_ + "/rgb.png --pose \"" +
                       pose.substr(0, pose.find('\n')) + "\" --json " + dir_ + "/p.json --labels " +
                       dir_ + "/l.pcd --overlay " + dir_ + "/o.png");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("height_m"), std::string::npos) << r.output;
  // --repeat: the same planes from every call, the cold and steady timings printed; two
  // threads and one give the same JSON.
  const CliRun repeated =
      run("--depth " + dir_ + "/depth.png --pose \"" + pose.substr(0, pose.find('\n')) +
          "\" --repeat 3 --threads 2 --json " + dir_ + "/p2.json");
  ASSERT_EQ(repeated.exit_code, 0) << repeated.output;
  EXPECT_NE(repeated.output.find("cold first call "), std::string::npos) << repeated.output;
  EXPECT_NE(repeated.output.find("(median of 2 more calls)"), std::string::npos) << repeated.output;
  const CliRun single =
      run("--depth " + dir_ + "/depth.png --pose \"" + pose.substr(0, pose.find('\n')) +
          "\" --threads 1 --quiet --json " + dir_ + "/p1.json");
  ASSERT_EQ(single.exit_code, 0) << single.output;
  auto withoutTimings = [](std::string json) {
    return json.substr(0, json.find("\"timings_ms\""));
  };
  EXPECT_EQ(withoutTimings(slurp(dir_ + "/p1.json")), withoutTimings(slurp(dir_ + "/p2.json")));
  EXPECT_GT(slurp(dir_ + "/p1.json").find("\"timings_ms\""), 100u);

  const std::string json = slurp(dir_ + "/p.json");
  for (const char* key : {"\"planes\"", "\"id\"", "\"height\"", "\"bbox\"", "\"centroid\"",
                          "\"normal\"", "\"area\"", "\"num_points\"", "\"hull\""}) {
    EXPECT_NE(json.find(key), std::string::npos) << key;
  }
  // The table top (0.75 m) is among the planes.
  bool table = false;
  for (std::size_t at = json.find("\"height\": "); at != std::string::npos;
       at = json.find("\"height\": ", at + 1)) {
    table = table || std::fabs(std::stod(json.substr(at + 10)) - 0.75) < 0.01;
  }
  EXPECT_TRUE(table) << json.substr(0, 2000);

  pcl::PointCloud<pcl::PointXYZL> labels;
  ASSERT_EQ(pcl::io::loadPCDFile(dir_ + "/l.pcd", labels), 0);
  EXPECT_EQ(labels.width, 640u);
  EXPECT_EQ(labels.height, 480u);
  std::size_t labelled = 0;
  for (const auto& p : labels) labelled += p.label > 0 ? 1 : 0;
  EXPECT_GT(labelled, 100000u);

  const cv::Mat overlay = cv::imread(dir_ + "/o.png");
  EXPECT_EQ(overlay.cols, 640);
  EXPECT_EQ(overlay.rows, 480);
}

// The three numbers after `"key": [` in `json` (from the position `from` on).
Eigen::Vector3d vectorAfter(const std::string& json, const std::string& key, std::size_t from = 0) {
  const std::size_t at = json.find("\"" + key + "\": [", from);
  if (at == std::string::npos) return Eigen::Vector3d::Constant(NAN);
  std::istringstream in(json.substr(at + key.size() + 5));
  Eigen::Vector3d v;
  char comma;
  in >> v.x() >> comma >> v.y() >> comma >> v.z();
  return v;
}

double degreesBetween(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return std::acos(std::clamp(a.normalized().dot(b.normalized()), -1.0, 1.0)) * 180.0 / M_PI;
}

// The world's +z in the frame of a camera at pose "tx ty tz qx qy qz qw".
Eigen::Vector3d upOfPose(const std::string& pose) {
  std::istringstream in(pose);
  double t[3], q[4];
  in >> t[0] >> t[1] >> t[2] >> q[0] >> q[1] >> q[2] >> q[3];
  return Eigen::Quaterniond(q[3], q[0], q[1], q[2]).toRotationMatrix().transpose() *
         Eigen::Vector3d::UnitZ();
}

// No IMU, no pose: --level finds up from the demo room itself (heights then relative to the
// camera, 1.5 m above the floor); with a gravity vector 3° off it corrects it; with nothing at
// all hope_extract says the cloud looks like a camera's and names the options; a wall alone is
// refused; a sequence without poses is levelled frame by frame.
TEST_F(Cli, LevelFindsUpRefinesAGivenOneAndSpeaksUpWhenNoneIsGiven) {
  ASSERT_EQ(std::system((std::string(HOPE_SYNTH_BIN) + " --out " + dir_ + " >/dev/null").c_str()),
            0);
  const std::string pose = slurp(dir_ + "/pose.txt");
  const Eigen::Vector3d truth = upOfPose(pose);
  const double camera_height = std::stod(pose.substr(pose.find(' ', pose.find(' ') + 1)));
  const std::string depth = "--depth " + dir_ + "/depth.png";

  const CliRun levelled = run(depth + " --level --json " + dir_ + "/l.json");
  ASSERT_EQ(levelled.exit_code, 0) << levelled.output;
  EXPECT_NE(levelled.output.find("levelled from the scene"), std::string::npos);
  const std::string json = slurp(dir_ + "/l.json");
  EXPECT_LT(degreesBetween(vectorAfter(json, "up_in_sensor"), truth), 0.5) << json.substr(0, 600);
  EXPECT_NE(json.find("\"levelling\": {\"source\": \"scene\""), std::string::npos);
  EXPECT_NE(json.find("\"sensor_to_reference\": [["), std::string::npos);
  bool table = false;  // 0.75 m above the floor
  for (std::size_t at = json.find("\"height\": "); at != std::string::npos;
       at = json.find("\"height\": ", at + 1)) {
    table = table || std::fabs(std::stod(json.substr(at + 10)) - (0.75 - camera_height)) < 0.02;
  }
  EXPECT_TRUE(table) << json.substr(0, 2000);

  const Eigen::Vector3d axis = truth.cross(Eigen::Vector3d(0.3, 0.5, 0.8)).normalized();
  const Eigen::Vector3d off = Eigen::AngleAxisd(3 * M_PI / 180, axis) * truth;
  std::ostringstream gravity;
  gravity << std::setprecision(9) << off.x() << " " << off.y() << " " << off.z();
  const CliRun refined = run(depth + " --gravity \"" + gravity.str() +
                             "\" --level --quiet --json " + dir_ + "/r.json");
  ASSERT_EQ(refined.exit_code, 0) << refined.output;
  const std::string refined_json = slurp(dir_ + "/r.json");
  EXPECT_NE(refined_json.find("\"source\": \"refined\""), std::string::npos);
  EXPECT_NE(refined_json.find("\"applied\": true"), std::string::npos);
  EXPECT_LT(degreesBetween(vectorAfter(refined_json, "up_in_sensor"), truth), 0.5);
  // Without --level the given gravity is what the JSON reports.
  ASSERT_EQ(run(depth + " --gravity \"" + gravity.str() + "\" --quiet --json " + dir_ + "/g.json")
                .exit_code,
            0);
  EXPECT_LT(degreesBetween(vectorAfter(slurp(dir_ + "/g.json"), "up_in_sensor"), off), 1e-4);

  const CliRun unoriented = run(depth + " --quiet");
  ASSERT_EQ(unoriented.exit_code, 0) << unoriented.output;
  EXPECT_NE(unoriented.output.find("optical frame"), std::string::npos) << unoriented.output;
  EXPECT_NE(unoriented.output.find("--level"), std::string::npos) << unoriented.output;

  const CliRun bound_alone = run(depth + " --level-bound 3");
  EXPECT_EQ(bound_alone.exit_code, 2) << bound_alone.output;
  EXPECT_NE(bound_alone.output.find("--level-bound goes with --level"), std::string::npos);

  pcl::PointCloud<pcl::PointXYZ> wall;  // 3 m in front of the camera, nothing else
  for (double u = -1; u < 1; u += 0.01) {
    for (double v = -1; v < 1; v += 0.01) wall.push_back(pcl::PointXYZ(u, v, 3.0));
  }
  ASSERT_EQ(pcl::io::savePCDFileBinary(dir_ + "/wall.pcd", wall), 0);
  const CliRun refused = run("--input " + dir_ + "/wall.pcd --level");
  EXPECT_NE(refused.exit_code, 0) << refused.output;
  EXPECT_NE(refused.output.find("cannot find up from the scene"), std::string::npos);
  EXPECT_NE(refused.output.find("--gravity"), std::string::npos) << refused.output;

  // Up from each frame's scene (the folder's poses not read), against the poses it was made with:
  // unsmoothed, since this camera rolls and pitches quickly and the default smoothing lags it by
  // 2-4° (it pays on real data, where each frame's estimate is noisier: docs/quality.md).
  const std::string seq = dir_ + "/seq";
  ASSERT_EQ(runTool(HOPE_SYNTH_BIN, "--out " + seq + " --sequence rpy --frames 4").exit_code, 0);
  std::map<std::string, Eigen::Vector3d> true_up;  // by stamp, as written
  std::istringstream groundtruth(slurp(seq + "/groundtruth.txt"));
  for (std::string line; std::getline(groundtruth, line);) {
    if (line.empty() || line[0] == '#') continue;
    true_up[line.substr(0, line.find(' '))] = upOfPose(line.substr(line.find(' ') + 1));
  }
  const CliRun sequence =
      run("--sequence " + seq + " --orientation-source scene --level-smoothing 1 --quiet --jsonl " +
          dir_ + "/s.jsonl");
  ASSERT_EQ(sequence.exit_code, 0) << sequence.output;
  EXPECT_NE(sequence.output.find("levelling from the scene"), std::string::npos) << sequence.output;
  // Every line's levelling source and up (within 0.5° of the pose it was made with); the count.
  auto checkLines = [&](const std::string& path, const std::string& source) {
    std::istringstream lines(slurp(path));
    int frames = 0;
    for (std::string line; std::getline(lines, line); ++frames) {
      EXPECT_NE(line.find("\"levelling\": {\"source\": \"" + source + "\""), std::string::npos)
          << line;
      const double stamp = std::stod(line.substr(line.find(':') + 1));
      const auto nearest = std::min_element(true_up.begin(), true_up.end(), [&](auto& a, auto& b) {
        return std::fabs(std::stod(a.first) - stamp) < std::fabs(std::stod(b.first) - stamp);
      });
      EXPECT_LT(degreesBetween(vectorAfter(line, "up_in_sensor"), nearest->second), 0.5) << line;
    }
    return frames;
  };
  EXPECT_EQ(checkLines(dir_ + "/s.jsonl", "scene"), 4);
  // With its poses and --level: each frame's pose refined (exact poses: nothing to correct).
  const CliRun refined_sequence =
      run("--sequence " + seq + " --groundtruth " + seq +
          "/groundtruth.txt --level --quiet --jsonl " + dir_ + "/r.jsonl");
  ASSERT_EQ(refined_sequence.exit_code, 0) << refined_sequence.output;
  EXPECT_NE(refined_sequence.output.find("refinement from the scene"), std::string::npos);
  EXPECT_EQ(checkLines(dir_ + "/r.jsonl", "refined"), 4);
}

// A sequence's summary line gives the objects a frame, median and most, as the JSON lines hold
// them; a synthetic room that holds things has some in every frame.
TEST_F(Cli, SequenceSummaryGivesTheObjectsAFrame) {
  const std::string seq = dir_ + "/seq";
  ASSERT_EQ(runTool(HOPE_SYNTH_BIN, "--out " + seq + " --sequence pan --frames 4").exit_code, 0);
  const CliRun sequence = run("--sequence " + seq + " --quiet --jsonl " + dir_ + "/s.jsonl");
  ASSERT_EQ(sequence.exit_code, 0) << sequence.output;
  std::vector<int> objects_per_line;
  std::istringstream lines(slurp(dir_ + "/s.jsonl"));
  for (std::string line; std::getline(lines, line);) {
    int count = 0;  // "plane_id" is an object's field alone
    for (std::size_t at = line.find("\"plane_id\""); at != std::string::npos;
         at = line.find("\"plane_id\"", at + 1)) {
      ++count;
    }
    objects_per_line.push_back(count);
  }
  ASSERT_EQ(objects_per_line.size(), 4u);
  std::sort(objects_per_line.begin(), objects_per_line.end());
  EXPECT_GT(objects_per_line.front(), 0);
  std::ostringstream expected;
  expected << "objects/frame median " << 0.5 * (objects_per_line[1] + objects_per_line[2])
           << " (max " << objects_per_line.back() << ")";
  EXPECT_NE(sequence.output.find(expected.str()), std::string::npos)
      << expected.str() << " in " << sequence.output;
  // Without objects asked for (no --jsonl, no --overlay-dir) the line does not claim any.
  const CliRun planes_only = run("--sequence " + seq + " --quiet");
  ASSERT_EQ(planes_only.exit_code, 0) << planes_only.output;
  EXPECT_EQ(planes_only.output.find("objects/frame"), std::string::npos) << planes_only.output;
}

// The LiDAR path a new user takes: hope_synth writes a VLP-16 scan as a driver would publish it
// (x y z intensity ring label, rings × azimuth); hope_extract with the sensor at the origin
// finds the road 1.8 m below it as one plane reaching past 20 m, and --no-bridge does not.
TEST_F(Cli, SynthLidarScanThenExtractFindsTheRoadFarOut) {
  const CliRun synth = runTool(HOPE_SYNTH_BIN, "--out " + dir_ + " --lidar vlp16 --scene street");
  ASSERT_EQ(synth.exit_code, 0) << synth.output;
  pcl::PointCloud<pcl::PointXYZ> scan;
  ASSERT_EQ(pcl::io::loadPCDFile(dir_ + "/scan.pcd", scan), 0);
  EXPECT_EQ(scan.height, 16u);
  EXPECT_EQ(scan.width, 1800u);
  // The road's extent along x in each run's JSON: the bbox of the plane at -1.8 m.
  auto roadReach = [&](const std::string& extra) {
    const CliRun r = run("--input " + dir_ + "/scan.pcd --viewpoint \"0 0 0\" --r-xy 0.3 " +
                         "--r-z 0.1 --quiet --json " + dir_ + "/p.json" + extra);
    EXPECT_EQ(r.exit_code, 0) << r.output;
    const std::string json = slurp(dir_ + "/p.json");
    double reach = 0;
    for (std::size_t at = json.find("\"height\": "); at != std::string::npos;
         at = json.find("\"height\": ", at + 1)) {
      if (std::fabs(std::stod(json.substr(at + 10)) + 1.8) > 0.03) continue;
      const std::size_t bbox = json.find("\"bbox\": [", at);
      double x_min = 0, y_min = 0, x_max = 0, y_max = 0;
      std::sscanf(json.c_str() + bbox + 9, "%lf, %lf, %lf, %lf", &x_min, &y_min, &x_max, &y_max);
      reach = std::max(reach, std::max(-x_min, x_max));
    }
    return reach;
  };
  EXPECT_GT(roadReach(""), 20.0);
  EXPECT_LT(roadReach(" --no-bridge"), 10.0);
}

TEST_F(Cli, UnorganizedPcdGivesATopDownOverlayAndOneLabelPerPoint) {
  LabeledCloud cloud;
  addSheet(cloud, 0, 0, 1, 1, 0.0, 0.01, 0);
  addSheet(cloud, 0.2, 0.2, 0.6, 0.6, 0.3, 0.01, 1);
  ASSERT_EQ(pcl::io::savePCDFileBinary(dir_ + "/in.pcd", cloud.cloud), 0);
  const CliRun r = run("--input " + dir_ + "/in.pcd --labels " + dir_ + "/l.pcd --overlay " + dir_ +
                       "/o.png --quiet");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  pcl::PointCloud<pcl::PointXYZL> labels;
  ASSERT_EQ(pcl::io::loadPCDFile(dir_ + "/l.pcd", labels), 0);
  ASSERT_EQ(labels.size(), cloud.cloud.size());
  std::set<std::uint32_t> seen;
  for (const auto& p : labels) seen.insert(p.label);
  EXPECT_EQ(seen, (std::set<std::uint32_t>{1, 2}));
  EXPECT_FALSE(cv::imread(dir_ + "/o.png").empty());
}

// OpenCV's image codecs (and GDAL with them) are loaded only by a run that reads or writes an
// image: the dynamic loader's own log (LD_DEBUG=files) lists every library a run opens.
TEST_F(Cli, ImageCodecsAreLoadedOnlyForImages) {
  LabeledCloud cloud;
  addSheet(cloud, 0, 0, 1, 1, 0.0, 0.01, 0);
  ASSERT_EQ(pcl::io::savePCDFileBinary(dir_ + "/in.pcd", cloud.cloud), 0);
  auto opened = [&](const std::string& args) {
    const CliRun r = runTool("LD_DEBUG=files " HOPE_EXTRACT_BIN, args + " --quiet");
    EXPECT_EQ(r.exit_code, 0) << r.output.substr(0, 2000);
    return r.output;
  };
  const std::string cloud_only = opened("--input " + dir_ + "/in.pcd");
  EXPECT_NE(cloud_only.find("libhope_core.so"), std::string::npos);  // the log is there
  EXPECT_EQ(cloud_only.find("libopencv_imgcodecs"), std::string::npos);
  EXPECT_EQ(cloud_only.find("libhope_image_codecs"), std::string::npos);
  const std::string with_overlay =
      opened("--input " + dir_ + "/in.pcd --overlay " + dir_ + "/o.png");
  EXPECT_NE(with_overlay.find("libhope_image_codecs.so"), std::string::npos);
  EXPECT_NE(with_overlay.find("libopencv_imgcodecs"), std::string::npos);
  EXPECT_FALSE(cv::imread(dir_ + "/o.png").empty());
}

TEST_F(Cli, ErrorsGoToStderrWithTheirExitCode) {
  CliRun r = run("");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(
      r.output.find("hope_extract: error: give exactly one of --input, --depth or --sequence"),
      std::string::npos)
      << r.output;
  r = run("--input /nonexistent.pcd");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.output.find("hope_extract: error: '/nonexistent.pcd' cannot be opened: No such file "
                          "or directory"),
            std::string::npos)
      << r.output;
  r = run("--input x.pcd --r-xy -1");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.output.find("r_xy"), std::string::npos) << r.output;
  r = run("--input x.pcd --quaternion \"0 0 0 0\"");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.output.find("zero length"), std::string::npos) << r.output;
  r = run("--input x.pcd --rpy \"1 2\"");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.output.find("--rpy: expected 3 numbers, got 2"), std::string::npos) << r.output;
  r = run("--input x.pcd --threads 1.5");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.output.find("--threads must be a whole number in [0, 1024]"), std::string::npos)
      << r.output;
  r = run("--input x.pcd --repeat 0");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.output.find("--repeat must be a whole number in [1, 100000]"), std::string::npos)
      << r.output;
  r = run("--bogus");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.output.find("unknown option '--bogus'"), std::string::npos) << r.output;

  // A PCD without a z field.
  std::ofstream(dir_ + "/xy.pcd")
      << "VERSION .7\nFIELDS x y\nSIZE 4 4\nTYPE F F\nCOUNT 1 1\n"
         "WIDTH 1\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS 1\nDATA ascii\n1 2\n";
  r = run("--input " + dir_ + "/xy.pcd");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.output.find("xy.pcd' has no 'z' field; hope needs x, y, z"), std::string::npos)
      << r.output;
  // A PCD whose x is an integer: not metres.
  std::ofstream(dir_ + "/int.pcd")
      << "VERSION .7\nFIELDS x y z\nSIZE 4 4 4\nTYPE I F F\nCOUNT 1 1 1\n"
         "WIDTH 1\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS 1\nDATA ascii\n1 2 3\n";
  r = run("--input " + dir_ + "/int.pcd");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.output.find("int.pcd' field 'x' is not floating point"), std::string::npos)
      << r.output;
}

// ---- The command line every tool shares (tools/cli.h): the same rules and the same help.

namespace {

// The parts of a help text, as CommandLine::help lays them out.
struct HelpLayout {
  std::vector<std::string> usage;             // the usage lines
  std::string description;                    // the paragraph below them
  std::vector<std::string> sections;          // the sections' titles, in order
  std::vector<std::string> synopses;          // every option entry ("--r-xy M", "-h, --help")
  std::set<std::size_t> explanation_columns;  // where the options' explanations start
  std::size_t widest_line = 0;                // in characters on a terminal
};

std::size_t terminalColumns(const std::string& line) {
  std::size_t count = 0;
  for (const char c : line) count += (static_cast<unsigned char>(c) & 0xC0) != 0x80;
  return count;
}

std::size_t indentOf(const std::string& line) {
  const std::size_t first = line.find_first_not_of(' ');
  return first == std::string::npos ? line.size() : first;
}

// Reads `help` into its parts, failing the test where it strays from the common layout:
// "usage: TOOL …" (its other lines indented), a blank line, a one-paragraph description, then
// each section after a blank line: "title:", an optional note indented by two, and option
// entries "  --name PLACEHOLDER  explanation" (the explanation on the next line when the
// synopsis is long), the explanation's other lines indented to its column.
HelpLayout layoutOf(const std::string& tool, const std::string& help) {
  HelpLayout layout;
  std::vector<std::string> lines;
  std::istringstream in(help);
  for (std::string line; std::getline(in, line);) {
    lines.push_back(line);
    layout.widest_line = std::max(layout.widest_line, terminalColumns(line));
  }
  std::size_t i = 0;
  auto at = [&](std::size_t k) { return k < lines.size() ? lines[k] : std::string("<end>"); };
  EXPECT_EQ(at(0).rfind("usage: " + tool + " ", 0), 0u) << tool << ": " << at(0);
  layout.usage.push_back(at(i++));
  while (i < lines.size() && indentOf(lines[i]) >= 7 && !lines[i].empty()) {
    layout.usage.push_back(lines[i++]);
  }
  EXPECT_EQ(at(i++), "") << tool << ": no blank line after the usage";
  for (; i < lines.size() && !lines[i].empty(); ++i) {
    EXPECT_EQ(indentOf(lines[i]), 0u) << tool << ": " << lines[i];
    layout.description += lines[i] + " ";
  }
  EXPECT_FALSE(layout.description.empty()) << tool;
  while (i < lines.size()) {
    EXPECT_EQ(at(i++), "") << tool << ": no blank line before a section";
    const std::string title = at(i++);
    EXPECT_EQ(indentOf(title), 0u) << tool << ": " << title;
    EXPECT_EQ(title.back(), ':') << tool << ": " << title;
    layout.sections.push_back(title);
    bool in_option = false;
    std::size_t explanation_column = 0;
    for (; i < lines.size() && !lines[i].empty(); ++i) {
      const std::string& line = lines[i];
      const std::size_t indent = indentOf(line);
      if (indent == 2 && line[2] == '-') {  // an option entry
        in_option = true;
        const std::size_t gap = line.find("  ", 2);
        layout.synopses.push_back(line.substr(2, gap == std::string::npos ? gap : gap - 2));
        if (gap != std::string::npos) {
          explanation_column = line.find_first_not_of(' ', gap);
        } else {  // the explanation on the next line
          ++i;
          explanation_column = indentOf(at(i));
          EXPECT_GT(at(i).size(), explanation_column) << tool << ": " << line;
        }
        layout.explanation_columns.insert(explanation_column);
      } else if (in_option) {  // an explanation's next line
        EXPECT_EQ(indent, explanation_column) << tool << ": " << line;
      } else {  // the section's note, before its options
        EXPECT_GE(indent, 2u) << tool << ": " << line;
      }
    }
  }
  return layout;
}

// A JSON report without its timings, which differ from run to run.
std::string withoutTimings(const std::string& json) {
  return json.substr(0, json.find("\"timings_ms\""));
}

std::size_t planeCount(const std::string& json) {
  std::size_t count = 0;
  for (std::size_t at = json.find("\"height\": "); at != std::string::npos;
       at = json.find("\"height\": ", at + 1)) {
    ++count;
  }
  return count;
}

// hope_track_eval's Markdown without the tracking times (the last cell of the per-sequence
// rows), which differ from run to run.
std::string withoutTrackingTimes(const std::string& markdown) {
  std::istringstream in(markdown);
  std::string out;
  for (std::string line; std::getline(in, line);) {
    if (line.rfind("| ", 0) == 0 && line.find("µs") == std::string::npos &&
        std::count(line.begin(), line.end(), '|') == 13) {
      line = line.substr(0, line.rfind('|', line.size() - 2));
    }
    out += line + "\n";
  }
  return out;
}

// A floor at 0 and a table top at 0.3 m (z up), 1 cm apart.
LabeledCloud floorAndTable() {
  LabeledCloud cloud;
  addSheet(cloud, 0, 0, 1, 1, 0.0, 0.01, 0);
  addSheet(cloud, 0.2, 0.2, 0.6, 0.6, 0.3, 0.01, 1);
  return cloud;
}

const char* const kTools[] = {"hope_extract", "hope_synth", "hope_eval", "hope_track_eval"};

}  // namespace

TEST_F(Cli, EveryToolPrintsItsHelpInTheCommonLayout) {
  // A few entries each tool must list, as "name PLACEHOLDER".
  const std::map<std::string, std::vector<std::string>> expected = {
      {"hope_extract", {"--input FILE", "--r-xy M", "--no-merge", "--threads N", "--quiet"}},
      {"hope_synth", {"--out DIR", "--frames N", "--unorganized", "--room-scan SPACING"}},
      {"hope_eval", {"--out DIR", "--data DIR", "--quick"}},
      {"hope_track_eval", {"--frames N", "--r-xy M", "--sequences \"pan rpy ...\""}}};
  std::set<std::size_t> explanation_columns;
  for (const char* tool : kTools) {
    const CliRun help = runTool(toolBinary(tool), "--help");
    ASSERT_EQ(help.exit_code, 0) << tool << ": " << help.output;
    const CliRun short_help = runTool(toolBinary(tool), "-h");
    EXPECT_EQ(short_help.exit_code, 0) << tool;
    EXPECT_EQ(short_help.output, help.output) << tool;
    // Help wins over anything else on the command line.
    const CliRun help_and_more = runTool(toolBinary(tool), "--bogus --help");
    EXPECT_EQ(help_and_more.exit_code, 0) << tool << ": " << help_and_more.output;
    EXPECT_EQ(help_and_more.output, help.output) << tool;

    const HelpLayout layout = layoutOf(tool, help.output);
    EXPECT_LE(layout.widest_line, 80u) << tool;
    ASSERT_GE(layout.sections.size(), 2u) << tool;
    EXPECT_EQ(layout.sections.back(), "general:") << tool;
    ASSERT_FALSE(layout.synopses.empty()) << tool;
    EXPECT_EQ(layout.synopses.back(), "-h, --help") << tool;
    for (const std::string& synopsis : expected.at(tool)) {
      EXPECT_EQ(std::count(layout.synopses.begin(), layout.synopses.end(), synopsis), 1)
          << tool << " lists no '" << synopsis << "' in\n"
          << help.output;
    }
    EXPECT_EQ(layout.explanation_columns.size(), 1u) << tool << ":\n" << help.output;
    explanation_columns.insert(layout.explanation_columns.begin(),
                               layout.explanation_columns.end());
  }
  EXPECT_EQ(explanation_columns.size(), 1u) << "the tools' explanations start at different columns";
}

TEST_F(Cli, EveryToolRefusesUnknownRepeatedAndMissingOptionsNamingThem) {
  struct Case {
    const char* tool;
    std::string repeated_value, repeated_name, repeated_flag, flag_name, last_valued;
  };
  const std::string out = dir_ + "/out";
  const Case cases[] = {
      {"hope_extract", "--input x.pcd --r-xy 0.3 --r-xy=0.2", "--r-xy",
       "--input x.pcd --quiet --quiet", "--quiet", "--json"},
      {"hope_synth", "--out " + out + " --out=" + out + "2", "--out",
       "--out " + out + " --unorganized --unorganized", "--unorganized", "--lidar"},
      {"hope_eval", "--out " + out + " --out " + out, "--out", "--out " + out + " --quick --quick",
       "--quick", "--data"},
      {"hope_track_eval", "--frames 2 --frames 3", "--frames", "", "", "--markdown"}};
  for (const Case& c : cases) {
    const std::string bin = toolBinary(c.tool);
    const std::string error = std::string(c.tool) + ": error: ";
    auto expectError = [&](const std::string& args, const std::string& message) {
      const CliRun r = runTool(bin, args);
      EXPECT_EQ(r.exit_code, 2) << c.tool << " " << args << ": " << r.output;
      // One line: "<tool>: error: <message>…(see --help)".
      EXPECT_EQ(r.output.find(error + message), 0u) << c.tool << " " << args << ": " << r.output;
      EXPECT_EQ(r.output.find('\n'), r.output.size() - 1)
          << c.tool << " " << args << ": " << r.output;
      EXPECT_EQ(r.output.rfind(" (see --help)\n"), r.output.size() - 14)
          << c.tool << " " << args << ": " << r.output;
    };
    expectError(c.repeated_value, c.repeated_name + " given more than once");
    if (!c.repeated_flag.empty()) {
      expectError(c.repeated_flag, c.flag_name + " given more than once");
      expectError(c.flag_name + "=yes", c.flag_name + " takes no value");
    }
    expectError("--bogus", "unknown option '--bogus'");
    expectError("--bogus=1", "unknown option '--bogus'");
    expectError("-x", "unknown option '-x'");
    expectError(c.last_valued, c.last_valued + " needs a value");
    expectError(c.last_valued + "=", c.last_valued + " needs a value");
    // An option where a value belongs: its value was forgotten.
    expectError(c.last_valued + " --bogus", c.last_valued + " needs a value, not '--bogus'");
    expectError("stray", "unexpected argument 'stray': options start with --");
  }
  // Nothing was written by any of the refused runs.
  EXPECT_EQ(std::system(("test -z \"$(ls -A " + dir_ + ")\"").c_str()), 0);
}

TEST_F(Cli, ExtractTakesOptionEqualsValueAsOptionSpaceValue) {
  ASSERT_EQ(pcl::io::savePCDFileBinary(dir_ + "/in.pcd", floorAndTable().cloud), 0);
  const std::string in = dir_ + "/in.pcd";
  const CliRun spaced = run("--input " + in + " --r-xy 0.1 --r-z 0.04 --min-area 0.1 --json " +
                            dir_ + "/spaced.json --quiet");
  ASSERT_EQ(spaced.exit_code, 0) << spaced.output;
  const CliRun joined =
      run("--input=" + in + " --r-xy=0.1 --r-z=0.04 --min-area=0.1 --json=" + dir_ +
          "/joined.json --quiet");
  ASSERT_EQ(joined.exit_code, 0) << joined.output;
  const std::string json = slurp(dir_ + "/spaced.json");
  EXPECT_EQ(planeCount(json), 2u) << json;
  EXPECT_EQ(withoutTimings(slurp(dir_ + "/joined.json")), withoutTimings(json));
  // The values were used: the default grid gives other planes.
  ASSERT_EQ(run("--input=" + in + " --json=" + dir_ + "/default.json --quiet").exit_code, 0);
  EXPECT_NE(withoutTimings(slurp(dir_ + "/default.json")), withoutTimings(json));
}

TEST_F(Cli, ExtractTakesValuesThatStartWithAMinus) {
  ASSERT_EQ(pcl::io::savePCDFileBinary(dir_ + "/in.pcd", floorAndTable().cloud), 0);
  const std::string in = "--input " + dir_ + "/in.pcd --quiet --json " + dir_;
  auto planesWith = [&](const std::string& name, const std::string& args) {
    const CliRun r = run(in + "/" + name + " " + args);
    EXPECT_EQ(r.exit_code, 0) << args << ": " << r.output;
    return withoutTimings(slurp(dir_ + "/" + name));
  };
  // A height band below the floor holds no plane; one reaching below it holds both.
  EXPECT_EQ(planeCount(planesWith("below.json", "--min-height -1 --max-height -0.5")), 0u);
  EXPECT_EQ(planeCount(planesWith("band.json", "--min-height -1 --max-height=0.5")), 2u);
  EXPECT_EQ(planesWith("band2.json", "--min-height=-1 --max-height 0.5"),
            planesWith("band.json", "--min-height -1 --max-height=0.5"));
  // Rotations: a roll of -0.1 rad, given either way, is not one of +0.1 rad.
  const std::string minus = planesWith("minus.json", "--rpy \"-0.1 0 0\"");
  EXPECT_EQ(planeCount(minus), 2u);
  EXPECT_EQ(planesWith("minus2.json", "\"--rpy=-0.1 0 0\""), minus);
  EXPECT_NE(planesWith("plus.json", "--rpy \"0.1 0 0\""), minus);

  // The same floor and table seen by a sensor whose up is its -x axis: found with the
  // accelerometer reading "-9.8 0 0", at their heights.
  LabeledCloud sideways = floorAndTable();
  for (auto& p : sideways.cloud) p = pcl::PointXYZ(-p.z, p.y, p.x);
  ASSERT_EQ(pcl::io::savePCDFileBinary(dir_ + "/sideways.pcd", sideways.cloud), 0);
  const CliRun r = run("--input " + dir_ + "/sideways.pcd --gravity \"-9.8 0 0\" --quiet --json " +
                       dir_ + "/sideways.json");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const std::string json = slurp(dir_ + "/sideways.json");
  ASSERT_EQ(planeCount(json), 2u) << json;
  std::vector<double> heights;
  for (std::size_t at = json.find("\"height\": "); at != std::string::npos;
       at = json.find("\"height\": ", at + 1)) {
    heights.push_back(std::stod(json.substr(at + 10)));
  }
  std::sort(heights.begin(), heights.end());
  EXPECT_NEAR(heights[0], 0.0, 0.005);
  EXPECT_NEAR(heights[1], 0.3, 0.005);
}

TEST_F(Cli, SynthTakesOptionEqualsValueAndNegativeNumbers) {
  const std::string synth = toolBinary("hope_synth");
  const CliRun spaced = runTool(synth, "--out " + dir_ + "/spaced --room-scan 0.25");
  ASSERT_EQ(spaced.exit_code, 0) << spaced.output;
  const CliRun joined = runTool(synth, "--out=" + dir_ + "/joined --room-scan=0.25");
  ASSERT_EQ(joined.exit_code, 0) << joined.output;
  const std::string scan = slurp(dir_ + "/spaced/room_scan.pcd");
  EXPECT_GT(scan.size(), 1000u);
  EXPECT_EQ(slurp(dir_ + "/joined/room_scan.pcd"), scan);
  // A LiDAR scan with every option joined to its value.
  const CliRun lidar =
      runTool(synth, "--out=" + dir_ + "/lidar --lidar=vlp16 --scene=room --unorganized");
  ASSERT_EQ(lidar.exit_code, 0) << lidar.output;
  EXPECT_NE(lidar.output.find("vlp16 (16 rings"), std::string::npos) << lidar.output;
  EXPECT_NE(lidar.output.find(", room, "), std::string::npos) << lidar.output;
  EXPECT_EQ(lidar.output.find("(organized)"), std::string::npos) << lidar.output;
  // A negative spacing reaches the check of its range, in either form.
  for (const char* spacing : {"--room-scan -0.5", "--room-scan=-0.5"}) {
    const CliRun r = runTool(synth, "--out " + dir_ + "/negative " + spacing);
    EXPECT_EQ(r.exit_code, 2) << r.output;
    EXPECT_NE(r.output.find("hope_synth: error: --room-scan spacing must be in [0.001, 1] metres"),
              std::string::npos)
        << r.output;
  }
}

TEST_F(Cli, TrackEvalTakesOptionEqualsValueAndNegativeNumbers) {
  const std::string track_eval = toolBinary("hope_track_eval");
  const CliRun spaced = runTool(track_eval, "--frames 2 --width 160 --sequences pan --r-xy 0.1 " +
                                                std::string("--markdown ") + dir_ + "/spaced.md");
  ASSERT_EQ(spaced.exit_code, 0) << spaced.output;
  const CliRun joined = runTool(track_eval, "--frames=2 --width=160 --sequences=pan --r-xy=0.1 " +
                                                std::string("--markdown=") + dir_ + "/joined.md");
  ASSERT_EQ(joined.exit_code, 0) << joined.output;
  const std::string markdown = slurp(dir_ + "/spaced.md");
  EXPECT_NE(markdown.find("Sequences (2 frames at 30 Hz, 160 px wide, r_xy 0.1 m, r_z 0.02 m)"),
            std::string::npos)
      << markdown;
  EXPECT_NE(markdown.find("| pan | gravity | improved + merge |"), std::string::npos);
  EXPECT_EQ(markdown.find("| rpy |"), std::string::npos);
  EXPECT_EQ(withoutTrackingTimes(slurp(dir_ + "/joined.md")), withoutTrackingTimes(markdown));
  // A negative resolution reaches the extractor's check, in either form.
  for (const char* r_xy : {"--r-xy -1", "--r-xy=-1"}) {
    const CliRun r = runTool(track_eval, std::string("--frames 1 --sequences pan ") + r_xy);
    EXPECT_EQ(r.exit_code, 2) << r.output;
    EXPECT_NE(r.output.find("hope_track_eval: error: parameter r_xy = -1 is out of range"),
              std::string::npos)
        << r.output;
  }
}

// hope_eval's run takes minutes; where it puts its report shows how it read --out: into a
// path under a regular file, which cannot be made.
TEST_F(Cli, EvalTakesOptionEqualsValueAndValuesStartingWithAMinus) {
  std::ofstream(dir_ + "/blocked") << "a file, not a folder\n";
  const std::string eval = toolBinary("hope_eval");
  const CliRun spaced = runTool(eval, "--quick --out " + dir_ + "/blocked/report");
  EXPECT_EQ(spaced.exit_code, 1) << spaced.output;
  EXPECT_NE(spaced.output.find("hope_eval: error: "), std::string::npos) << spaced.output;
  EXPECT_NE(spaced.output.find(dir_ + "/blocked/report/evaluation"), std::string::npos)
      << spaced.output;
  const CliRun joined = runTool(eval, "--quick --out=" + dir_ + "/blocked/report");
  EXPECT_EQ(joined.exit_code, 1) << joined.output;
  EXPECT_EQ(joined.output, spaced.output);
  // A relative folder named "-blocked" (run in dir_), given as the next argument.
  std::ofstream(dir_ + "/-blocked") << "a file, not a folder\n";
  const CliRun minus = runTool("cd " + dir_ + " && " + eval, "--quick --out -blocked");
  EXPECT_EQ(minus.exit_code, 1) << minus.output;
  EXPECT_NE(minus.output.find("[-blocked/evaluation]"), std::string::npos) << minus.output;
}

}  // namespace test
}  // namespace hope
