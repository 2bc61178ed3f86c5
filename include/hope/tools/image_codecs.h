// Image files for the command-line tools, through hope's image module (image_codecs.cpp),
// which image_module.cpp loads on the first call: a run that reads and writes no image never
// loads OpenCV's imgcodecs (and GDAL with it). The module is looked for beside the program's
// directory (the package's lib/ for lib/hope/hope_extract, in the devel and the install space
// alike), then on the library path.
#pragma once

#include <string>

#include <opencv2/core.hpp>

// The module's entry points (C linkage: found by name with dlsym). Both return false when
// the file cannot be read or written; neither throws.
extern "C" {
bool hopeReadImage(const char* path, int flags, cv::Mat* image);
bool hopeWriteImage(const char* path, const cv::Mat* image);
}

namespace hope {
namespace tools {

// The module's file name.
constexpr const char* kImageModule = "libhope_image_codecs.so";

// cv::imread(path, flags) and cv::imwrite(path, image) through the module; false when the file
// cannot be read or written. Throw std::runtime_error, saying where the module was looked for,
// when it cannot be loaded.
bool readImageFile(const std::string& path, int flags, cv::Mat& image);
bool writeImageFile(const std::string& path, const cv::Mat& image);

}  // namespace tools
}  // namespace hope
