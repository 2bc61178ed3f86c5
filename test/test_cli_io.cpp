// hope_extract and hope_synth as a user runs them: files in, files and exit codes out.
#include <sys/wait.h>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <limits>
#include <set>
#include <sstream>

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

}  // namespace test
}  // namespace hope
