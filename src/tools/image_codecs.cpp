// hope's image module (libhope_image_codecs.so): reading and writing image files through
// OpenCV's imgcodecs, loaded by the tools only when an image is read or written (image_module.cpp).
//
// Why a module of its own: on Debian, OpenCV's imgcodecs pulls in GDAL and through it some 130
// libraries, some initialised at load; linked into hope_extract they cost every run ~0.1 s and
// ~40 MB before main(), though a run on a .pcd file never touches an image.
#include <string>

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include "hope/tools/image_codecs.h"

extern "C" {

__attribute__((visibility("default"))) bool hopeReadImage(const char* path, int flags,
                                                          cv::Mat* image) {
  try {
    *image = cv::imread(path, flags);
    return !image->empty();
  } catch (...) {  // a decoder's exception must not cross the module's C boundary
    return false;
  }
}

__attribute__((visibility("default"))) bool hopeWriteImage(const char* path, const cv::Mat* image) {
  try {
    return cv::imwrite(path, *image);
  } catch (...) {  // e.g. an extension OpenCV has no encoder for
    return false;
  }
}

}  // extern "C"
