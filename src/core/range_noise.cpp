#include "hope/params.h"

#include <cmath>
#include <stdexcept>

namespace hope {

void validate(const RangeNoise& noise, const std::string& owner) {
  for (double c : {noise.constant, noise.per_metre, noise.quadratic, noise.offset}) {
    if (!(std::isfinite(c) && c >= 0 && c <= 100)) {
      throw std::invalid_argument(owner + ": each coefficient must be finite and in [0, 100]");
    }
  }
}

}  // namespace hope
