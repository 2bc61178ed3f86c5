// Sequences from the command line: the TUM RGB-D folder layout and PCD folders, orientation
// by timestamp from ground truth or the accelerometer, ids kept across frames.
#include <cmath>
#include <map>
#include <set>
#include <vector>

#include <pcl/io/pcd_io.h>

#include "cli_helpers.h"
#include "helpers.h"
#include "hope/tools/sequence.h"

namespace hope {
namespace test {

namespace {

struct JsonPlane {
  int id;
  double height;
  long points;
};

// The planes of each line of a --jsonl file: id and height of every plane object.
std::vector<std::vector<JsonPlane>> readJsonLines(const std::string& path) {
  std::vector<std::vector<JsonPlane>> frames;
  std::istringstream lines(slurp(path));
  // Plain scanning, not std::regex: libstdc++'s matcher recurses per character and overflows
  // the stack on lines as long as a frame's outlines.
  const std::string id_key = "{\"id\": ", height_key = "\"height\": ",
                    points_key = "\"num_points\": ";
  for (std::string line; std::getline(lines, line);) {
    EXPECT_EQ(line.rfind("{\"stamp\": ", 0), 0u) << line.substr(0, 80);
    std::vector<JsonPlane> planes;
    for (std::size_t at = line.find(id_key); at != std::string::npos;
         at = line.find(id_key, at + 1)) {
      const std::size_t height = line.find(height_key, at), points = line.find(points_key, at);
      if (height == std::string::npos || points == std::string::npos) break;
      planes.push_back({std::stoi(line.substr(at + id_key.size())),
                        std::stod(line.substr(height + height_key.size())),
                        std::stol(line.substr(points + points_key.size()))});
    }
    frames.push_back(planes);
  }
  return frames;
}

// The id of the largest plane within 3 cm of `height`, or -1.
int idNear(const std::vector<JsonPlane>& planes, double height) {
  int id = -1;
  long largest = 0;
  for (const auto& p : planes) {
    if (std::fabs(p.height - height) < 0.03 && p.points > largest) {
      largest = p.points;
      id = p.id;
    }
  }
  return id;
}

class Sequence : public Cli {
 protected:
  // A 6-frame occlusion sequence, 320 px wide, in the TUM layout.
  void makeTumSequence() {
    const CliRun synth = runTool(
        HOPE_SYNTH_BIN, "--out " + dir_ + "/seq --sequence occlusion --frames 6 --width 320");
    ASSERT_EQ(synth.exit_code, 0) << synth.output;
    intrinsics_ = "--intrinsics \"" + slurp(dir_ + "/seq/intrinsics.txt") + "\"";
    intrinsics_.erase(std::remove(intrinsics_.begin(), intrinsics_.end(), '\n'), intrinsics_.end());
  }
  std::string intrinsics_;
};

}  // namespace

TEST(SequenceFiles, ReadsTumListsAndPairsByNearestTime) {
  char tmpl[] = "/tmp/hope_seqfiles_XXXXXX";
  const std::string dir = mkdtemp(tmpl);
  std::ofstream(dir + "/depth.txt") << "# comment\n\n2.0 depth/b.png\n1.0 depth/a.png\n";
  const auto files = tools::readFileList(dir + "/depth.txt", dir);
  ASSERT_EQ(files.size(), 2u);
  EXPECT_EQ(files[0].stamp, 1.0) << "sorted by time";
  EXPECT_EQ(files[0].path, dir + "/depth/a.png");
  EXPECT_EQ(tools::nearestInTime(files, 1.4, 0.5), 0);
  EXPECT_EQ(tools::nearestInTime(files, 1.6, 0.5), 1);
  EXPECT_EQ(tools::nearestInTime(files, 3.0, 0.5), -1) << "too far from any entry";
  std::ofstream(dir + "/gt.txt") << "1.0 0 0 1.5 0 0 0 2\n";  // non-unit quaternion: normalized
  const auto poses = tools::readGroundTruth(dir + "/gt.txt");
  ASSERT_EQ(poses.size(), 1u);
  EXPECT_TRUE(poses[0].pose.linear().isIdentity(1e-12));
  EXPECT_EQ(poses[0].pose.translation().z(), 1.5);
  std::ofstream(dir + "/bad.txt") << "1.0 0 0 1.5 0 0 0 0\n";
  try {
    tools::readGroundTruth(dir + "/bad.txt");
    ADD_FAILURE() << "a zero quaternion must be an error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("bad.txt:1"), std::string::npos) << e.what();
  }
  std::ofstream(dir + "/short.txt") << "1.0 0 0\n";
  try {
    tools::readAccelerometer(dir + "/short.txt");
    ADD_FAILURE() << "a short line must be an error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("short.txt:1"), std::string::npos) << e.what();
  }
  std::system(("rm -rf " + dir).c_str());
}

TEST_F(Sequence, TumFolderWithGroundTruthKeepsTheTableIdAtItsRealHeight) {
  makeTumSequence();
  const CliRun r = run("--sequence " + dir_ + "/seq " + intrinsics_ + " --jsonl " + dir_ +
                       "/out.jsonl --overlay-dir " + dir_ + "/overlays");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("6 frame(s)"), std::string::npos) << r.output;
  const auto frames = readJsonLines(dir_ + "/out.jsonl");
  ASSERT_EQ(frames.size(), 6u);
  const int table = idNear(frames[0], 0.75), floor = idNear(frames[0], 0.0);
  ASSERT_GE(table, 0) << "no table at 0.75 m in the first frame";
  ASSERT_GE(floor, 0);
  for (std::size_t f = 0; f < frames.size(); ++f) {
    EXPECT_EQ(idNear(frames[f], 0.75), table) << "frame " << f;
    EXPECT_EQ(idNear(frames[f], 0.0), floor) << "frame " << f;
    std::set<int> ids;
    for (const auto& p : frames[f])
      EXPECT_TRUE(ids.insert(p.id).second) << "id twice in frame " << f;
  }
  EXPECT_TRUE(std::ifstream(dir_ + "/overlays/1300000000.000000.png").good());
}

// A folder whose camera is not TUM's (320 pixels wide: half the focal length) carries its
// intrinsics.txt, and --sequence reads it without being told: the table at its true 0.75 m in
// every frame, and the run says where the intrinsics came from. Without the file it says that
// it fell back on TUM freiburg1's.
TEST_F(Sequence, TheFoldersOwnIntrinsicsAreReadAndNamed) {
  makeTumSequence();
  CliRun r = run("--sequence " + dir_ + "/seq --jsonl " + dir_ + "/out.jsonl");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(
      r.output.find("intrinsics 258.65 258.25 159.3 127.65 from " + dir_ + "/seq/intrinsics.txt"),
      std::string::npos)
      << r.output;
  const auto frames = readJsonLines(dir_ + "/out.jsonl");
  ASSERT_EQ(frames.size(), 6u);
  for (std::size_t f = 0; f < frames.size(); ++f) {
    EXPECT_GE(idNear(frames[f], 0.75), 0) << "no table at 0.75 m in frame " << f;
  }
  // --intrinsics wins, and the run says so.
  r = run("--sequence " + dir_ + "/seq " + intrinsics_ + " --quiet");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(r.output.find("intrinsics 517.3"), std::string::npos) << r.output;
  r = run("--sequence " + dir_ + "/seq " + intrinsics_);
  EXPECT_NE(r.output.find("from --intrinsics (not " + dir_ + "/seq/intrinsics.txt)"),
            std::string::npos)
      << r.output;
  // Without intrinsics.txt the run says it falls back to TUM freiburg1's, and since those are a
  // 640 x 480 camera's (principal point 318.6, 255.3), every 320 x 240 frame is refused with
  // the reason rather than turned into wrong planes.
  std::remove((dir_ + "/seq/intrinsics.txt").c_str());
  r = run("--sequence " + dir_ + "/seq");
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("intrinsics 517.3 516.5 318.6 255.3 from TUM freiburg1's"),
            std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find("do not fit the 320 x 240 image: the principal point is outside"),
            std::string::npos)
      << r.output;
}

// A malformed intrinsics.txt stops the run with the file named, rather than planes computed
// with a camera nobody gave.
TEST_F(Sequence, AMalformedIntrinsicsFileIsAnErrorNamingIt) {
  makeTumSequence();
  for (const char* bad : {"585 585 320\n", "585 585 320 240\n585 585 320 240\n", "0 585 320 240\n",
                          "585 585 320 240 7\n"}) {
    std::ofstream(dir_ + "/seq/intrinsics.txt") << bad;
    const CliRun r = run("--sequence " + dir_ + "/seq");
    EXPECT_EQ(r.exit_code, 1) << bad << r.output;
    EXPECT_NE(r.output.find(dir_ + "/seq/intrinsics.txt"), std::string::npos) << bad << r.output;
  }
}

TEST_F(Sequence, AccelerometerGivesHeightsRelativeToTheCamera) {
  makeTumSequence();
  const CliRun r = run("--sequence " + dir_ + "/seq " + intrinsics_ + " --accelerometer " + dir_ +
                       "/seq/accelerometer.txt --tracking paper --jsonl " + dir_ + "/acc.jsonl");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto frames = readJsonLines(dir_ + "/acc.jsonl");
  ASSERT_EQ(frames.size(), 6u);
  // The camera is 1.5 m above the floor: floor at -1.5, table at -0.75 relative to it.
  EXPECT_GE(idNear(frames[0], -1.5), 0) << r.output;
  EXPECT_GE(idNear(frames[0], -0.75), 0) << r.output;
}

TEST_F(Sequence, FramesWithoutAnOrientationAreSkippedAndCounted) {
  makeTumSequence();
  // Keep only the first three poses.
  std::istringstream all(slurp(dir_ + "/seq/groundtruth.txt"));
  std::ofstream partial(dir_ + "/partial.txt");
  int kept = 0;
  for (std::string line; std::getline(all, line);) {
    if (line[0] == '#' || kept++ < 3) partial << line << "\n";
  }
  partial.close();
  const CliRun r = run("--sequence " + dir_ + "/seq " + intrinsics_ + " --groundtruth " + dir_ +
                       "/partial.txt --quiet --jsonl " + dir_ + "/p.jsonl");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("skipped 3 frame(s): no orientation within 0.02 s"), std::string::npos)
      << r.output;
  // Every frame has its line, in time order: the three with a pose, then the three skipped.
  std::istringstream jsonl(slurp(dir_ + "/p.jsonl"));
  std::vector<std::string> lines;
  for (std::string line; std::getline(jsonl, line);) lines.push_back(line);
  ASSERT_EQ(lines.size(), 6u);
  for (std::size_t i = 0; i < lines.size(); ++i) {
    EXPECT_EQ(lines[i].find("\"skipped\": \"no orientation within 0.02 s\"") != std::string::npos,
              i >= 3)
        << lines[i].substr(0, 200);
  }
}

// Poses whose position never changes are an orientation only: the scene's odometry finds the
// position by default, and the map is kept in its frame; asking for the map on the poses anyway
// is warned about.
TEST_F(Sequence, PosesThatNeverMoveGetTheOdometryNotTheMapOnThePoses) {
  makeTumSequence();
  std::istringstream all(slurp(dir_ + "/seq/groundtruth.txt"));
  std::ofstream turned(dir_ + "/rotation_only.txt");
  for (std::string line; std::getline(all, line);) {
    std::istringstream fields(line);
    std::string stamp, tx, ty, tz, rest;
    if (line[0] == '#' || !(fields >> stamp >> tx >> ty >> tz)) continue;
    std::getline(fields, rest);
    turned << stamp << " 0 0 0" << rest << "\n";
  }
  turned.close();
  const std::string base = "--sequence " + dir_ + "/seq " + intrinsics_ + " --groundtruth " + dir_ +
                           "/rotation_only.txt --quiet";
  CliRun r = run(base);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("(TUM RGB-D, odometry tracking)"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("position never changes"), std::string::npos) << r.output;
  r = run(base + " --tracking map");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("(TUM RGB-D, map tracking)"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("warning: the poses' position never changes"), std::string::npos)
      << r.output;
  // The folder's own poses move: the map, with no word about it.
  r = run("--sequence " + dir_ + "/seq " + intrinsics_ + " --quiet");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("(TUM RGB-D, map tracking)"), std::string::npos) << r.output;
  EXPECT_EQ(r.output.find("position never changes"), std::string::npos) << r.output;
}

// --every N keeps the 1st, the N+1-th, ... frame of the folder (depth.txt's order): 6 frames at
// --every 4 are the 1st and the 5th, by their stamps, and the table keeps its id across them.
TEST_F(Sequence, EveryNthFrameOnly) {
  makeTumSequence();
  std::vector<std::string> stamps;
  std::istringstream listing(slurp(dir_ + "/seq/depth.txt"));
  for (std::string line; std::getline(listing, line);) {
    if (!line.empty() && line[0] != '#') stamps.push_back(line.substr(0, line.find(' ')));
  }
  ASSERT_EQ(stamps.size(), 6u);
  const CliRun r = run("--sequence " + dir_ + "/seq " + intrinsics_ + " --every 4 --jsonl " + dir_ +
                       "/out.jsonl --quiet");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("2 frame(s)"), std::string::npos) << r.output;
  std::istringstream lines(slurp(dir_ + "/out.jsonl"));
  std::vector<std::string> written;
  for (std::string line; std::getline(lines, line);) {
    const std::string key = "{\"stamp\": ";
    ASSERT_EQ(line.rfind(key, 0), 0u);
    written.push_back(line.substr(key.size(), line.find(',') - key.size()));
  }
  ASSERT_EQ(written.size(), 2u);
  EXPECT_DOUBLE_EQ(std::stod(written[0]), std::stod(stamps[0]));
  EXPECT_DOUBLE_EQ(std::stod(written[1]), std::stod(stamps[4]));
  const auto frames = readJsonLines(dir_ + "/out.jsonl");
  ASSERT_GE(idNear(frames[0], 0.75), 0);
  EXPECT_EQ(idNear(frames[1], 0.75), idNear(frames[0], 0.75));
  const CliRun bad = run("--sequence " + dir_ + "/seq " + intrinsics_ + " --every 0");
  EXPECT_NE(bad.exit_code, 0);
  EXPECT_NE(bad.output.find("--every must be a whole number"), std::string::npos) << bad.output;
}

TEST_F(Sequence, PcdFolderNamedByTimestamp) {
  // Three clouds of a table top at 0.7 m and a floor, named by stamp, poses by stamp.
  std::ofstream gt(dir_ + "/groundtruth.txt");
  for (int f = 0; f < 3; ++f) {
    LabeledCloud scene;
    addSheet(scene, 0, 0, 1, 1, 0.7, 0.01, 1);
    addSheet(scene, -2, -2, 2, -1, 0.0, 0.02, 0);
    // Stored in a sensor frame 0.1·f m lower: the pose lifts it back.
    for (auto& p : scene.cloud) p.z -= 0.1f * f;
    const std::string stamp = std::to_string(100 + f) + ".5";
    pcl::io::savePCDFileBinary(dir_ + "/" + stamp + ".pcd", scene.cloud);
    gt << stamp << " 0 0 " << 0.1 * f << " 0 0 0 1\n";
  }
  gt.close();
  const CliRun r = run("--sequence " + dir_ + " --jsonl " + dir_ + "/pcd.jsonl");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("PCD folder"), std::string::npos) << r.output;
  const auto frames = readJsonLines(dir_ + "/pcd.jsonl");
  ASSERT_EQ(frames.size(), 3u);
  const int table = idNear(frames[0], 0.7), floor = idNear(frames[0], 0.0);
  ASSERT_GE(table, 0) << r.output;
  ASSERT_GE(floor, 0) << r.output;
  EXPECT_NE(table, floor);
  for (const auto& planes : frames) {
    EXPECT_EQ(planes.size(), 2u);
    EXPECT_EQ(idNear(planes, 0.7), table);
    EXPECT_EQ(idNear(planes, 0.0), floor);
  }
}

TEST_F(Sequence, ClearErrorsForBadSequences) {
  // A missing folder is said to be missing, not to lack a groundtruth.txt.
  CliRun r = run("--sequence " + dir_ + "/missing");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("--sequence '" + dir_ + "/missing' does not exist"), std::string::npos)
      << r.output;
  EXPECT_EQ(r.output.find("groundtruth.txt"), std::string::npos) << r.output;
  std::ofstream(dir_ + "/file") << "x";
  r = run("--sequence " + dir_ + "/file --rpy \"0 0 0\"");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("is not a folder"), std::string::npos) << r.output;
  r = run("--sequence " + dir_ + " --rpy \"0 0 0\"");
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("no frames"), std::string::npos) << r.output;
  r = run("--sequence " + dir_ + " --tracking best --rpy \"0 0 0\"");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("improved, paper, map"), std::string::npos) << r.output;
  r = run("--input x.pcd --jsonl out.jsonl");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("goes with --sequence"), std::string::npos) << r.output;
  r = run("--sequence " + dir_ + " --json out.json --rpy \"0 0 0\"");
  EXPECT_EQ(r.exit_code, 2) << r.output;
}

}  // namespace test
}  // namespace hope
