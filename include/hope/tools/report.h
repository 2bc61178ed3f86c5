// Human-readable and JSON reports of an extraction.
#pragma once

#include <ostream>
#include <string>

#include "hope/extractor.h"

namespace hope {
namespace tools {

// A table: id, height, area, points, bbox; then counts and stage timings.
void printTable(std::ostream& out, const Result& result);

// {"planes": [{"id", "height", "bbox", "centroid", "normal", "area", "num_points", "hull",
// …}], "stats": {…}, "timings_ms": {…}}
void writeJson(std::ostream& out, const Result& result);

// One plane as a JSON object on one line: every field of hope::HorizontalPlane.
void writePlaneJson(std::ostream& out, const HorizontalPlane& plane);

// A string as a JSON string literal (quotes added, control characters replaced).
std::string jsonString(const std::string& text);

}  // namespace tools
}  // namespace hope
