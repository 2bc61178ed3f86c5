// Output files that are complete or absent: written under a temporary name beside the
// destination and renamed into place only when every write succeeded.
#pragma once

#include <functional>
#include <ostream>
#include <string>

namespace hope {
namespace tools {

class OutputFile {
 public:
  // Creates the temporary file now, so an unwritable destination (a missing folder, no
  // permission) fails before any work is done: std::runtime_error "cannot write 'PATH': why".
  // A destination that exists and is not a regular file (/dev/stdout, /dev/full, a FIFO) is
  // written directly, without a temporary.
  explicit OutputFile(const std::string& path);
  OutputFile(OutputFile&& other) noexcept;
  OutputFile(const OutputFile&) = delete;
  OutputFile& operator=(const OutputFile&) = delete;
  OutputFile& operator=(OutputFile&&) = delete;
  // Removes the temporary file unless commit() succeeded.
  ~OutputFile();

  const std::string& path() const { return path_; }
  // Where writers write until commit(): the temporary file (with the destination's
  // extension, so writers that choose a format by extension still do).
  const std::string& writePath() const { return temp_.empty() ? path_ : temp_; }
  // Renames the temporary file into place; throws std::runtime_error on failure.
  void commit();

 private:
  std::string path_;
  std::string temp_;  // empty when writing directly
};

// Writes text into `file` through `write` and checks that all of it reached the file
// (flush and close included); throws std::runtime_error "cannot write 'PATH': why".
void writeText(const OutputFile& file, const std::function<void(std::ostream&)>& write);

// "cannot write 'PATH': <strerror(errno)>" as a std::runtime_error.
[[noreturn]] void throwCannotWrite(const std::string& path);

}  // namespace tools
}  // namespace hope
