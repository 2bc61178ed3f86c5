// libFuzzer target: a .pcd or .ply file (the first byte picks the extension, the rest is the
// file) → hope_extract's loader → the pipeline. A malformed file is refused with a message;
// nothing crashes, hangs or allocates what the file cannot hold.
#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <fstream>
#include <stdexcept>
#include <string>

#include <pcl/console/print.h>

#include "hope/extractor.h"
#include "hope/tools/io.h"

namespace {
// One scratch file per process, removed at exit.
struct Scratch {
  std::string pcd = "/tmp/hope_fuzz_" + std::to_string(getpid()) + ".pcd";
  std::string ply = "/tmp/hope_fuzz_" + std::to_string(getpid()) + ".ply";
  Scratch() { pcl::console::setVerbosityLevel(pcl::console::L_ALWAYS); }
  ~Scratch() {
    std::remove(pcd.c_str());
    std::remove(ply.c_str());
  }
};
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static Scratch scratch;
  if (size < 1) return 0;
  const std::string& path = (data[0] & 1) ? scratch.ply : scratch.pcd;
  {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(data + 1), static_cast<std::streamsize>(size - 1));
  }
  hope::tools::InputCloud input;
  try {
    // A cap far below the default keeps each run small; the checks are the same.
    input = hope::tools::loadCloud(path, 1000000);
  } catch (const std::runtime_error&) {
    return 0;  // refused, with a message
  }
  try {
    hope::Extractor extractor;
    extractor.extract(input.view(), hope::Orientation::identity());
  } catch (const std::invalid_argument&) {
  }
  return 0;
}
