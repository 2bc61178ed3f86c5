// Loading hope's image module (image_codecs.h) on the first image a tool reads or writes.
#include <dlfcn.h>
#include <unistd.h>

#include <climits>
#include <stdexcept>
#include <string>
#include <vector>

#include "hope/tools/image_codecs.h"

namespace hope {
namespace tools {

namespace {

struct ImageModule {
  decltype(&hopeReadImage) read = nullptr;
  decltype(&hopeWriteImage) write = nullptr;
};

// The directory of the running program ("" when /proc does not say).
std::string programDirectory() {
  char path[PATH_MAX];
  const ssize_t length = readlink("/proc/self/exe", path, sizeof(path) - 1);
  if (length <= 0) return "";
  const std::string program(path, static_cast<std::size_t>(length));
  const std::size_t slash = program.rfind('/');
  return slash == std::string::npos ? "" : program.substr(0, slash);
}

// The image module, loaded on first use (image_codecs.h says where it is looked for). A failed
// load throws and is tried again on the next call.
const ImageModule& imageModule() {
  static const ImageModule module = [] {
    std::vector<std::string> candidates;
    const std::string directory = programDirectory();
    if (!directory.empty()) {
      candidates.push_back(directory + "/../" + kImageModule);  // lib/hope/hope_extract
      candidates.push_back(directory + "/" + kImageModule);
    }
    candidates.emplace_back(kImageModule);  // LD_LIBRARY_PATH, the program's RUNPATH, system
    std::string reasons;
    for (const std::string& candidate : candidates) {
      void* handle = dlopen(candidate.c_str(), RTLD_NOW | RTLD_LOCAL);
      if (!handle) {
        reasons += std::string("\n  ") + dlerror();
        continue;
      }
      ImageModule found;
      found.read = reinterpret_cast<decltype(found.read)>(dlsym(handle, "hopeReadImage"));
      found.write = reinterpret_cast<decltype(found.write)>(dlsym(handle, "hopeWriteImage"));
      if (found.read && found.write) return found;
      reasons += "\n  " + candidate + ": not hope's image module (no hopeReadImage/hopeWriteImage)";
      dlclose(handle);
    }
    throw std::runtime_error(std::string("reading and writing images needs hope's image module ") +
                             kImageModule + ", which could not be loaded:" + reasons +
                             "\nRebuild or reinstall hope, or add its lib directory to "
                             "LD_LIBRARY_PATH.");
  }();
  return module;
}

}  // namespace

bool readImageFile(const std::string& path, int flags, cv::Mat& image) {
  return imageModule().read(path.c_str(), flags, &image);
}

bool writeImageFile(const std::string& path, const cv::Mat& image) {
  return imageModule().write(path.c_str(), &image);
}

}  // namespace tools
}  // namespace hope
