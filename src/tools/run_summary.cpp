#include "hope/tools/run_summary.h"

#include <cctype>

namespace hope {
namespace tools {

namespace {

// `text` with every run of digits (and the decimal points and signs between them) written as
// '#': the kind of a warning whose numbers change from frame to frame.
std::string withNumbersBlanked(const std::string& text) {
  std::string kind;
  for (std::size_t i = 0; i < text.size(); ++i) {
    const unsigned char c = static_cast<unsigned char>(text[i]);
    if (std::isdigit(c)) {
      if (kind.empty() || kind.back() != '#') kind += '#';
    } else if ((c == '.' || c == '-' || c == 'e') && !kind.empty() && kind.back() == '#' &&
               i + 1 < text.size() && std::isdigit(static_cast<unsigned char>(text[i + 1]))) {
      // inside a number: 3.25, 1e-05
    } else {
      kind += static_cast<char>(c);
    }
  }
  return kind;
}

}  // namespace

std::string withFile(const std::string& file, const std::string& reason) {
  return reason.find(file) != std::string::npos ? reason : file + ": " + reason;
}

void RunSummary::add(std::vector<Tally>& tallies, const std::string& kind,
                     const std::string& first) {
  for (Tally& t : tallies) {
    if (t.kind == kind) {
      ++t.count;
      return;
    }
  }
  tallies.push_back({kind, 1, first});
}

void RunSummary::skipFrame(const std::string& kind, const std::string& file,
                           const std::string& reason) {
  add(skipped_frames_, kind, withFile(file, reason));
}

void RunSummary::warn(const std::string& file, const std::string& warning) {
  add(warnings_, withNumbersBlanked(warning), file + ": " + warning);
}

void RunSummary::skipLine(const std::string& problem) { skipped_lines_.push_back(problem); }

std::size_t RunSummary::skippedFrames() const {
  std::size_t n = 0;
  for (const Tally& t : skipped_frames_) n += t.count;
  return n;
}

void RunSummary::print(std::ostream& err, const std::string& tool) const {
  if (!skipped_lines_.empty()) {
    err << tool << ": warning: skipped " << skipped_lines_.size()
        << " line(s) that could not be read (the first: " << skipped_lines_.front() << ")\n";
  }
  for (const Tally& t : skipped_frames_) {
    err << tool << ": warning: skipped " << t.count << " frame(s): " << t.kind
        << " (the first: " << t.first << ")\n";
  }
  for (const Tally& t : warnings_) {
    err << tool << ": warning on " << t.count << " frame(s), the first: " << t.first << "\n";
  }
}

}  // namespace tools
}  // namespace hope
