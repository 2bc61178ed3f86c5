#include "hope/tools/cloud_file_check.h"

#include <sys/stat.h>

#include <cctype>
#include <cerrno>
#include <cstring>
#include <fstream>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <vector>

namespace hope {
namespace tools {

namespace {

// A header longer than this is not a header (PCD and PLY headers are a few hundred bytes).
constexpr std::size_t kMaxHeaderBytes = 1 << 20;
// LZF, PCD's compression, emits at least one 3-byte token per 264 bytes of output: no
// valid compressed block expands more than ~88 times.
constexpr std::uint64_t kMaxLzfExpansion = 90;

[[noreturn]] void fail(const std::string& path, const std::string& what) {
  throw std::runtime_error("'" + path + "' " + what);
}

std::string lowerExtension(const std::string& path) {
  const std::size_t dot = path.rfind('.');
  if (dot == std::string::npos || path.find('/', dot) != std::string::npos) return "";
  std::string ext = path.substr(dot);
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return ext;
}

// a · b, or false when it overflows 64 bits.
bool multiply(std::uint64_t a, std::uint64_t b, std::uint64_t& product) {
  if (a != 0 && b > std::numeric_limits<std::uint64_t>::max() / a) return false;
  product = a * b;
  return true;
}

bool add(std::uint64_t a, std::uint64_t b, std::uint64_t& sum) {
  if (b > std::numeric_limits<std::uint64_t>::max() - a) return false;
  sum = a + b;
  return true;
}

// A whole decimal unsigned number, at most `max`.
bool parseCount(const std::string& text, std::uint64_t max, std::uint64_t& value) {
  if (text.empty() || text.size() > 20) return false;
  std::uint64_t v = 0;
  for (char c : text) {
    if (c < '0' || c > '9') return false;
    if (!multiply(v, 10, v) || !add(v, static_cast<std::uint64_t>(c - '0'), v)) return false;
  }
  if (v > max) return false;
  value = v;
  return true;
}

std::vector<std::string> tokens(const std::string& line) {
  std::istringstream in(line);
  std::vector<std::string> out;
  std::string t;
  while (in >> t) out.push_back(t);
  return out;
}

// Reads header lines up to and including the one whose first token is `last`; returns them
// and sets `data_offset` to the byte after that line.
std::vector<std::vector<std::string>> readHeader(const std::string& path, const char* last,
                                                 const char* format, std::uint64_t& data_offset) {
  std::ifstream in(path, std::ios::binary);
  if (!in) fail(path, "cannot be opened: " + std::string(std::strerror(errno)));
  std::vector<std::vector<std::string>> lines;
  std::string line;
  std::size_t consumed = 0;
  while (consumed < kMaxHeaderBytes && std::getline(in, line)) {
    consumed += line.size() + 1;
    std::vector<std::string> t = tokens(line);
    if (t.empty() || t[0][0] == '#') continue;
    lines.push_back(t);
    if (t[0] == last) {
      data_offset = consumed;
      return lines;
    }
  }
  fail(path,
       std::string("is not a ") + format + " file (no '" + last + "' line in its first megabyte)");
}

void checkPcd(const std::string& path, std::uint64_t file_size, std::uint64_t max_points) {
  std::uint64_t data_offset = 0;
  const auto lines = readHeader(path, "DATA", "PCD", data_offset);
  std::vector<std::string> fields, sizes, types, counts;
  std::uint64_t width = 0, height = 1, points = 0;
  bool has_width = false, has_points = false;
  const std::uint64_t max32 = std::numeric_limits<std::uint32_t>::max();
  std::string data;
  for (const auto& t : lines) {
    const std::string& key = t[0];
    const std::vector<std::string> rest(t.begin() + 1, t.end());
    auto count = [&](std::uint64_t& value) {
      if (rest.size() != 1 || !parseCount(rest[0], max32, value)) {
        fail(path, "has a malformed " + key + " line (expected one number up to 2^32 - 1)");
      }
    };
    if (key == "FIELDS") {
      fields = rest;
    } else if (key == "SIZE") {
      sizes = rest;
    } else if (key == "TYPE") {
      types = rest;
    } else if (key == "COUNT") {
      counts = rest;
    } else if (key == "WIDTH") {
      count(width);
      has_width = true;
    } else if (key == "HEIGHT") {
      count(height);
    } else if (key == "POINTS") {
      count(points);
      has_points = true;
    } else if (key == "DATA") {
      data = rest.empty() ? "" : rest[0];
    }
  }
  if (fields.empty()) fail(path, "is not a PCD file (no FIELDS line)");
  if (sizes.size() != fields.size() || types.size() != fields.size() ||
      (!counts.empty() && counts.size() != fields.size())) {
    fail(path, "has a malformed PCD header: FIELDS, SIZE, TYPE and COUNT differ in length");
  }
  if (!has_width) fail(path, "has no WIDTH line");
  std::uint64_t declared = 0;
  multiply(width, height, declared);  // both below 2^32: cannot overflow 64 bits
  if (has_points && points != declared) {
    fail(path, "has WIDTH " + std::to_string(width) + " x HEIGHT " + std::to_string(height) +
                   " != POINTS " + std::to_string(points));
  }
  if (declared > max_points) {
    fail(path, "claims " + std::to_string(declared) + " points, more than the cap of " +
                   std::to_string(max_points) + " (raise it with --max-points)");
  }
  std::uint64_t point_bytes = 0, values_per_point = 0;
  for (std::size_t f = 0; f < fields.size(); ++f) {
    std::uint64_t size = 0, count = 1;
    if (!parseCount(sizes[f], 8, size) || (size != 1 && size != 2 && size != 4 && size != 8)) {
      fail(path, "field '" + fields[f] + "' has SIZE '" + sizes[f] + "' (expected 1, 2, 4 or 8)");
    }
    if (types[f] != "F" && types[f] != "I" && types[f] != "U") {
      fail(path, "field '" + fields[f] + "' has TYPE '" + types[f] + "' (expected F, I or U)");
    }
    if (types[f] == "F" && size != 4 && size != 8) {
      fail(path, "field '" + fields[f] + "' is a float of SIZE " + sizes[f]);
    }
    if (!counts.empty() && (!parseCount(counts[f], max32, count) || count == 0)) {
      fail(path, "field '" + fields[f] + "' has COUNT '" + counts[f] + "'");
    }
    // At most 2^32 fields of 8 · 2^32 bytes each: the sums stay far below 2^64.
    point_bytes += size * count;
    values_per_point += count;
  }
  const std::uint64_t available = file_size > data_offset ? file_size - data_offset : 0;
  std::uint64_t needed = 0;
  const bool fits = multiply(declared, point_bytes, needed);
  const std::string claim =
      std::to_string(declared) + " points of " + std::to_string(point_bytes) + " bytes";
  if (data == "binary") {
    if (!fits || needed > available) {
      fail(path, "is truncated: its header claims " + claim + ", the file holds " +
                     std::to_string(available) + " bytes of data");
    }
  } else if (data == "ascii") {
    // Each value takes at least one character and one separator.
    std::uint64_t least = 0;
    if (!multiply(declared, values_per_point, least) || least > available) {
      fail(path, "is truncated: its header claims " + claim + ", the file holds " +
                     std::to_string(available) + " bytes of text");
    }
  } else if (data == "binary_compressed") {
    std::ifstream in(path, std::ios::binary);
    in.seekg(static_cast<std::streamoff>(data_offset));
    std::uint32_t sizes_le[2] = {0, 0};
    in.read(reinterpret_cast<char*>(sizes_le), sizeof(sizes_le));
    if (!in) fail(path, "is truncated: no compressed block after its header");
    const std::uint64_t compressed = sizes_le[0], uncompressed = sizes_le[1];
    if (compressed + 8 > available) {
      fail(path, "is truncated: its compressed block claims " + std::to_string(compressed) +
                     " bytes, the file holds " + std::to_string(available - 8));
    }
    if (!fits || uncompressed != needed) {
      fail(path, "is inconsistent: its header claims " + claim + ", the compressed block " +
                     std::to_string(uncompressed) + " bytes");
    }
    if (needed > compressed * kMaxLzfExpansion + 1024) {
      fail(path, "claims " + std::to_string(needed) + " bytes from a compressed block of " +
                     std::to_string(compressed) + " bytes, more than LZF can expand to");
    }
  } else {
    fail(path, "has DATA '" + data + "' (expected ascii, binary or binary_compressed)");
  }
}

std::uint64_t plyTypeSize(const std::string& type) {
  if (type == "char" || type == "uchar" || type == "int8" || type == "uint8") return 1;
  if (type == "short" || type == "ushort" || type == "int16" || type == "uint16") return 2;
  if (type == "int" || type == "uint" || type == "int32" || type == "uint32" || type == "float" ||
      type == "float32") {
    return 4;
  }
  if (type == "double" || type == "float64") return 8;
  return 0;
}

void checkPly(const std::string& path, std::uint64_t file_size, std::uint64_t max_points) {
  {
    std::ifstream in(path, std::ios::binary);
    char magic[4] = {0, 0, 0, 0};
    in.read(magic, 4);
    if (!in || std::strncmp(magic, "ply", 3) != 0 || (magic[3] != '\n' && magic[3] != '\r')) {
      fail(path, "is not a PLY file (it does not start with 'ply')");
    }
  }
  std::uint64_t data_offset = 0;
  const auto lines = readHeader(path, "end_header", "PLY", data_offset);
  bool ascii = false, has_format = false;
  // Per element: its count and the fewest bytes one item can take.
  std::vector<std::pair<std::uint64_t, std::uint64_t>> elements;
  bool has_vertex = false;
  for (const auto& t : lines) {
    if (t[0] == "format") {
      if (t.size() < 2 ||
          (t[1] != "ascii" && t[1] != "binary_little_endian" && t[1] != "binary_big_endian")) {
        fail(path, "has an unknown PLY format line");
      }
      ascii = t[1] == "ascii";
      has_format = true;
    } else if (t[0] == "element") {
      std::uint64_t count = 0;
      if (t.size() != 3 || !parseCount(t[2], std::numeric_limits<std::uint32_t>::max(), count)) {
        fail(path, "has a malformed element line (expected 'element NAME COUNT')");
      }
      if (t[1] == "vertex") {
        has_vertex = true;
        if (count > max_points) {
          fail(path, "claims " + std::to_string(count) + " vertices, more than the cap of " +
                         std::to_string(max_points) + " (raise it with --max-points)");
        }
      }
      elements.emplace_back(count, 0);
    } else if (t[0] == "property") {
      if (elements.empty()) fail(path, "has a property before any element");
      std::uint64_t least = 0;
      if (t.size() == 5 && t[1] == "list") {
        least = plyTypeSize(t[2]);  // an empty list is just its count
        if (least == 0 || plyTypeSize(t[3]) == 0) fail(path, "has a list of an unknown type");
      } else if (t.size() == 3) {
        least = plyTypeSize(t[1]);
        if (least == 0) fail(path, "property '" + t[2] + "' has unknown type '" + t[1] + "'");
      } else {
        fail(path, "has a malformed property line");
      }
      elements.back().second += ascii ? 2 : least;  // ascii: a digit and a separator
    }
  }
  if (!has_format) fail(path, "has no PLY format line");
  if (!has_vertex) fail(path, "has no vertex element");
  const std::uint64_t available = file_size > data_offset ? file_size - data_offset : 0;
  std::uint64_t least = 0;
  for (const auto& e : elements) {
    std::uint64_t bytes = 0;
    if (!multiply(e.first, e.second, bytes) || !add(least, bytes, least) || least > available) {
      fail(path, "is truncated: its header claims more elements than the " +
                     std::to_string(available) + " bytes of data can hold");
    }
  }
}

}  // namespace

std::uint64_t requireRegularFile(const std::string& path) {
  struct stat info;
  if (::stat(path.c_str(), &info) != 0) {
    fail(path, "cannot be opened: " + std::string(std::strerror(errno)));
  }
  if (!S_ISREG(info.st_mode)) {
    fail(path, std::string("is not a regular file (") +
                   (S_ISDIR(info.st_mode)    ? "a directory"
                    : S_ISFIFO(info.st_mode) ? "a FIFO"
                    : S_ISCHR(info.st_mode)  ? "a character device"
                                             : "a device or socket") +
                   ")");
  }
  std::ifstream probe(path);
  if (!probe) fail(path, "cannot be opened: " + std::string(std::strerror(errno)));
  if (info.st_size == 0) fail(path, "is empty");
  return static_cast<std::uint64_t>(info.st_size);
}

CloudFormat checkCloudFile(const std::string& path, std::uint64_t max_points) {
  const std::string ext = lowerExtension(path);
  if (ext != ".pcd" && ext != ".ply") fail(path, "is neither .pcd nor .ply");
  const std::uint64_t size = requireRegularFile(path);
  if (ext == ".pcd") {
    checkPcd(path, size, max_points);
    return CloudFormat::kPcd;
  }
  checkPly(path, size, max_points);
  return CloudFormat::kPly;
}

}  // namespace tools
}  // namespace hope
