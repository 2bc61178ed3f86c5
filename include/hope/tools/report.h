// Human-readable and JSON reports of an extraction.
#pragma once

#include <ostream>
#include <string>
#include <vector>

#include "hope/extractor.h"
#include "hope/placement.h"
#include "hope/up_estimation.h"

namespace hope {
namespace tools {

// A table: id, height, area, points, bbox; then counts and stage timings.
void printTable(std::ostream& out, const Result& result);

// {"planes": [{"id", "height", "bbox", "centroid", "normal", "area", "free_area", "num_points",
// "hull", …}], "objects": [{"index", "plane_id", "num_points", "centroid", "box": {"centre",
// "yaw", "size"}, "height_above_plane", "footprint"}], "placements": [{"plane_id", "x", "y", "z",
// "yaw", "margin"}] (when given), "sensor_to_reference": 4×4 row-major, "up_in_sensor": [x, y, z],
// "levelling": {…} (when up was estimated or refined from the scene), "stats": {…},
// "timings_ms": {…}}
void writeJson(std::ostream& out, const Result& result, const UpEstimate* levelling = nullptr,
               const std::vector<Placement>* placements = nullptr);

// A transform as a JSON array of its 4 x 4 matrix's rows, 9 significant digits.
std::string matrixJson(const Eigen::Isometry3d& transform);

// The orientation a result was extracted with, as JSON members (no braces):
// "sensor_to_reference": [[…], […], […], […]], "up_in_sensor": [x, y, z].
std::string orientationJson(const Eigen::Isometry3d& sensor_to_reference);

// What up from the scene found, as a JSON object: "source" ("scene" or "refined"), "up_in_sensor",
// "support_area_m2", "angle_spread_deg", "level_surfaces", "level_heights", "prior", "pitch_deg",
// "roll_deg", "ms", and for a refinement "correction_deg", "resolution_deg" (the tilt the level
// surfaces can tell), "applied" and "note".
std::string levellingJson(const UpEstimate& estimate);

// One plane as a JSON object on one line: every field of hope::HorizontalPlane.
void writePlaneJson(std::ostream& out, const HorizontalPlane& plane);

// One object as a JSON object on one line, as writeJson's "objects" hold them.
void writeObjectJson(std::ostream& out, const StandingObject& object);

// A string as a JSON string literal: quotes added, control characters escaped, bytes that are
// not valid UTF-8 written as \u00NN (read as Latin-1), so the JSON is valid whatever the bytes.
std::string jsonString(const std::string& text);

// A timestamp as text that reads back as the same double: "%.6f" (TUM's form) when that
// round-trips, all 17 significant digits otherwise (1e45 included); never cut.
std::string stampText(double stamp);

// The middle value (the mean of the two middle ones for an even count); NaN for none.
double median(std::vector<double> values);

}  // namespace tools
}  // namespace hope
