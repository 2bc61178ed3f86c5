#include "hope/tools/output_file.h"

#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <stdexcept>
#include <vector>

namespace hope {
namespace tools {

void throwCannotWrite(const std::string& path) {
  const int error = errno;
  throw std::runtime_error("cannot write '" + path + "'" +
                           (error ? std::string(": ") + std::strerror(error) : std::string()));
}

OutputFile::OutputFile(const std::string& path) : path_(path) {
  if (path.empty()) throw std::invalid_argument("an output file name is empty");
  struct stat info;
  if (::stat(path.c_str(), &info) == 0 && !S_ISREG(info.st_mode)) {
    if (S_ISDIR(info.st_mode)) throw std::runtime_error("cannot write '" + path + "': a directory");
    return;  // a device or FIFO: write it directly, there is nothing to rename over
  }
  const std::size_t slash = path.rfind('/');
  const std::string dir = slash == std::string::npos ? "" : path.substr(0, slash + 1);
  const std::string base = path.substr(dir.size());
  const std::size_t dot = base.rfind('.');
  const std::string ext = dot == std::string::npos || dot == 0 ? "" : base.substr(dot);
  // A hidden name in the same folder, so the rename stays within one file system.
  std::string pattern = dir + "." + base + ".XXXXXX" + ext;
  std::vector<char> name(pattern.begin(), pattern.end());
  name.push_back('\0');
  errno = 0;
  const int fd = ::mkstemps(name.data(), static_cast<int>(ext.size()));
  if (fd < 0) throwCannotWrite(path);
  // mkstemps makes the file private (0600); give it the permissions a plain open would.
  const mode_t mask = ::umask(0);
  ::umask(mask);
  ::fchmod(fd, 0666 & ~mask);
  ::close(fd);
  temp_ = name.data();
}

OutputFile::OutputFile(OutputFile&& other) noexcept
    : path_(std::move(other.path_)), temp_(std::move(other.temp_)) {
  other.temp_.clear();
}

OutputFile::~OutputFile() {
  if (!temp_.empty()) std::remove(temp_.c_str());
}

void OutputFile::commit() {
  if (temp_.empty()) return;
  errno = 0;
  if (std::rename(temp_.c_str(), path_.c_str()) != 0) throwCannotWrite(path_);
  temp_.clear();
}

void writeText(const OutputFile& file, const std::function<void(std::ostream&)>& write) {
  errno = 0;
  std::ofstream out(file.writePath(), std::ios::out | std::ios::trunc);
  if (!out) throwCannotWrite(file.path());
  write(out);
  out.flush();
  if (!out) throwCannotWrite(file.path());
  out.close();
  if (out.fail()) throwCannotWrite(file.path());
}

}  // namespace tools
}  // namespace hope
