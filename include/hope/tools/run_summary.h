// What a sequence run left out and warned about, said once per kind with a count: a recording
// of thousands of frames must not print a thousand identical lines, nor hide the one problem.
#pragma once

#include <cstddef>
#include <ostream>
#include <string>
#include <vector>

namespace hope {
namespace tools {

// A frame's error as said: a reason that names its file already as it is, otherwise the file
// first.
std::string withFile(const std::string& file, const std::string& reason);

class RunSummary {
 public:
  // A frame not used. `kind` is how it is counted ("could not be read", "nothing level in
  // view"); `reason` the error, shown for the first frame of each kind.
  void skipFrame(const std::string& kind, const std::string& file, const std::string& reason);
  // A warning of the extraction on `file`. Warnings are counted by kind: the text with its
  // numbers blanked, so that "3.2 % of points" and "4.1 % of points" are one kind.
  void warn(const std::string& file, const std::string& warning);
  // A line of a list or orientation file that was skipped ("file:line: reason").
  void skipLine(const std::string& problem);

  std::size_t skippedFrames() const;

  // "<tool>: warning: …" lines: skipped lines, skipped frames, warnings, one line per kind.
  void print(std::ostream& err, const std::string& tool) const;

 private:
  struct Tally {
    std::string kind;
    std::size_t count = 0;
    std::string first;  // the first occurrence, with its file
  };
  static void add(std::vector<Tally>& tallies, const std::string& kind, const std::string& first);
  std::vector<Tally> skipped_frames_, warnings_;  // in order of first appearance
  std::vector<std::string> skipped_lines_;
};

}  // namespace tools
}  // namespace hope
