// hope_extract and hope_synth as a user runs them: files in, files and exit codes out.
#include <sys/wait.h>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <set>
#include <sstream>

#include <pcl/io/pcd_io.h>
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

TEST(Tools, ParseNumbersSaysWhatIsWrong) {
  EXPECT_EQ(tools::parseNumbers("1 2.5 -3", 3, "x"), (std::vector<double>{1, 2.5, -3}));
  EXPECT_THROW(tools::parseNumbers("1 2", 3, "x"), std::invalid_argument);
  EXPECT_THROW(tools::parseNumbers("1 two 3", 3, "x"), std::invalid_argument);
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
