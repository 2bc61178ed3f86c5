// One colour per plane id, the same in every output (overlay pictures, labelled clouds, RViz
// markers, Python), without any image library.
#pragma once

#include <cstdint>

namespace hope {

struct Rgb {
  std::uint8_t r = 0, g = 0, b = 0;
};

// The Pascal VOC colour map entry `index` (index 0 is the black background, so plane id k
// uses index k + 1).
Rgb vocColor(int index);

// The colour of plane id `id`: VOC entry id + 1, wrapping after 255 ids so that large (or
// negative) ids still get a colour and never the black background.
Rgb planeColor(int id);

}  // namespace hope
