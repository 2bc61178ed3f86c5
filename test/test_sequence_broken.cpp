// Broken sequences and absurd values: one bad frame never loses the run, nothing is silently
// wrong, nothing hangs. Each test breaks one thing in a valid synthetic TUM folder (6 frames of
// the demo room, table top at 0.75 m, floor at 0 in the ground-truth world) and runs
// hope_extract under `timeout`, so a hang fails the test instead of stalling the suite.
#include <sys/stat.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <functional>
#include <sstream>
#include <string>
#include <vector>

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include "cli_helpers.h"

namespace hope {
namespace test {

namespace {

constexpr int kFrames = 6;
constexpr double kTableHeight = 0.75;  // the demo room's table top (hope_synth)
constexpr int kHung = 124;             // timeout's exit code

// Whether `text` is well-formed UTF-8 (what every JSON reader requires).
bool validUtf8(const std::string& text) {
  for (std::size_t i = 0; i < text.size();) {
    const unsigned char c = static_cast<unsigned char>(text[i]);
    std::size_t length = c < 0x80           ? 1
                         : (c >> 5) == 0x6  ? 2
                         : (c >> 4) == 0xe  ? 3
                         : (c >> 3) == 0x1e ? 4
                                            : 0;
    if (length == 0 || i + length > text.size()) return false;
    for (std::size_t k = 1; k < length; ++k) {
      if ((static_cast<unsigned char>(text[i + k]) >> 6) != 0x2) return false;
    }
    i += length;
  }
  return true;
}

std::vector<std::string> linesOf(const std::string& path) {
  std::istringstream in(slurp(path));
  std::vector<std::string> lines;
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

// Whether a JSON line holds a plane at `height` (±2 cm).
bool hasPlaneAt(const std::string& line, double height) {
  const std::string key = "\"height\": ";
  for (std::size_t at = line.find(key); at != std::string::npos; at = line.find(key, at + 1)) {
    if (std::fabs(std::stod(line.substr(at + key.size())) - height) < 0.02) return true;
  }
  return false;
}

class BrokenSequence : public Cli {
 protected:
  void SetUp() override {
    Cli::SetUp();
    const CliRun synth =
        runTool(HOPE_SYNTH_BIN, "--out " + dir_ + "/seq --sequence pan --frames 6 --width 320");
    ASSERT_EQ(synth.exit_code, 0) << synth.output;
    std::istringstream list(slurp(dir_ + "/seq/depth.txt"));
    for (std::string line; std::getline(list, line);) {
      if (line.empty() || line[0] == '#') continue;
      std::istringstream fields(line);
      std::string stamp, file;
      fields >> stamp >> file;
      stamps_.push_back(stamp);
      frames_.push_back(dir_ + "/seq/" + file);
    }
    ASSERT_EQ(frames_.size(), static_cast<std::size_t>(kFrames));
  }

  // hope_extract `args` on the folder, stopped after 30 s.
  CliRun extract(const std::string& args) {
    const CliRun r = runTool("timeout 30 " + std::string(HOPE_EXTRACT_BIN), args);
    EXPECT_NE(r.exit_code, kHung) << "hung: " << args;
    return r;
  }
  CliRun extractSequence(const std::string& args = "") {
    return extract("--sequence " + dir_ + "/seq --quiet --jsonl " + dir_ + "/out.jsonl " + args);
  }
  void replaceFile(const std::string& path, const std::string& contents) {
    std::remove(path.c_str());
    std::ofstream(path, std::ios::binary) << contents;
  }
  // The N-th (0-based) data line of a list file replaced by `line`.
  void replaceDataLine(const std::string& path, int n, const std::string& line) {
    std::istringstream in(slurp(path));
    std::ostringstream out;
    int data = 0;
    for (std::string l; std::getline(in, l);) {
      const bool is_data = !l.empty() && l[0] != '#';
      out << (is_data && data == n ? line : l) << "\n";
      data += is_data ? 1 : 0;
    }
    replaceFile(path, out.str());
  }

  std::vector<std::string> frames_, stamps_;
};

}  // namespace

// Hang class: a FIFO nobody writes to, or a device with no end, given as a list file.
TEST_F(BrokenSequence, ListFilesThatAreNotRegularAreRefusedWithoutBlocking) {
  const std::string seq = dir_ + "/seq";
  ASSERT_EQ(::mkfifo((dir_ + "/fifo").c_str(), 0644), 0);
  struct Case {
    std::string setup_file;  // replaced by a link to `target` ("" for none)
    std::string target;
    std::string args;
    std::string named;  // the file the error must name
    std::string kind;
  };
  const std::vector<Case> cases = {
      {seq + "/depth.txt", dir_ + "/fifo", "", seq + "/depth.txt", "a FIFO"},
      {seq + "/depth.txt", "/dev/zero", "", seq + "/depth.txt", "a character device"},
      {seq + "/groundtruth.txt", dir_ + "/fifo", "", seq + "/groundtruth.txt", "a FIFO"},
      {seq + "/rgb.txt", dir_ + "/fifo", "", seq + "/rgb.txt", "a FIFO"},
      {seq + "/intrinsics.txt", dir_ + "/fifo", "", seq + "/intrinsics.txt", "a FIFO"},
      {"", "", "--groundtruth " + dir_ + "/fifo", dir_ + "/fifo", "a FIFO"},
      {"", "", "--groundtruth /dev/zero", "/dev/zero", "a character device"},
      {"", "", "--accelerometer " + dir_ + "/fifo", dir_ + "/fifo", "a FIFO"},
      {"", "", "--accelerometer /dev/zero", "/dev/zero", "a character device"},
  };
  for (const Case& c : cases) {
    std::string saved;
    if (!c.setup_file.empty()) {
      saved = slurp(c.setup_file);
      std::remove(c.setup_file.c_str());
      ASSERT_EQ(::symlink(c.target.c_str(), c.setup_file.c_str()), 0);
    }
    const CliRun r = extract("--sequence " + seq + " --quiet " + c.args);
    EXPECT_EQ(r.exit_code, 1) << c.named << ": " << r.output;
    EXPECT_NE(r.output.find("'" + c.named + "' is not a regular file (" + c.kind + ")"),
              std::string::npos)
        << r.output;
    if (!c.setup_file.empty()) replaceFile(c.setup_file, saved);
  }
}

// Lost-run class: one frame that cannot be read among good ones is skipped, named in the
// summary and in its JSON line, and the other five frames are extracted; --strict stops.
TEST_F(BrokenSequence, OneBadFrameIsSkippedNamedAndCountedAndTheRunGoesOn) {
  const std::string bad = frames_[2];
  const std::string good_png = slurp(frames_[3]);
  struct Case {
    const char* name;
    std::function<void()> breakFrame;
    const char* reason;
  };
  const std::vector<Case> cases = {
      {"missing", [&] { std::remove(bad.c_str()); }, "cannot be opened: No such file"},
      {"empty", [&] { replaceFile(bad, ""); }, "is empty"},
      {"truncated", [&] { replaceFile(bad, good_png.substr(0, good_png.size() / 3)); },
       "is not a readable image"},
      {"8-bit", [&] { cv::imwrite(bad, cv::Mat(240, 320, CV_8UC1, cv::Scalar(100))); },
       "is a grey PNG of 8 bits a pixel"},
      {"16-bit RGB",
       [&] { cv::imwrite(bad, cv::Mat(240, 320, CV_16UC3, cv::Scalar(5000, 5000, 5000))); },
       "is a colour PNG (16-bit, colour type 2)"},
      {"JPEG in disguise",
       [&] {
         cv::imwrite(dir_ + "/x.jpg", cv::Mat(240, 320, CV_8UC3, cv::Scalar(9, 9, 9)));
         replaceFile(bad, slurp(dir_ + "/x.jpg"));
       },
       "this one is 8-bit unsigned with 3 channel(s)"},
      {"directory",
       [&] {
         std::remove(bad.c_str());
         ::mkdir(bad.c_str(), 0755);
       },
       "is not a regular file (a directory)"},
      {"FIFO",
       [&] {
         std::remove(bad.c_str());
         ::mkfifo(bad.c_str(), 0644);
       },
       "is not a regular file (a FIFO)"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    c.breakFrame();
    CliRun r = extractSequence();
    ASSERT_EQ(r.exit_code, 0) << r.output;
    EXPECT_NE(r.output.find("skipped 1 frame(s): could not be read (the first: '" + bad + "'"),
              std::string::npos)
        << r.output;
    const std::vector<std::string> lines = linesOf(dir_ + "/out.jsonl");
    ASSERT_EQ(lines.size(), static_cast<std::size_t>(kFrames));
    for (int f = 0; f < kFrames; ++f) {
      if (f == 2) {
        EXPECT_NE(lines[f].find("\"file\": \"" + bad + "\", \"skipped\": "), std::string::npos)
            << lines[f];
        EXPECT_NE(lines[f].find(c.reason), std::string::npos) << lines[f];
      } else {
        EXPECT_TRUE(hasPlaneAt(lines[f], kTableHeight)) << "no table in good frame " << f;
      }
    }
    r = extractSequence("--strict");
    EXPECT_EQ(r.exit_code, 1) << r.output;
    EXPECT_NE(r.output.find(bad), std::string::npos) << r.output;
    // The frame restored for the next case.
    if (::rmdir(bad.c_str()) != 0) std::remove(bad.c_str());
    replaceFile(bad, good_png);
  }
}

// Lost-run class for orientations: a bad line of the ground truth or the accelerometer is
// skipped with its file:line, its frame goes without an orientation, the others are extracted.
TEST_F(BrokenSequence, BadOrientationLinesAreSkippedWithFileAndLine) {
  const std::string gt = dir_ + "/seq/groundtruth.txt", acc = dir_ + "/seq/accelerometer.txt";
  replaceDataLine(gt, 2, stamps_[2] + " 0 0 1.5 0 0 0 0");
  replaceDataLine(acc, 3, stamps_[3] + " 0 0 0");
  CliRun r = extractSequence();
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("skipped 1 line(s) that could not be read (the first: " + gt +
                          ":5: orientation quaternion"),
            std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find("skipped 1 frame(s): no orientation within 0.02 s"), std::string::npos)
      << r.output;
  std::vector<std::string> lines = linesOf(dir_ + "/out.jsonl");
  ASSERT_EQ(lines.size(), static_cast<std::size_t>(kFrames));
  EXPECT_NE(lines[2].find("\"skipped\": \"no orientation within 0.02 s\""), std::string::npos);
  EXPECT_TRUE(hasPlaneAt(lines[3], kTableHeight));

  r = extractSequence("--accelerometer " + acc);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find(acc + ":6: gravity vector has zero length"), std::string::npos)
      << r.output;
  lines = linesOf(dir_ + "/out.jsonl");
  ASSERT_EQ(lines.size(), static_cast<std::size_t>(kFrames));
  EXPECT_NE(lines[3].find("\"skipped\": \"no orientation"), std::string::npos) << lines[3];

  r = extractSequence("--strict");
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find(gt + ":5: orientation quaternion"), std::string::npos) << r.output;
}

// Silent-overflow class: components that overflow when squared (1e200) still name a rotation;
// scaled by 1e200 the ground truth and the accelerometer give the same planes as unscaled.
TEST_F(BrokenSequence, OverflowingOrientationsGiveTheSamePlanes) {
  // Every plane's height, to the millimetre, frame by frame.
  auto heights = [&](const std::string& args, double table) {
    const CliRun r = extractSequence(args);
    EXPECT_EQ(r.exit_code, 0) << r.output;
    std::vector<std::vector<long>> result;
    const std::string key = "\"height\": ";
    for (const std::string& line : linesOf(dir_ + "/out.jsonl")) {
      EXPECT_TRUE(hasPlaneAt(line, table)) << line.substr(0, 300);
      result.emplace_back();
      for (std::size_t at = line.find(key); at != std::string::npos; at = line.find(key, at + 1)) {
        result.back().push_back(std::lround(1000 * std::stod(line.substr(at + key.size()))));
      }
    }
    return result;
  };
  // Each orientation line with its numbers after the stamp and position scaled.
  auto scaled = [&](const std::string& path, int skip_fields, const char* exponent) {
    std::istringstream in(slurp(path));
    std::ostringstream out;
    for (std::string line; std::getline(in, line);) {
      if (line.empty() || line[0] == '#') continue;
      std::istringstream fields(line);
      std::string field;
      for (int k = 0; fields >> field; ++k)
        out << field << (k > skip_fields ? exponent : "") << " ";
      out << "\n";
    }
    const std::string copy = path + ".scaled";
    replaceFile(copy, out.str());
    return copy;
  };
  const auto pose_heights = heights("", kTableHeight);
  EXPECT_EQ(
      heights("--groundtruth " + scaled(dir_ + "/seq/groundtruth.txt", 3, "e200"), kTableHeight),
      pose_heights);
  // An accelerometer's magnitude means something: 1e300 m/s² is not gravity. Every frame is
  // skipped with that reason, as the nodelet refuses such an IMU message, and nothing overflows.
  const std::string acc = dir_ + "/seq/accelerometer.txt";
  const CliRun r = extractSequence("--accelerometer " + scaled(acc, 0, "e300"));
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("9.8e+300 m/s² is not gravity; is it in m/s²?"), std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find("none of the"), std::string::npos) << r.output;
}

// Ignored-option class: an option that cannot apply to the chosen mode is an error or a
// warning, never silently dropped.
TEST_F(BrokenSequence, OptionsThatDoNotApplyAreRefusedOrSaid) {
  const std::string seq = "--sequence " + dir_ + "/seq --quiet ";
  for (const char* repeat : {"abc", "0", "-1", "1e12", "3"}) {
    const CliRun r = extract(seq + "--repeat " + repeat);
    EXPECT_EQ(r.exit_code, 2) << r.output;
    EXPECT_NE(r.output.find("--repeat times repeated extractions of one input; it does not go "
                            "with --sequence"),
              std::string::npos)
        << r.output;
  }
  CliRun r = extract(seq + "--viewpoint \"0 0 1\"");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("--viewpoint does not go with ground-truth poses"), std::string::npos);
  r = extract("--input x.pcd --strict");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("--strict goes with --sequence"), std::string::npos) << r.output;
  r = extract(seq + "--rpy \"0 0 0\" --max-time-difference 0.1");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("--max-time-difference pairs frames with poses"), std::string::npos);
  r = extract(seq + "--threads 1024");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("--threads 1024: this machine has"), std::string::npos) << r.output;
  // A folder of clouds has no camera: depth-image options are refused.
  ASSERT_EQ(::mkdir((dir_ + "/clouds").c_str(), 0755), 0);
  std::ofstream(dir_ + "/clouds/1.pcd") << "x";
  r = extract("--sequence " + dir_ + "/clouds --rpy \"0 0 0\" --depth-scale 1000");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("--intrinsics and --depth-scale are for depth images"), std::string::npos)
      << r.output;
}

// Unbounded-size class: an image's size is checked against --max-points before it is decoded
// (a 1 KB PNG header claiming 20000 x 20000 pixels), and a list line is read up to 4 KB.
TEST_F(BrokenSequence, SizesAreCheckedBeforeDecodingOrReading) {
  std::string header("\x89PNG\r\n\x1a\n\0\0\0\x0dIHDR", 16);
  header += std::string("\0\0\x4e\x20\0\0\x4e\x20\x10\0\0\0\0", 13);  // 20000 x 20000, 16-bit grey
  replaceFile(frames_[1], header + std::string(1000, '\0'));
  CliRun r = extractSequence();
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("'" + frames_[1] +
                          "' is a 20000 x 20000 image, more pixels than --max-points 100000000"),
            std::string::npos)
      << r.output;
  // --max-points applies to depth images: every 320 x 240 frame is over 1000.
  r = extractSequence("--max-points 1000");
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("none of the 6 frame(s)"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("320 x 240 image, more pixels than --max-points 1000"), std::string::npos)
      << r.output;
  // A 64 MB line of binary bytes: refused after 4 KB, shown escaped and cut.
  std::ofstream(dir_ + "/seq/depth.txt", std::ios::app)
      << "1300000001.0 \x01\xff" << std::string(64 << 20, 'a') << "\n";
  r = extractSequence();
  ASSERT_EQ(r.exit_code, 0) << r.output.substr(0, 2000);
  EXPECT_NE(r.output.find("depth.txt:10: line longer than 4096 bytes: not a list of \"timestamp "
                          "filename\" lines ('1300000001.0 \\x01\\xffaaa"),
            std::string::npos)
      << r.output.substr(0, 2000);
  EXPECT_LT(r.output.size(), 2000u) << "the line was echoed";
}

// Intrinsics that cannot be the camera of the images: refused with the reason, not every frame
// turned into non-finite points and an empty, successful run.
TEST_F(BrokenSequence, IntrinsicsThatDoNotFitTheImageAreRefused) {
  CliRun r = extractSequence("--intrinsics \"1e-300 1e-300 160 120\"");
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("do not fit the 320 x 240 image: at 1 m depth the image would span"),
            std::string::npos)
      << r.output;
  r = extractSequence("--intrinsics \"258 258 1e300 120\"");
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("do not fit the 320 x 240 image: the principal point is outside"),
            std::string::npos)
      << r.output;
}

// Messages that mislead: the folder is named as missing, a list that is a directory is said to
// be one, a file name with a space is read whole.
TEST_F(BrokenSequence, MessagesNameTheActualProblem) {
  CliRun r = extract("--sequence " + dir_ + "/nothing");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("--sequence '" + dir_ + "/nothing' does not exist"), std::string::npos);
  const std::string list = dir_ + "/seq/depth.txt";
  const std::string saved = slurp(list);
  std::remove(list.c_str());
  ASSERT_EQ(::mkdir(list.c_str(), 0755), 0);
  r = extractSequence();
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("'" + list + "' is not a regular file (a directory)"), std::string::npos)
      << r.output;
  ::rmdir(list.c_str());
  replaceFile(list, saved);
  const std::string spaced = dir_ + "/seq/depth/frame two.png";
  ASSERT_EQ(std::rename(frames_[1].c_str(), spaced.c_str()), 0);
  replaceDataLine(list, 1, stamps_[1] + " depth/frame two.png");
  r = extractSequence();
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const std::vector<std::string> lines = linesOf(dir_ + "/out.jsonl");
  ASSERT_EQ(lines.size(), static_cast<std::size_t>(kFrames));
  EXPECT_NE(lines[1].find("\"file\": \"" + spaced + "\""), std::string::npos) << lines[1];
  EXPECT_TRUE(hasPlaneAt(lines[1], kTableHeight));
}

// Output correctness: overlays of two frames with one stamp are both kept, a huge stamp is
// written in full, a file name that is not UTF-8 still gives valid UTF-8 JSON.
TEST_F(BrokenSequence, OutputsStayDistinctExactAndValid) {
  const std::string list = dir_ + "/seq/depth.txt";
  replaceDataLine(list, 1, stamps_[0] + " " + frames_[1]);  // frame 1 with frame 0's stamp
  replaceDataLine(list, 5, "1e45 " + frames_[5]);
  const std::string latin1 = dir_ + "/seq/depth/caf\xe9.png";
  ASSERT_EQ(std::rename(frames_[3].c_str(), latin1.c_str()), 0);
  replaceDataLine(list, 3, stamps_[3] + " " + latin1);
  const CliRun r =
      extractSequence("--quaternion \"0.7071 0 0 0.7071\" --overlay-dir " + dir_ + "/overlays");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const std::string json = slurp(dir_ + "/out.jsonl");
  EXPECT_TRUE(validUtf8(json));
  EXPECT_NE(json.find("caf\\u00e9.png"), std::string::npos);
  const std::vector<std::string> lines = linesOf(dir_ + "/out.jsonl");
  ASSERT_EQ(lines.size(), static_cast<std::size_t>(kFrames));
  const std::string last = lines.back();
  ASSERT_EQ(last.rfind("{\"stamp\": ", 0), 0u);
  EXPECT_EQ(std::strtod(last.c_str() + 10, nullptr), 1e45) << last.substr(0, 60);
  int overlays = 0;
  for (const std::string& name : {stamps_[0] + ".png", stamps_[0] + "_2.png"}) {
    overlays += ::access((dir_ + "/overlays/" + name).c_str(), F_OK) == 0 ? 1 : 0;
  }
  EXPECT_EQ(overlays, 2) << "two frames stamped " << stamps_[0];
}

// The extractor's warnings, never printed in sequence mode before: once per kind with a count,
// and each frame's in its JSON line.
TEST_F(BrokenSequence, ExtractorWarningsAreSaidOnceWithACountAndKept) {
  const CliRun r = extractSequence("--depth-scale 5");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const std::string said = "warning on 6 frame(s), the first: " + frames_[0] + ": the cloud spans";
  const std::size_t at = r.output.find(said);
  ASSERT_NE(at, std::string::npos) << r.output;
  EXPECT_NE(r.output.find("is it in millimetres?", at), std::string::npos) << r.output;
  EXPECT_EQ(r.output.find("is it in millimetres?", r.output.find("millimetres", at) + 1),
            std::string::npos)
      << "said more than once: " << r.output;
  for (const std::string& line : linesOf(dir_ + "/out.jsonl")) {
    EXPECT_NE(line.find("\"warnings\": [\"the cloud spans"), std::string::npos)
        << line.substr(0, 200);
  }
}

// The sweep: many broken lists and values, each run to its end. Whatever is broken, the run
// ends (no hang) with exit 0 (and a JSON line per usable listed frame, each valid UTF-8 and
// either extracted or skipped with a reason), or with a usage (2) or input (1) error that says
// "error:" — never a crash, a raw exception or a flood of output.
TEST_F(BrokenSequence, NoBrokenListOrValueCrashesHangsOrFloods) {
  const std::string seq = dir_ + "/seq";
  const std::string depth_list = slurp(seq + "/depth.txt"), gt = slurp(seq + "/groundtruth.txt"),
                    acc = slurp(seq + "/accelerometer.txt");
  const std::string first = stamps_[0] + " depth/" + stamps_[0] + ".png";
  struct Case {
    const char* file;  // in the folder
    std::string contents;
    std::string args;
  };
  const std::string binary("\x00\x01\xfe\xff\x80garbage\x00\n\x7f\x1b[31m", 20);
  const std::vector<Case> cases = {
      {"depth.txt", "", ""},
      {"depth.txt", "# only a comment\n", ""},
      {"depth.txt", binary, ""},
      {"depth.txt", "nan depth/a.png\ninf depth/b.png\n-1e308 depth/c.png\n", ""},
      {"depth.txt", first + "\n" + first + "\n" + first + "\n", ""},
      {"depth.txt", stamps_[0] + "\n", ""},
      {"depth.txt", first + " extra columns\n", ""},
      {"depth.txt", first + "\r\n", ""},
      {"depth.txt", stamps_[0] + " ../../../../etc/passwd\n", ""},
      {"depth.txt", stamps_[0] + " /dev/zero\n", ""},
      {"depth.txt", stamps_[0] + " depth\n", ""},
      {"depth.txt", "1e400 depth/a.png\n", ""},
      {"depth.txt", std::string(5000, '1') + " depth/a.png\n", ""},
      {"groundtruth.txt", "", ""},
      {"groundtruth.txt", binary, ""},
      {"groundtruth.txt", stamps_[0] + " 0 0 1.5 nan 0 0 1\n", ""},
      {"groundtruth.txt", stamps_[0] + " 0 0 1.5 1e308 1e308 1e308 1e308\n", ""},
      {"groundtruth.txt", stamps_[0] + " 0 0 1.5 1e-320 0 0 0\n", ""},
      {"groundtruth.txt", stamps_[0] + " 1e308 0 1.5 0 0 0 1\n", ""},
      {"groundtruth.txt", stamps_[0] + " 0 0 1.5\n", ""},
      {"groundtruth.txt", gt + "\r\n", ""},
      {"accelerometer.txt", "", "--accelerometer " + seq + "/accelerometer.txt"},
      {"accelerometer.txt", stamps_[0] + " 1e308 1e308 1e308\n",
       "--accelerometer " + seq + "/accelerometer.txt"},
      {"accelerometer.txt", stamps_[0] + " inf 0 0\n",
       "--accelerometer " + seq + "/accelerometer.txt"},
      {"accelerometer.txt", binary, "--accelerometer " + seq + "/accelerometer.txt"},
      {"intrinsics.txt", "", ""},
      {"intrinsics.txt", "0 0 0 0\n", ""},
      {"intrinsics.txt", "-500 500 160 120\n", ""},
      {"intrinsics.txt", "1e308 1e308 160 120\n", ""},
      {"intrinsics.txt", binary, ""},
      {"rgb.txt", binary, "--overlay-dir " + dir_ + "/overlays"},
      {"depth.txt", depth_list, "--depth-scale 1e-300"},
      {"depth.txt", depth_list, "--depth-scale 1e300"},
      {"depth.txt", depth_list, "--max-time-difference 1e308"},
      {"depth.txt", depth_list, "--max-time-difference -1"},
      {"depth.txt", depth_list, "--r-xy 1e-9"},
      {"depth.txt", depth_list, "--quaternion \"1e308 1e308 1e308 1e308\""},
      {"depth.txt", depth_list, "--gravity \"1e-310 0 0\""},
      {"depth.txt", depth_list, "--level --level-bound 1e308"},
  };
  for (const Case& c : cases) {
    const std::string path = seq + "/" + c.file;
    const std::string saved = slurp(path);
    replaceFile(path, c.contents);
    std::remove((dir_ + "/out.jsonl").c_str());
    const CliRun r = extractSequence(c.args);
    const std::string what =
        std::string(c.file) + " = '" + c.contents.substr(0, 60) + "' " + c.args;
    EXPECT_TRUE(r.exit_code == 0 || r.exit_code == 1 || r.exit_code == 2) << what << r.output;
    EXPECT_LT(r.output.size(), 3000u) << what << r.output.substr(0, 3000);
    for (const char* crash : {"terminate called", "Segmentation", "Aborted", "what():"}) {
      EXPECT_EQ(r.output.find(crash), std::string::npos) << what << r.output;
    }
    if (r.exit_code == 0) {
      const std::string json = slurp(dir_ + "/out.jsonl");
      EXPECT_TRUE(validUtf8(json)) << what;
      const std::vector<std::string> lines = linesOf(dir_ + "/out.jsonl");
      EXPECT_FALSE(lines.empty()) << what << r.output;
      for (const std::string& line : lines) {
        EXPECT_EQ(line.rfind("{\"stamp\": ", 0), 0u) << what << line.substr(0, 100);
        EXPECT_TRUE(line.find("\"planes\": [") != std::string::npos ||
                    line.find("\"skipped\": \"") != std::string::npos)
            << what << line.substr(0, 200);
      }
    } else {
      EXPECT_NE(r.output.find("hope_extract: error: "), std::string::npos) << what << r.output;
    }
    replaceFile(path, saved);
  }
}

}  // namespace test
}  // namespace hope
