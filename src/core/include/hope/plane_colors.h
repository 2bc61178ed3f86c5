// One colour per plane id, the same in every output (overlay pictures, labelled clouds, RViz
// markers, Python), without any image library.
#pragma once

#include <cstdint>

namespace hope {

struct Rgb {
  std::uint8_t r = 0, g = 0, b = 0;
};

// The colour as PCL and PointCloud2 store it in a float-sized "rgb" field: 0x00RRGGBB.
inline std::uint32_t packRgb(Rgb c) {
  return (std::uint32_t{c.r} << 16) | (std::uint32_t{c.g} << 8) | c.b;
}

// The Pascal VOC colour map entry `index` (index 0 is the black background, so plane id k
// uses index k + 1).
Rgb vocColor(int index);

// The colour of plane id `id`: VOC entry id + 1, wrapping after 255 ids so that large (or
// negative) ids still get a colour and never the black background.
Rgb planeColor(int id);

}  // namespace hope
