// Section 8 of docs/evaluation.md: up from the scene (up_estimation.h) measured against the
// truth on every cloud whose up is known, beside the −y tilt search hope_eval used before.
#pragma once

#include <ostream>
#include <string>
#include <vector>

namespace hope {
namespace tools {

// Writes the section to `md` and returns its headline claims ("Met: …" / "**Missed**: …").
std::vector<std::string> writeLevellingSection(std::ostream& md, const std::string& data_dir,
                                               bool quick);

}  // namespace tools
}  // namespace hope
