// hope_extract on hostile files and outputs: every case ends with its exact exit code and a
// message naming the problem, never a crash, a hang, an allocation of gigabytes, silent zeros
// or a partial output file.
#include <sys/stat.h>
#include <unistd.h>

#include <cstdint>
#include <fstream>
#include <string>

#include <pcl/io/pcd_io.h>
#include <pcl/io/ply_io.h>

#include "cli_helpers.h"
#include "helpers.h"

namespace hope {
namespace test {

namespace {

bool exists(const std::string& path) {
  struct stat info;
  return ::lstat(path.c_str(), &info) == 0;
}

// A PCD header for x y z float32 points, with the given size lines.
std::string pcdHeader(const std::string& width, const std::string& height,
                      const std::string& points, const std::string& data) {
  return "# .PCD v0.7\nVERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\nWIDTH " +
         width + "\nHEIGHT " + height + "\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS " + points + "\nDATA " +
         data + "\n";
}

// Two level sheets (floor at 0, a table top at 0.3 m) as a z-up cloud.
LabeledCloud twoSheets() {
  LabeledCloud cloud;
  addSheet(cloud, 0, 0, 1, 1, 0.0, 0.01, 0);
  addSheet(cloud, 0.2, 0.2, 0.6, 0.6, 0.3, 0.01, 1);
  return cloud;
}

// The "height" values of a JSON report, in order.
std::vector<double> heightsIn(const std::string& json) {
  std::vector<double> heights;
  for (std::size_t at = json.find("\"height\": "); at != std::string::npos;
       at = json.find("\"height\": ", at + 1)) {
    heights.push_back(std::stod(json.substr(at + 10)));
  }
  return heights;
}

}  // namespace

TEST_F(Cli, FilesThatAreNotRegularAreRefusedWithoutBlocking) {
  // A link to /dev/null: an endless empty read for PCL.
  ASSERT_EQ(::symlink("/dev/null", (dir_ + "/null.pcd").c_str()), 0);
  CliRun r = run("--input " + dir_ + "/null.pcd");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.output.find("null.pcd' is not a regular file (a character device)"),
            std::string::npos)
      << r.output;
  // A directory named like a cloud: PCL spun forever on it.
  ASSERT_EQ(::mkdir((dir_ + "/x.pcd").c_str(), 0755), 0);
  r = run("--input " + dir_ + "/x.pcd");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.output.find("x.pcd' is not a regular file (a directory)"), std::string::npos)
      << r.output;
  // A FIFO nobody writes to: opening it would block forever.
  ASSERT_EQ(::mkfifo((dir_ + "/fifo.ply").c_str(), 0644), 0);
  r = run("--input " + dir_ + "/fifo.ply");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.output.find("fifo.ply' is not a regular file (a FIFO)"), std::string::npos)
      << r.output;
  r = run("--input /dev/zero");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.output.find("'/dev/zero' is neither .pcd nor .ply"), std::string::npos) << r.output;
}

TEST_F(Cli, EmptyJunkAndHeaderOnlyFilesAreRefusedWithTheReason) {
  std::ofstream(dir_ + "/empty.pcd");
  CliRun r = run("--input " + dir_ + "/empty.pcd");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.output.find("empty.pcd' is empty"), std::string::npos) << r.output;

  std::ofstream(dir_ + "/junk.pcd") << "hello, this is no point cloud\n";
  r = run("--input " + dir_ + "/junk.pcd");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.output.find("junk.pcd' is not a PCD file (no 'DATA' line"), std::string::npos)
      << r.output;

  std::ofstream(dir_ + "/junk.ply") << "hello\n";
  r = run("--input " + dir_ + "/junk.ply");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.output.find("junk.ply' is not a PLY file"), std::string::npos) << r.output;

  // The header promises 1000 binary points; the data never comes.
  std::ofstream(dir_ + "/header.pcd") << pcdHeader("1000", "1", "1000", "binary");
  r = run("--input " + dir_ + "/header.pcd");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.output.find("header.pcd' is truncated: its header claims 1000 points of 12 bytes, "
                          "the file holds 0 bytes of data"),
            std::string::npos)
      << r.output;

  // A PLY promising a million vertices with ten bytes of data.
  std::ofstream(dir_ + "/short.ply") << "ply\nformat binary_little_endian 1.0\nelement vertex "
                                        "1000000\nproperty float x\nproperty float y\nproperty "
                                        "float z\nend_header\n0123456789";
  r = run("--input " + dir_ + "/short.ply");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.output.find("short.ply' is truncated"), std::string::npos) << r.output;
}

TEST_F(Cli, HeadersWhoseSizesOverflowOrExceedTheCapAreRefusedBeforeAllocating) {
  // WIDTH × HEIGHT = 2^64 - 2^33 + 1 points: wrapped in PCL's 32-bit arithmetic, it wrote out of
  // bounds.
  std::ofstream(dir_ + "/wrap.pcd")
      << pcdHeader("4294967295", "4294967295", "1", "ascii") << "1 2 3\n";
  CliRun r = run("--input " + dir_ + "/wrap.pcd");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.output.find("has WIDTH 4294967295 x HEIGHT 4294967295 != POINTS 1"),
            std::string::npos)
      << r.output;
  std::ofstream(dir_ + "/big.pcd") << pcdHeader("65536", "65536", "4294967296", "binary");
  r = run("--input " + dir_ + "/big.pcd");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.output.find("has a malformed POINTS line"), std::string::npos) << r.output;
  std::ofstream(dir_ + "/cap.pcd") << pcdHeader("200000", "1000", "200000000", "binary");
  r = run("--input " + dir_ + "/cap.pcd");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.output.find("claims 200000000 points, more than the cap of 100000000 (raise it "
                          "with --max-points)"),
            std::string::npos)
      << r.output;
  r = run("--input " + dir_ + "/cap.pcd --max-points 1e9");
  EXPECT_EQ(r.exit_code, 1);  // over the cap no more, but the file still holds no data
  EXPECT_NE(r.output.find("cap.pcd' is truncated"), std::string::npos) << r.output;
  r = run("--input " + dir_ + "/cap.pcd --max-points 0");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.output.find("--max-points must be a whole number in [1, 1e12]"), std::string::npos)
      << r.output;

  // A tiny compressed PCD claiming 1.2 GB (100 M points): took 13 s and 4 GB before.
  {
    std::ofstream out(dir_ + "/bomb.pcd", std::ios::binary);
    out << pcdHeader("100000000", "1", "100000000", "binary_compressed");
    const std::uint32_t sizes[2] = {16, 1200000000u};
    out.write(reinterpret_cast<const char*>(sizes), sizeof(sizes));
    out << std::string(16, '\0');
  }
  r = run("--input " + dir_ + "/bomb.pcd");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.output.find("claims 1200000000 bytes from a compressed block of 16 bytes"),
            std::string::npos)
      << r.output;
}

TEST_F(Cli, Float64CoordinatesAreReadNotZeroed) {
  const LabeledCloud sheets = twoSheets();
  pcl::PointCloud<pcl::PointXYZ> shifted = sheets.cloud;
  for (auto& p : shifted) p.z += 0.5f;  // floor at 0.5 m, table top at 0.8 m
  // The same points with double x, y, z, written as PCD (binary) and as PLY (binary).
  std::ofstream pcd(dir_ + "/f64.pcd", std::ios::binary);
  pcd << "VERSION 0.7\nFIELDS x y z\nSIZE 8 8 8\nTYPE F F F\nCOUNT 1 1 1\nWIDTH " << shifted.size()
      << "\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS " << shifted.size() << "\nDATA binary\n";
  std::ofstream ply(dir_ + "/f64.ply", std::ios::binary);
  ply << "ply\nformat binary_little_endian 1.0\nelement vertex " << shifted.size()
      << "\nproperty double x\nproperty double y\nproperty double z\nend_header\n";
  for (const auto& p : shifted) {
    const double xyz[3] = {p.x, p.y, p.z};
    pcd.write(reinterpret_cast<const char*>(xyz), sizeof(xyz));
    ply.write(reinterpret_cast<const char*>(xyz), sizeof(xyz));
  }
  pcd.close();
  ply.close();
  for (const char* name : {"/f64.pcd", "/f64.ply"}) {
    const CliRun r = run("--input " + dir_ + name + " --json " + dir_ + "/p.json --quiet");
    ASSERT_EQ(r.exit_code, 0) << name << ": " << r.output;
    const std::vector<double> heights = heightsIn(slurp(dir_ + "/p.json"));
    ASSERT_EQ(heights.size(), 2u) << name;
    EXPECT_NEAR(std::min(heights[0], heights[1]), 0.5, 0.005) << name;
    EXPECT_NEAR(std::max(heights[0], heights[1]), 0.8, 0.005) << name;
  }
}

TEST_F(Cli, OutputsAreCompleteOrAbsentAndWriteErrorsAreReported) {
  ASSERT_EQ(pcl::io::savePCDFileBinary(dir_ + "/in.pcd", twoSheets().cloud), 0);
  const std::string input = "--input " + dir_ + "/in.pcd --quiet";
  // A full disk: the JSON cannot be written, and the tool says so.
  CliRun r = run(input + " --json /dev/full");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.output.find("cannot write '/dev/full': No space left on device"), std::string::npos)
      << r.output;
  // The JSON can be written, the labels cannot: neither is left behind, nor a temporary.
  r = run(input + " --json " + dir_ + "/p.json --labels " + dir_ + "/no/such/dir/l.pcd");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(
      r.output.find("cannot write '" + dir_ + "/no/such/dir/l.pcd': No such file or directory"),
      std::string::npos)
      << r.output;
  EXPECT_FALSE(exists(dir_ + "/p.json"));
  // An overlay in a format OpenCV cannot write fails after the JSON was written: no JSON either.
  r = run(input + " --json " + dir_ + "/p.json --overlay " + dir_ + "/o.unknown");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.output.find("cannot write '" + dir_ + "/o.unknown'"), std::string::npos) << r.output;
  EXPECT_FALSE(exists(dir_ + "/p.json"));

  // A sequence whose second frame is corrupt, run with --strict (stop at the first bad frame):
  // the JSON lines of a previous run stay as they were (they were truncated at the start
  // before), and no partial file replaces them.
  ASSERT_EQ(::mkdir((dir_ + "/seq").c_str(), 0755), 0);
  ASSERT_EQ(pcl::io::savePCDFileBinary(dir_ + "/seq/1.pcd", twoSheets().cloud), 0);
  std::ofstream(dir_ + "/seq/2.pcd") << "not a cloud";
  std::ofstream(dir_ + "/old.jsonl") << "previous run\n";
  r = run("--sequence " + dir_ + "/seq --quaternion \"0 0 0 1\" --strict --jsonl " + dir_ +
          "/old.jsonl --quiet");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.output.find("2.pcd' is not a PCD file"), std::string::npos) << r.output;
  EXPECT_EQ(slurp(dir_ + "/old.jsonl"), "previous run\n");
  EXPECT_EQ(
      std::system(
          ("test -z \"$(ls -A " + dir_ + " | grep -v '^in.pcd$\\|^seq$\\|^old.jsonl$')\"").c_str()),
      0)
      << "temporary files left in " << dir_;

  // And a good run replaces the output whole.
  r = run(input + " --json " + dir_ + "/p.json");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(heightsIn(slurp(dir_ + "/p.json")).size(), 2u);
}

}  // namespace test
}  // namespace hope
