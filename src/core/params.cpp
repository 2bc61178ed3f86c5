#include "hope/params.h"

#include <cmath>
#include <sstream>
#include <stdexcept>

namespace hope {

double Params::maxSlope() const { return std::atan(gamma()); }

namespace {

// Resolutions below 0.1 mm are below any range sensor's noise; above 10 m no indoor or
// outdoor horizontal surface is resolved. Both ends are almost certainly unit mistakes
// (millimetres or centimetres passed as metres).
constexpr double kMinResolution = 1e-4;
constexpr double kMaxResolution = 10.0;
// More threads than any machine hope runs on has cores: a typo or an uninitialised value.
constexpr int kMaxThreads = 1024;

void requireRange(const char* name, double value, double lo, double hi, const char* hint) {
  if (!std::isfinite(value) || value < lo || value > hi) {
    std::ostringstream msg;
    msg << "parameter " << name << " = " << value << " is out of range [" << lo << ", " << hi << "]"
        << hint;
    throw std::invalid_argument(msg.str());
  }
}

}  // namespace

void validate(const Params& p) {
  const char* units = " (metres; did you pass millimetres or centimetres?)";
  requireRange("r_xy", p.r_xy, kMinResolution, kMaxResolution, units);
  requireRange("r_z", p.r_z, kMinResolution, kMaxResolution, units);
  requireRange("normal_radius_factor", p.normal_radius_factor, 1.0, 5.0,
               " (δ of the paper, 1.01 by default; it must exceed 1 to reach grid neighbours)");
  if (p.min_cluster_voxels < 3 || p.min_cluster_voxels > 1000000) {
    std::ostringstream msg;
    msg << "parameter min_cluster_voxels = " << p.min_cluster_voxels
        << " is out of range [3, 1000000] (a plane needs at least 3 normals, paper §2.4)";
    throw std::invalid_argument(msg.str());
  }
  if (std::isnan(p.min_height) || std::isnan(p.max_height) || p.min_height > p.max_height) {
    std::ostringstream msg;
    msg << "parameters min_height = " << p.min_height << " and max_height = " << p.max_height
        << " do not form a height band (need min_height <= max_height, no NaN)";
    throw std::invalid_argument(msg.str());
  }
  requireRange("min_area", p.min_area, 0.0, 1e6, " (square metres)");
  if (p.threads < 0 || p.threads > kMaxThreads) {
    std::ostringstream msg;
    msg << "parameter threads = " << p.threads << " is out of range [0, " << kMaxThreads
        << "] (0 takes every core)";
    throw std::invalid_argument(msg.str());
  }
  requireRange("max_merge_gap", p.max_merge_gap, 0.0, 100.0,
               " (metres: the widest gap between two fragments of one surface)");
}

}  // namespace hope
