#include "hope/tools/cloud_file.h"

#include <sys/stat.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <vector>

#include "hope/plane_colors.h"

namespace hope {
namespace tools {

namespace {

// A header longer than this is not a header (PCD and PLY headers are a few hundred bytes).
constexpr std::size_t kMaxHeaderBytes = 1 << 20;
// LZF, PCD's compression, emits at least one 3-byte token per 264 bytes of output: no
// valid compressed block expands more than ~88 times.
constexpr std::uint64_t kMaxLzfExpansion = 90;
constexpr std::uint64_t kMax32 = std::numeric_limits<std::uint32_t>::max();

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

void checkPcd(const std::string& path, CloudFileLayout& layout, std::uint64_t max_points) {
  const auto lines = readHeader(path, "DATA", "PCD", layout.data_offset);
  std::vector<std::string> fields, sizes, types, counts;
  std::uint64_t width = 0, height = 1, points = 0;
  bool has_width = false, has_points = false;
  std::string data;
  for (const auto& t : lines) {
    const std::string& key = t[0];
    const std::vector<std::string> rest(t.begin() + 1, t.end());
    auto count = [&](std::uint64_t& value) {
      if (rest.size() != 1 || !parseCount(rest[0], kMax32, value)) {
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
  const std::uint64_t declared = width * height;  // both below 2^32: no overflow
  if (has_points && points != declared) {
    fail(path, "has WIDTH " + std::to_string(width) + " x HEIGHT " + std::to_string(height) +
                   " != POINTS " + std::to_string(points));
  }
  if (declared > max_points) {
    fail(path, "claims " + std::to_string(declared) + " points, more than the cap of " +
                   std::to_string(max_points) + " (raise it with --max-points)");
  }
  layout.width = static_cast<std::uint32_t>(width);
  layout.height = static_cast<std::uint32_t>(height);
  std::uint64_t values_per_point = 0;
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
    if (!counts.empty() && (!parseCount(counts[f], kMax32, count) || count == 0)) {
      fail(path, "field '" + fields[f] + "' has COUNT '" + counts[f] + "'");
    }
    FileField field;
    field.name = fields[f];
    field.type = types[f][0];
    field.size = static_cast<std::uint32_t>(size);
    field.count = static_cast<std::uint32_t>(count);
    field.offset = layout.point_bytes;
    layout.fields.push_back(field);
    // At most 2^32 fields of 8 · 2^32 bytes each: the sums stay far below 2^64.
    layout.point_bytes += size * count;
    values_per_point += count;
  }
  const std::uint64_t available =
      layout.file_size > layout.data_offset ? layout.file_size - layout.data_offset : 0;
  std::uint64_t needed = 0;
  const bool fits = multiply(declared, layout.point_bytes, needed);
  const std::string claim =
      std::to_string(declared) + " points of " + std::to_string(layout.point_bytes) + " bytes";
  if (data == "binary") {
    layout.encoding = CloudFileLayout::Encoding::kBinary;
    if (!fits || needed > available) {
      fail(path, "is truncated: its header claims " + claim + ", the file holds " +
                     std::to_string(available) + " bytes of data");
    }
  } else if (data == "ascii") {
    layout.encoding = CloudFileLayout::Encoding::kAscii;
    // Each value takes at least one character and one separator.
    std::uint64_t least = 0;
    if (!multiply(declared, values_per_point, least) || least > available) {
      fail(path, "is truncated: its header claims " + claim + ", the file holds " +
                     std::to_string(available) + " bytes of text");
    }
  } else if (data == "binary_compressed") {
    layout.encoding = CloudFileLayout::Encoding::kBinaryCompressed;
    std::ifstream in(path, std::ios::binary);
    in.seekg(static_cast<std::streamoff>(layout.data_offset));
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

// PLY type name → size and PCD-style type letter; size 0 for an unknown name.
std::uint32_t plyType(const std::string& name, char& type) {
  type = 'I';
  if (name == "char" || name == "int8") return 1;
  if (name == "short" || name == "int16") return 2;
  if (name == "int" || name == "int32") return 4;
  type = 'U';
  if (name == "uchar" || name == "uint8") return 1;
  if (name == "ushort" || name == "uint16") return 2;
  if (name == "uint" || name == "uint32") return 4;
  type = 'F';
  if (name == "float" || name == "float32") return 4;
  if (name == "double" || name == "float64") return 8;
  return 0;
}

void checkPly(const std::string& path, CloudFileLayout& layout, std::uint64_t max_points) {
  {
    std::ifstream in(path, std::ios::binary);
    char magic[4] = {0, 0, 0, 0};
    in.read(magic, 4);
    if (!in || std::strncmp(magic, "ply", 3) != 0 || (magic[3] != '\n' && magic[3] != '\r')) {
      fail(path, "is not a PLY file (it does not start with 'ply')");
    }
  }
  layout.format = CloudFileLayout::Format::kPly;
  const auto lines = readHeader(path, "end_header", "PLY", layout.data_offset);
  bool has_format = false, in_vertex = false, vertex_seen = false;
  // The fewest bytes of data the elements up to the vertices need.
  std::uint64_t least = 0, least_per_item = 0, current_count = 0;
  auto closeElement = [&]() {
    std::uint64_t bytes = 0;
    if (!multiply(current_count, least_per_item, bytes) || !add(least, bytes, least)) {
      fail(path, "claims more elements than any file can hold");
    }
  };
  bool open = false;
  for (const auto& t : lines) {
    if (t[0] == "format") {
      if (t.size() < 2) fail(path, "has an unknown PLY format line");
      if (t[1] == "ascii") {
        layout.encoding = CloudFileLayout::Encoding::kAscii;
      } else if (t[1] == "binary_little_endian") {
        layout.encoding = CloudFileLayout::Encoding::kBinary;
      } else if (t[1] == "binary_big_endian") {
        layout.encoding = CloudFileLayout::Encoding::kBinaryBigEndian;
      } else {
        fail(path, "has an unknown PLY format '" + t[1] + "'");
      }
      has_format = true;
    } else if (t[0] == "element") {
      if (open) closeElement();
      open = false;
      if (vertex_seen) break;  // elements after the vertices are not read
      std::uint64_t count = 0;
      if (t.size() != 3 || !parseCount(t[2], kMax32, count)) {
        fail(path, "has a malformed element line (expected 'element NAME COUNT')");
      }
      in_vertex = t[1] == "vertex";
      if (in_vertex) {
        if (count > max_points) {
          fail(path, "claims " + std::to_string(count) + " vertices, more than the cap of " +
                         std::to_string(max_points) + " (raise it with --max-points)");
        }
        vertex_seen = true;
        layout.width = static_cast<std::uint32_t>(count);
      } else {
        layout.skipped.push_back({count, {}});
      }
      current_count = count;
      least_per_item = 0;
      open = true;
    } else if (t[0] == "property") {
      if (!open) fail(path, "has a property before any element");
      const bool ascii = layout.encoding == CloudFileLayout::Encoding::kAscii;
      char type;
      if (t.size() == 5 && t[1] == "list") {
        char item_type;
        const std::uint32_t count_size = plyType(t[2], type), item_size = plyType(t[3], item_type);
        if (count_size == 0 || item_size == 0 || type == 'F') {
          fail(path, "has a list of an unknown type");
        }
        if (in_vertex) fail(path, "has a list property in its vertices; hope reads scalar ones");
        layout.skipped.back().properties.emplace_back(count_size, item_size);
        least_per_item += ascii ? 2 : count_size;  // an empty list is just its count
      } else if (t.size() == 3) {
        const std::uint32_t size = plyType(t[1], type);
        if (size == 0) fail(path, "property '" + t[2] + "' has unknown type '" + t[1] + "'");
        if (in_vertex) {
          FileField field;
          field.name = t[2];
          field.type = type;
          field.size = size;
          field.offset = layout.point_bytes;
          layout.fields.push_back(field);
          layout.point_bytes += size;
        } else {
          layout.skipped.back().properties.emplace_back(size, 0);
        }
        least_per_item += ascii ? 2 : size;  // ascii: a digit and a separator
      } else {
        fail(path, "has a malformed property line");
      }
    }
  }
  if (open) closeElement();
  if (!has_format) fail(path, "has no PLY format line");
  if (!vertex_seen) fail(path, "has no vertex element");
  const std::uint64_t available =
      layout.file_size > layout.data_offset ? layout.file_size - layout.data_offset : 0;
  if (least > available) {
    fail(path, "is truncated: its header claims more elements than the " +
                   std::to_string(available) + " bytes of data can hold");
  }
}

// --- reading ------------------------------------------------------------------------------

bool bigEndianHost() {
  const std::uint16_t probe = 1;
  std::uint8_t first;
  std::memcpy(&first, &probe, 1);
  return first == 0;
}

// One binary value of `field` at `p` as a double (integers exactly up to 2^53).
double binaryValue(const std::uint8_t* p, const FileField& field, bool swap) {
  std::uint8_t bytes[8];
  for (std::uint32_t b = 0; b < field.size; ++b) bytes[b] = swap ? p[field.size - 1 - b] : p[b];
  switch (field.type) {
    case 'F':
      if (field.size == 8) {
        double d;
        std::memcpy(&d, bytes, 8);
        return d;
      } else {
        float f;
        std::memcpy(&f, bytes, 4);
        return f;
      }
    case 'I': {
      std::int64_t v = 0;
      std::memcpy(&v, bytes, field.size);  // little-endian host assumed for integers
      const int shift = 64 - 8 * static_cast<int>(field.size);
      return static_cast<double>((v << shift) >> shift);
    }
    default: {
      std::uint64_t v = 0;
      std::memcpy(&v, bytes, field.size);
      return static_cast<double>(v);
    }
  }
}

// The raw 32 bits of a packed PCD colour field (float or unsigned), as PCL writes it.
std::uint32_t packedColor(const std::uint8_t* p, const FileField& field) {
  std::uint32_t rgb = 0;
  if (field.size == 4) std::memcpy(&rgb, p, 4);
  return rgb;
}

struct Roles {
  const FileField* x = nullptr;
  const FileField* y = nullptr;
  const FileField* z = nullptr;
  const FileField* packed = nullptr;  // PCD rgb / rgba
  const FileField* red = nullptr;     // PLY red, green, blue
  const FileField* green = nullptr;
  const FileField* blue = nullptr;
};

Roles rolesOf(const std::string& path, const CloudFileLayout& layout) {
  Roles r;
  for (const FileField& f : layout.fields) {
    if (f.name == "x" && !r.x) r.x = &f;
    if (f.name == "y" && !r.y) r.y = &f;
    if (f.name == "z" && !r.z) r.z = &f;
    if ((f.name == "rgb" || f.name == "rgba") && f.size == 4 && f.count == 1 && !r.packed) {
      r.packed = &f;
    }
    if ((f.name == "red" || f.name == "diffuse_red") && f.size == 1) r.red = &f;
    if ((f.name == "green" || f.name == "diffuse_green") && f.size == 1) r.green = &f;
    if ((f.name == "blue" || f.name == "diffuse_blue") && f.size == 1) r.blue = &f;
  }
  const FileField* axes[3] = {r.x, r.y, r.z};
  const char* names[3] = {"x", "y", "z"};
  for (int k = 0; k < 3; ++k) {
    if (!axes[k]) fail(path, std::string("has no '") + names[k] + "' field; hope needs x, y, z");
    if (axes[k]->type != 'F' || axes[k]->count != 1) {
      fail(path, std::string("field '") + names[k] +
                     "' is not floating point; hope needs x, y, z in metres");
    }
  }
  if (!(r.red && r.green && r.blue)) r.red = r.green = r.blue = nullptr;
  return r;
}

// Decompresses one LZF block (PCD's binary_compressed) into out[0, out_size); returns the bytes
// written, or 0 when the block is malformed or does not fit. The format is a sequence of
// tokens: a control byte below 32 starts a run of (control + 1) literal bytes; any other is a
// back reference of length (control >> 5) + 2 (with one more length byte when that field is
// 7), to a distance of ((control & 31) << 8 | next byte) + 1 before the output's end. Every
// read and write is checked, so a hostile block cannot leave either buffer.
std::size_t lzfDecompress(const std::uint8_t* in, std::size_t in_size, std::uint8_t* out,
                          std::size_t out_size) {
  std::size_t i = 0, o = 0;
  while (i < in_size) {
    const std::size_t control = in[i++];
    if (control < 32) {
      const std::size_t run = control + 1;
      if (run > in_size - i || run > out_size - o) return 0;
      std::memcpy(out + o, in + i, run);
      i += run;
      o += run;
      continue;
    }
    std::size_t length = control >> 5;
    if (length == 7) {
      if (i >= in_size) return 0;
      length += in[i++];
    }
    length += 2;
    if (i >= in_size) return 0;
    const std::size_t distance = ((control & 31) << 8 | in[i++]) + 1;
    if (distance > o || length > out_size - o) return 0;
    // Byte by byte: a reference may overlap the bytes it produces (a repeated pattern).
    for (std::size_t k = 0; k < length; ++k, ++o) out[o] = out[o - distance];
  }
  return o;
}

void readBytes(const std::string& path, std::ifstream& in, std::uint64_t count,
               std::vector<std::uint8_t>& bytes) {
  bytes.resize(static_cast<std::size_t>(count));
  in.read(reinterpret_cast<char*>(bytes.data()), static_cast<std::streamsize>(count));
  if (static_cast<std::uint64_t>(in.gcount()) != count) fail(path, "is truncated");
}

// Points stored point after point (binary PCD and PLY): point i of the block at
// i · point_bytes. The common layout (native float32 x, y, z side by side) is copied whole.
void fromPointMajor(const std::uint8_t* data, std::size_t first, std::size_t count,
                    const CloudFileLayout& layout, const Roles& r, bool swap, InputCloud& cloud) {
  const bool packed_xyz = !swap && r.x->type == 'F' && r.x->size == 4 && r.y->size == 4 &&
                          r.z->size == 4 && r.y->type == 'F' && r.z->type == 'F' &&
                          r.y->offset == r.x->offset + 4 && r.z->offset == r.x->offset + 8;
  for (std::size_t k = 0; k < count; ++k) {
    const std::uint8_t* point = data + k * layout.point_bytes;
    Eigen::Vector3f& p = cloud.points[first + k];
    if (packed_xyz) {
      std::memcpy(p.data(), point + r.x->offset, 3 * sizeof(float));
    } else {
      p = Eigen::Vector3f(static_cast<float>(binaryValue(point + r.x->offset, *r.x, swap)),
                          static_cast<float>(binaryValue(point + r.y->offset, *r.y, swap)),
                          static_cast<float>(binaryValue(point + r.z->offset, *r.z, swap)));
    }
    if (r.packed)
      cloud.rgb[first + k] = packedColor(point + r.packed->offset, *r.packed) & 0xFFFFFF;
    if (r.red) {
      cloud.rgb[first + k] =
          packRgb({point[r.red->offset], point[r.green->offset], point[r.blue->offset]});
    }
  }
}

// The next whitespace-separated token of `text` from `at`, or an empty view at the end.
bool nextToken(const std::string& text, std::size_t& at, const char*& begin, std::size_t& length) {
  while (at < text.size() && std::isspace(static_cast<unsigned char>(text[at]))) ++at;
  if (at >= text.size()) return false;
  const std::size_t start = at;
  while (at < text.size() && !std::isspace(static_cast<unsigned char>(text[at]))) ++at;
  begin = text.data() + start;
  length = at - start;
  return true;
}

double parseValue(const std::string& path, const char* begin, std::size_t length) {
  const std::string token(begin, std::min<std::size_t>(length, 64));
  char* end = nullptr;
  const double v = std::strtod(token.c_str(), &end);
  if (end != token.c_str() + token.size()) fail(path, "has a value '" + token + "' in its data");
  return v;
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

CloudFileLayout checkCloudFile(const std::string& path, std::uint64_t max_points) {
  const std::string ext = lowerExtension(path);
  if (ext != ".pcd" && ext != ".ply") fail(path, "is neither .pcd nor .ply");
  CloudFileLayout layout;
  layout.file_size = requireRegularFile(path);
  if (ext == ".pcd") {
    checkPcd(path, layout, max_points);
  } else {
    checkPly(path, layout, max_points);
  }
  return layout;
}

PointsView InputCloud::view() const {
  PointsView v;
  v.data = points.empty() ? nullptr : reinterpret_cast<const std::uint8_t*>(points.data());
  v.count = points.size();
  v.stride = sizeof(Eigen::Vector3f);
  v.setShape(width, height);
  return v;
}

InputCloud readCloudFile(const std::string& path, const CloudFileLayout& layout) {
  static_assert(sizeof(Eigen::Vector3f) == 3 * sizeof(float), "points must be packed");
  const Roles r = rolesOf(path, layout);
  const bool has_color = r.packed || r.red;
  InputCloud cloud;
  cloud.points.resize(static_cast<std::size_t>(layout.points()));
  if (has_color) cloud.rgb.assign(cloud.points.size(), 0);
  cloud.width = layout.width;
  cloud.height = layout.height;
  std::ifstream in(path, std::ios::binary);
  in.seekg(static_cast<std::streamoff>(layout.data_offset));
  if (!in) fail(path, "cannot be read past its header");
  const bool big = layout.encoding == CloudFileLayout::Encoding::kBinaryBigEndian;
  const bool swap = big != bigEndianHost();
  using Encoding = CloudFileLayout::Encoding;

  if (layout.encoding == Encoding::kAscii) {
    std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    std::size_t at = 0;
    const char* begin = nullptr;
    std::size_t length = 0;
    // PLY elements before the vertices: one item per line.
    for (const auto& element : layout.skipped) {
      for (std::uint64_t item = 0; item < element.count; ++item) {
        const std::size_t eol = text.find('\n', at);
        if (eol == std::string::npos) fail(path, "is truncated in an element before its vertices");
        at = eol + 1;
      }
    }
    for (std::size_t i = 0; i < cloud.size(); ++i) {
      Eigen::Vector3f& p = cloud.points[i];
      std::uint8_t channel[3] = {0, 0, 0};
      for (const FileField& f : layout.fields) {
        for (std::uint32_t c = 0; c < f.count; ++c) {
          if (!nextToken(text, at, begin, length)) {
            fail(path, "is truncated: point " + std::to_string(i) + " of " +
                           std::to_string(cloud.size()) + " is missing values");
          }
          if (c > 0) continue;
          if (&f == r.x || &f == r.y || &f == r.z) {
            const float v = static_cast<float>(parseValue(path, begin, length));
            p[&f == r.x ? 0 : &f == r.y ? 1 : 2] = v;
          } else if (&f == r.packed) {
            // PCL writes a float rgb as the float whose bits are the colour.
            const double v = parseValue(path, begin, length);
            std::uint32_t rgb = 0;
            if (f.type == 'F') {
              const float packed = static_cast<float>(v);
              std::memcpy(&rgb, &packed, 4);
            } else if (v >= 0 && v <= 4294967295.0) {
              rgb = static_cast<std::uint32_t>(v);
            }
            cloud.rgb[i] = rgb & 0xFFFFFF;
          } else if (&f == r.red || &f == r.green || &f == r.blue) {
            const double v = parseValue(path, begin, length);
            channel[&f == r.red     ? 0
                    : &f == r.green ? 1
                                    : 2] = static_cast<std::uint8_t>(v >= 0 && v <= 255 ? v : 0);
          }
        }
      }
      if (r.red) cloud.rgb[i] = packRgb({channel[0], channel[1], channel[2]});
    }
    return cloud;
  }

  if (layout.encoding == Encoding::kBinaryCompressed) {
    std::uint32_t sizes[2];
    in.read(reinterpret_cast<char*>(sizes), sizeof(sizes));
    std::vector<std::uint8_t> compressed;
    readBytes(path, in, sizes[0], compressed);
    std::vector<std::uint8_t> data(sizes[1]);
    if (sizes[1] > 0 &&
        lzfDecompress(compressed.data(), sizes[0], data.data(), sizes[1]) != sizes[1]) {
      fail(path, "has a compressed block that does not decompress to its size");
    }
    // Stored field after field: field f of point i at start_f + i · size_f · count_f.
    std::uint64_t start = 0;
    std::vector<std::uint64_t> starts;
    for (const FileField& f : layout.fields) {
      starts.push_back(start);
      start += std::uint64_t(f.size) * f.count * cloud.size();
    }
    auto at = [&](const FileField* f, std::size_t i) {
      const std::size_t k = static_cast<std::size_t>(f - layout.fields.data());
      return data.data() + starts[k] + i * std::uint64_t(f->size) * f->count;
    };
    for (std::size_t i = 0; i < cloud.size(); ++i) {
      cloud.points[i] = Eigen::Vector3f(static_cast<float>(binaryValue(at(r.x, i), *r.x, false)),
                                        static_cast<float>(binaryValue(at(r.y, i), *r.y, false)),
                                        static_cast<float>(binaryValue(at(r.z, i), *r.z, false)));
      if (r.packed) cloud.rgb[i] = packedColor(at(r.packed, i), *r.packed) & 0xFFFFFF;
    }
    return cloud;
  }

  // Binary, point after point; PLY elements before the vertices are skipped item by item.
  for (const auto& element : layout.skipped) {
    for (std::uint64_t item = 0; item < element.count; ++item) {
      for (const auto& property : element.properties) {
        if (property.second == 0) {  // a scalar
          in.seekg(property.first, std::ios::cur);
          continue;
        }
        std::uint8_t raw[4] = {0, 0, 0, 0};
        in.read(reinterpret_cast<char*>(raw), property.first);
        FileField count_field;
        count_field.type = 'U';
        count_field.size = property.first;
        const double items = binaryValue(raw, count_field, swap);
        in.seekg(static_cast<std::streamoff>(items * property.second), std::ios::cur);
      }
      if (!in) fail(path, "is truncated in an element before its vertices");
    }
  }
  std::uint64_t bytes = 0;
  if (!multiply(layout.points(), layout.point_bytes, bytes) ||
      bytes > layout.file_size - std::min<std::uint64_t>(layout.file_size, layout.data_offset)) {
    fail(path, "is truncated");
  }
  // A block of about 1 MB at a time: the file's bytes are never held whole beside the cloud.
  const std::size_t block_points = static_cast<std::size_t>(std::max<std::uint64_t>(
      1, (std::uint64_t{1} << 20) / std::max<std::uint64_t>(1, layout.point_bytes)));
  std::vector<std::uint8_t> block;
  for (std::size_t first = 0; first < cloud.size(); first += block_points) {
    const std::size_t count = std::min(block_points, cloud.size() - first);
    readBytes(path, in, std::uint64_t(count) * layout.point_bytes, block);
    fromPointMajor(block.data(), first, count, layout, r, swap, cloud);
  }
  return cloud;
}

}  // namespace tools
}  // namespace hope
