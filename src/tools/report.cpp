#include "hope/tools/report.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <iomanip>

namespace hope {
namespace tools {

namespace {

// JSON has no NaN or infinity; none should reach here, but never write invalid JSON.
std::string number(double value, int precision = 6) {
  if (!std::isfinite(value)) return "null";
  char text[40];
  std::snprintf(text, sizeof(text), "%.*g", precision, value);
  return text;
}

std::string vec3(const Eigen::Vector3d& v) {
  return "[" + number(v.x()) + ", " + number(v.y()) + ", " + number(v.z()) + "]";
}

// Length of the well-formed UTF-8 sequence starting at s[i], or 0 when it is not one (a
// stray continuation byte, an overlong form, a surrogate, a cut sequence).
std::size_t utf8SequenceLength(const std::string& s, std::size_t i) {
  const auto byte = [&](std::size_t k) { return static_cast<unsigned char>(s[k]); };
  const unsigned char lead = byte(i);
  std::size_t length = 0;
  unsigned char lo = 0x80, hi = 0xbf;  // the range of the second byte
  if (lead >= 0xc2 && lead <= 0xdf) {
    length = 2;
  } else if (lead >= 0xe0 && lead <= 0xef) {
    length = 3;
    if (lead == 0xe0) lo = 0xa0;
    if (lead == 0xed) hi = 0x9f;
  } else if (lead >= 0xf0 && lead <= 0xf4) {
    length = 4;
    if (lead == 0xf0) lo = 0x90;
    if (lead == 0xf4) hi = 0x8f;
  } else {
    return 0;
  }
  if (i + length > s.size()) return 0;
  if (byte(i + 1) < lo || byte(i + 1) > hi) return 0;
  for (std::size_t k = 2; k < length; ++k) {
    if (byte(i + k) < 0x80 || byte(i + k) > 0xbf) return 0;
  }
  return length;
}

// JSON string content: quotes and backslashes escaped, control characters as \u00NN, and a
// byte that is not part of valid UTF-8 (a Latin-1 file name) as the character of that code
// (\u00NN), so that the output is always valid UTF-8 JSON and the name still readable.
std::string escape(const std::string& s) {
  std::string out;
  for (std::size_t i = 0; i < s.size();) {
    const unsigned char c = static_cast<unsigned char>(s[i]);
    if (c == '"' || c == '\\') {
      out += '\\';
      out += static_cast<char>(c);
      ++i;
    } else if (c < 0x80) {
      if (c < 0x20 || c == 0x7f) {
        char code[8];
        std::snprintf(code, sizeof(code), "\\u%04x", c);
        out += code;
      } else {
        out += static_cast<char>(c);
      }
      ++i;
    } else if (const std::size_t length = utf8SequenceLength(s, i)) {
      out.append(s, i, length);
      i += length;
    } else {
      char code[8];
      std::snprintf(code, sizeof(code), "\\u%04x", c);
      out += code;
      ++i;
    }
  }
  return out;
}

}  // namespace

std::string jsonString(const std::string& text) { return "\"" + escape(text) + "\""; }

std::string stampText(double stamp) {
  char text[40];
  if (std::fabs(stamp) < 1e15) {
    std::snprintf(text, sizeof(text), "%.6f", stamp);
    if (std::strtod(text, nullptr) == stamp) return text;
  }
  std::snprintf(text, sizeof(text), "%.17g", stamp);  // round-trips any double, <= 24 chars
  return text;
}

void printTable(std::ostream& out, const Result& result) {
  char line[200];
  std::snprintf(line, sizeof(line), "%4s %9s %9s %9s %8s  %s\n", "id", "height_m", "area_m2",
                "points", "tilt_deg", "bbox x_min y_min x_max y_max (m)");
  out << line;
  for (const HorizontalPlane& p : result.planes) {
    std::snprintf(line, sizeof(line), "%4d %9.3f %9.3f %9zu %8.2f  %.3f %.3f %.3f %.3f\n", p.id,
                  p.height, p.area, p.num_points, p.tilt * 180.0 / M_PI, p.bbox[0], p.bbox[1],
                  p.bbox[2], p.bbox[3]);
    out << line;
  }
  const StageTimings& t = result.timings;
  out << result.planes.size() << " plane(s) from " << result.finite_points << " finite of "
      << result.input_points << " points, " << result.voxels << " voxels, " << result.candidates
      << " candidates, " << result.clusters << " clusters (" << result.rejected_by_refinement
      << " rejected by refinement, " << result.rejected_by_band_or_area
      << " by height band / area, " << result.merged_fragments << " fragment(s) merged, "
      << result.bridged_voxels << " voxel(s) bridged)\n";
  out << std::fixed << std::setprecision(2) << "time " << t.total_ms << " ms: alignment "
      << t.alignment_ms << ", grid " << t.grid_filter_ms << ", normals " << t.normals_ms
      << ", candidates " << t.candidates_ms << ", clustering " << t.clustering_ms << ", refinement "
      << t.refinement_ms << ", description " << t.description_ms << ", merging " << t.merging_ms
      << "\n";
  out.unsetf(std::ios::floatfield);
}

void writePlaneJson(std::ostream& out, const HorizontalPlane& p) {
  out << "{\"id\": " << p.id << ", \"height\": " << number(p.height) << ", \"bbox\": ["
      << number(p.bbox[0]) << ", " << number(p.bbox[1]) << ", " << number(p.bbox[2]) << ", "
      << number(p.bbox[3]) << "]"
      << ", \"centroid\": " << vec3(p.centroid) << ", \"normal\": " << vec3(p.normal)
      << ", \"tilt\": " << number(p.tilt) << ", \"area\": " << number(p.area)
      << ", \"free_area\": " << number(p.free_area) << ", \"num_points\": " << p.num_points
      << ", \"num_voxels\": " << p.num_voxels << ", \"num_parts\": " << p.num_parts
      << ", \"facing\": \"" << toString(p.facing) << "\""
      << ", \"age\": " << p.age << ", \"last_seen\": " << number(p.last_seen, 17)
      << ", \"split_from\": " << p.split_from << ", \"surface_id\": " << p.surface_id
      << ", \"hull\": [";
  for (std::size_t h = 0; h < p.hull.size(); ++h) out << (h ? ", " : "") << vec3(p.hull[h]);
  out << "], \"outline\": [";
  for (std::size_t r = 0; r < p.outline.size(); ++r) {
    out << (r ? ", " : "") << "[";
    for (std::size_t k = 0; k < p.outline[r].size(); ++k) {
      out << (k ? ", " : "") << vec3(p.outline[r][k]);
    }
    out << "]";
  }
  out << "]}";
}

std::string matrixJson(const Eigen::Isometry3d& transform) {
  const Eigen::Matrix4d m = transform.matrix();
  std::string text = "[";
  for (int r = 0; r < 4; ++r) {
    text += r ? ", [" : "[";
    for (int c = 0; c < 4; ++c) text += (c ? ", " : "") + number(m(r, c), 9);
    text += "]";
  }
  return text + "]";
}

std::string orientationJson(const Eigen::Isometry3d& sensor_to_reference) {
  const Eigen::Vector3d up = upInSensor(sensor_to_reference);
  return "\"sensor_to_reference\": " + matrixJson(sensor_to_reference) + ", \"up_in_sensor\": [" +
         number(up.x(), 9) + ", " + number(up.y(), 9) + ", " + number(up.z(), 9) + "]";
}

std::string levellingJson(const UpEstimate& e) {
  std::string text = std::string("{\"source\": \"") + (e.refinement ? "refined" : "scene") +
                     "\", \"up_in_sensor\": " + vec3(e.up_in_sensor) +
                     ", \"support_area_m2\": " + number(e.support_area) +
                     ", \"angle_spread_deg\": " + number(e.angle_spread_deg) +
                     ", \"level_surfaces\": " + std::to_string(e.level_surfaces) +
                     ", \"level_heights\": " + std::to_string(e.level_heights) + ", \"prior\": \"" +
                     toString(e.prior) + "\"";
  if (e.prior == UpPrior::kCamera) {
    text += ", \"pitch_deg\": " + number(e.pitch_deg) + ", \"roll_deg\": " + number(e.roll_deg);
  }
  if (e.refinement) {
    text += ", \"correction_deg\": " + number(e.correction_deg) +
            ", \"resolution_deg\": " + number(e.resolution_deg) +
            ", \"applied\": " + (e.applied ? "true" : "false") + ", \"note\": \"" + escape(e.note) +
            "\"";
  }
  return text + ", \"ms\": " + number(e.time_ms) + "}";
}

void writeObjectJson(std::ostream& out, const StandingObject& o) {
  out << "{\"index\": " << o.index << ", \"plane_id\": " << o.plane_id
      << ", \"num_points\": " << o.num_points << ", \"centroid\": " << vec3(o.centroid)
      << ", \"box\": {\"centre\": " << vec3(o.box_centre) << ", \"yaw\": " << number(o.yaw)
      << ", \"size\": " << vec3(o.box_size) << "}, \"height_above_plane\": " << number(o.height)
      << ", \"footprint\": [";
  for (std::size_t k = 0; k < o.footprint.size(); ++k)
    out << (k ? ", " : "") << vec3(o.footprint[k]);
  out << "]}";
}

void writePlacementJson(std::ostream& out, const Placement& p) {
  out << "{\"plane_id\": " << p.plane_id << ", \"x\": " << number(p.centre.x(), 9)
      << ", \"y\": " << number(p.centre.y(), 9) << ", \"z\": " << number(p.centre.z(), 9)
      << ", \"yaw\": " << number(p.yaw) << ", \"margin\": " << number(p.margin) << "}";
}

void writeJson(std::ostream& out, const Result& result, const UpEstimate* levelling,
               const std::vector<Placement>* placements) {
  out << "{\n  \"planes\": [";
  for (std::size_t k = 0; k < result.planes.size(); ++k) {
    out << (k ? "," : "") << "\n    ";
    writePlaneJson(out, result.planes[k]);
  }
  out << "\n  ],\n  \"objects\": [";
  for (std::size_t k = 0; k < result.objects.size(); ++k) {
    out << (k ? "," : "") << "\n    ";
    writeObjectJson(out, result.objects[k]);
  }
  out << (result.objects.empty() ? "]" : "\n  ]");
  if (placements) {
    out << ",\n  \"placements\": [";
    for (std::size_t k = 0; k < placements->size(); ++k) {
      out << (k ? "," : "") << "\n    ";
      writePlacementJson(out, (*placements)[k]);
    }
    out << (placements->empty() ? "]" : "\n  ]");
  }
  const StageTimings& t = result.timings;
  out << ",\n  " << orientationJson(result.sensor_to_reference) << ",\n";
  if (levelling) out << "  \"levelling\": " << levellingJson(*levelling) << ",\n";
  out << "  \"stats\": {\"input_points\": " << result.input_points
      << ", \"finite_points\": " << result.finite_points << ", \"voxels\": " << result.voxels
      << ", \"candidates\": " << result.candidates << ", \"clusters\": " << result.clusters
      << ", \"rejected_by_refinement\": " << result.rejected_by_refinement
      << ", \"rejected_by_band_or_area\": " << result.rejected_by_band_or_area
      << ", \"merged_fragments\": " << result.merged_fragments
      << ", \"bridged_voxels\": " << result.bridged_voxels << "},\n"
      << "  \"warnings\": [";
  for (std::size_t w = 0; w < result.warnings.size(); ++w) {
    out << (w ? ", " : "") << "\"" << escape(result.warnings[w]) << "\"";
  }
  out << "],\n  \"timings_ms\": {\"alignment\": " << number(t.alignment_ms)
      << ", \"grid_filter\": " << number(t.grid_filter_ms)
      << ", \"normals\": " << number(t.normals_ms)
      << ", \"candidates\": " << number(t.candidates_ms)
      << ", \"clustering\": " << number(t.clustering_ms)
      << ", \"refinement\": " << number(t.refinement_ms)
      << ", \"description\": " << number(t.description_ms)
      << ", \"merging\": " << number(t.merging_ms) << ", \"objects\": " << number(t.objects_ms)
      << ", \"total\": " << number(t.total_ms) << "}\n}\n";
}

double median(std::vector<double> values) {
  if (values.empty()) return NAN;
  std::sort(values.begin(), values.end());
  const std::size_t n = values.size();
  return n % 2 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]);
}

}  // namespace tools
}  // namespace hope
