#include "hope/plane_colors.h"

namespace hope {

Rgb vocColor(int index) {
  // The VOC map spreads the bits of the index over the three channels, most significant
  // first, so that neighbouring indices get clearly different colours.
  int r = 0, g = 0, b = 0;
  int c = index;
  for (int bit = 7; bit >= 0 && c > 0; --bit) {
    r |= (c & 1) << bit;
    g |= ((c >> 1) & 1) << bit;
    b |= ((c >> 2) & 1) << bit;
    c >>= 3;
  }
  Rgb color;
  color.r = static_cast<std::uint8_t>(r);
  color.g = static_cast<std::uint8_t>(g);
  color.b = static_cast<std::uint8_t>(b);
  return color;
}

Rgb planeColor(int id) { return vocColor((id % 255 + 255) % 255 + 1); }

}  // namespace hope
