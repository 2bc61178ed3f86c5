// libFuzzer target: a depth image (size, type, scale and intrinsics from the fuzzer, pixels
// from the rest) → back-projection → the pipeline with a fuzzed orientation. Bad intrinsics,
// scales or orientations are refused with std::invalid_argument; nothing else may escape.
#include <cmath>
#include <cstdint>
#include <cstring>
#include <stdexcept>

#include <opencv2/core.hpp>

#include "fuzz_input.h"
#include "hope/depth_image.h"
#include "hope/extractor.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  hope::fuzz::Input in(data, size);
  const int rows = 1 + in.take<std::uint8_t>() % 64, cols = 1 + in.take<std::uint8_t>() % 64;
  const bool metres = in.take<std::uint8_t>() & 1;
  hope::PinholeIntrinsics k{in.take<float>(), in.take<float>(), in.take<float>(), in.take<float>()};
  const double scale = in.take<float>();
  const float q[4] = {in.take<float>(), in.take<float>(), in.take<float>(), in.take<float>()};
  cv::Mat depth(rows, cols, metres ? CV_32FC1 : CV_16UC1, cv::Scalar(0));
  const std::vector<std::uint8_t> pixels = in.rest();
  if (!pixels.empty()) {
    std::memcpy(depth.data, pixels.data(),
                std::min(pixels.size(), depth.total() * depth.elemSize()));
  }
  try {
    const auto cloud = hope::depthToCloud(depth, k, scale);
    hope::Params params;
    params.r_xy = 0.02;
    hope::Extractor extractor(params);
    extractor.extract(cloud, hope::Orientation::fromQuaternion(q[0], q[1], q[2], q[3]));
  } catch (const std::invalid_argument&) {
    // bad intrinsics, scale or quaternion, or a cloud that cannot be a scene in metres
  }
  return 0;
}
