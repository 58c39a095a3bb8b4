#include "io/ply.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstring>
#include <fstream>
#include <iterator>
#include <limits>
#include <optional>
#include <sstream>
#include <string_view>
#include <vector>

#include "io/io_error.hpp"

namespace dammloam::io {
namespace {

enum class PlyType { kI8, kU8, kI16, kU16, kI32, kU32, kF32, kF64 };

std::optional<PlyType> ParseType(const std::string& name) {
  if (name == "char" || name == "int8") return PlyType::kI8;
  if (name == "uchar" || name == "uint8") return PlyType::kU8;
  if (name == "short" || name == "int16") return PlyType::kI16;
  if (name == "ushort" || name == "uint16") return PlyType::kU16;
  if (name == "int" || name == "int32") return PlyType::kI32;
  if (name == "uint" || name == "uint32") return PlyType::kU32;
  if (name == "float" || name == "float32") return PlyType::kF32;
  if (name == "double" || name == "float64") return PlyType::kF64;
  return std::nullopt;
}

std::size_t SizeOf(PlyType t) {
  switch (t) {
    case PlyType::kI8:
    case PlyType::kU8: return 1;
    case PlyType::kI16:
    case PlyType::kU16: return 2;
    case PlyType::kI32:
    case PlyType::kU32:
    case PlyType::kF32: return 4;
    case PlyType::kF64: return 8;
  }
  return 0;
}

bool IsFloat(PlyType t) { return t == PlyType::kF32 || t == PlyType::kF64; }

template <typename T>
double Load(const std::uint8_t* p) {
  T v;
  std::memcpy(&v, p, sizeof(T));
  return static_cast<double>(v);
}

double LoadValue(const std::uint8_t* p, PlyType t) {
  switch (t) {
    case PlyType::kI8: return Load<std::int8_t>(p);
    case PlyType::kU8: return Load<std::uint8_t>(p);
    case PlyType::kI16: return Load<std::int16_t>(p);
    case PlyType::kU16: return Load<std::uint16_t>(p);
    case PlyType::kI32: return Load<std::int32_t>(p);
    case PlyType::kU32: return Load<std::uint32_t>(p);
    case PlyType::kF32: return Load<float>(p);
    case PlyType::kF64: return Load<double>(p);
  }
  return 0.0;
}

struct Property {
  std::string name;
  PlyType type = PlyType::kF32;
  bool list = false;
};

struct Element {
  std::string name;
  std::uint64_t count = 0;
  std::vector<Property> properties;
};

enum class Format { kAscii, kBinaryLittleEndian };

}  // namespace

Scan ParsePly(const std::uint8_t* data, std::size_t size, const std::string& name,
              PlyReadReport* report) {
  // --- header ---
  std::size_t pos = 0;
  int line_no = 0;
  auto fail_line = [&](const std::string& problem) -> void {
    throw IoError(name + ": PLY header line " + std::to_string(line_no) + ": " + problem);
  };
  auto next_line = [&]() {
    const auto* nl = static_cast<const std::uint8_t*>(std::memchr(data + pos, '\n', size - pos));
    ++line_no;
    if (nl == nullptr) {
      throw IoError(name + ": PLY header ends without end_header (truncated at byte " +
                    std::to_string(size) + ")");
    }
    std::string line(data + pos, nl);
    pos = static_cast<std::size_t>(nl - data) + 1;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    return line;
  };
  if (size < 4 || std::memcmp(data, "ply", 3) != 0) {
    throw IoError(name + ": not a PLY file (no 'ply' at byte 0)");
  }
  if (next_line() != "ply") fail_line("expected 'ply'");
  std::optional<Format> format;
  std::vector<Element> elements;
  for (;;) {
    if (line_no > 10000) fail_line("header longer than 10000 lines");
    const std::string line = next_line();
    std::istringstream words(line);
    std::string keyword;
    words >> keyword;
    if (keyword.empty() || keyword == "comment" || keyword == "obj_info") continue;
    if (keyword == "end_header") break;
    if (keyword == "format") {
      std::string kind, version;
      words >> kind >> version;
      if (version != "1.0") fail_line("format version '" + version + "' (1.0 is read)");
      if (kind == "ascii") {
        format = Format::kAscii;
      } else if (kind == "binary_little_endian") {
        format = Format::kBinaryLittleEndian;
      } else {
        fail_line("format '" + kind + "' is not read (ascii, binary_little_endian)");
      }
    } else if (keyword == "element") {
      Element e;
      std::string count;
      words >> e.name >> count;
      const auto [end, ec] = std::from_chars(count.data(), count.data() + count.size(), e.count);
      if (e.name.empty() || ec != std::errc() || end != count.data() + count.size()) {
        fail_line("element needs a name and a count");
      }
      elements.push_back(std::move(e));
    } else if (keyword == "property") {
      if (elements.empty()) fail_line("property before any element");
      Property p;
      std::string type;
      words >> type;
      if (type == "list") {
        std::string count_type, item_type;
        words >> count_type >> item_type >> p.name;
        const auto ct = ParseType(count_type);
        const auto it = ParseType(item_type);
        if (!ct || !it || IsFloat(*ct)) fail_line("list property with types '" + count_type + "' '" + item_type + "'");
        p.list = true;
      } else {
        const auto t = ParseType(type);
        if (!t) fail_line("unknown property type '" + type + "'");
        p.type = *t;
        words >> p.name;
      }
      if (p.name.empty()) fail_line("property without a name");
      elements.back().properties.push_back(std::move(p));
    } else {
      fail_line("unknown keyword '" + keyword + "'");
    }
  }
  if (!format) throw IoError(name + ": PLY header has no format line");
  const auto vertex_it =
      std::find_if(elements.begin(), elements.end(), [](const Element& e) { return e.name == "vertex"; });
  if (vertex_it == elements.end()) throw IoError(name + ": PLY header has no vertex element");
  const Element& vertex = *vertex_it;

  int ix = -1, iy = -1, iz = -1, ii = -1, it = -1, ir = -1;
  for (std::size_t k = 0; k < vertex.properties.size(); ++k) {
    const Property& p = vertex.properties[k];
    const int index = static_cast<int>(k);
    if (p.list) throw IoError(name + ": PLY vertex property '" + p.name + "' is a list");
    if (p.name == "x") ix = index;
    if (p.name == "y") iy = index;
    if (p.name == "z") iz = index;
    if (p.name == "intensity") ii = index;
    if (p.name == "t" || p.name == "time") it = index;
    if (p.name == "ring") ir = index;
  }
  if (ix < 0 || iy < 0 || iz < 0) throw IoError(name + ": PLY vertex element lacks x, y or z");

  // --- body: skip the elements before vertex, then read it ---
  const std::size_t body = pos;
  std::vector<double> values(vertex.properties.size());
  Scan scan;
  std::vector<double> times;
  std::size_t dropped = 0;
  auto add = [&](std::uint64_t v) {
    const Eigen::Vector3d p(values[static_cast<std::size_t>(ix)], values[static_cast<std::size_t>(iy)],
                            values[static_cast<std::size_t>(iz)]);
    if (!p.allFinite() || p.isZero()) {
      ++dropped;
      return;
    }
    if (ir >= 0) {
      const double ring = values[static_cast<std::size_t>(ir)];
      if (!(ring >= 0.0 && ring <= 32767.0) || ring != std::floor(ring)) {
        throw IoError(name + ": PLY vertex " + std::to_string(v) + ": ring " + std::to_string(ring) +
                      " is not a beam index");
      }
      scan.rings.push_back(static_cast<std::int16_t>(ring));
    }
    if (it >= 0) {
      double t = values[static_cast<std::size_t>(it)];
      if (!IsFloat(vertex.properties[static_cast<std::size_t>(it)].type)) t *= 1e-9;
      if (!std::isfinite(t)) {
        throw IoError(name + ": PLY vertex " + std::to_string(v) + ": time is not finite");
      }
      times.push_back(t);
    }
    scan.points.push_back(p);
    if (ii >= 0) scan.intensities.push_back(static_cast<float>(values[static_cast<std::size_t>(ii)]));
  };

  if (*format == Format::kBinaryLittleEndian) {
    for (auto e = elements.begin(); e != vertex_it; ++e) {
      std::size_t stride = 0;
      for (const Property& p : e->properties) {
        if (p.list) throw IoError(name + ": PLY element '" + e->name + "' before vertex has a list property");
        stride += SizeOf(p.type);
      }
      if (stride != 0 && e->count > (size - pos) / stride) {
        throw IoError(name + ": PLY truncated: element '" + e->name + "' needs " + std::to_string(e->count) +
                      " x " + std::to_string(stride) + " bytes at byte " + std::to_string(pos));
      }
      pos += static_cast<std::size_t>(e->count * stride);
    }
    std::size_t stride = 0;
    for (const Property& p : vertex.properties) stride += SizeOf(p.type);
    if (vertex.count > (size - pos) / stride) {
      throw IoError(name + ": PLY truncated: " + std::to_string(vertex.count) + " vertices of " +
                    std::to_string(stride) + " bytes need " + std::to_string(vertex.count * stride) +
                    " bytes at byte " + std::to_string(pos) + ", " + std::to_string(size - pos) + " left");
    }
    scan.points.reserve(static_cast<std::size_t>(vertex.count));
    for (std::uint64_t v = 0; v < vertex.count; ++v) {
      for (std::size_t k = 0; k < vertex.properties.size(); ++k) {
        values[k] = LoadValue(data + pos, vertex.properties[k].type);
        pos += SizeOf(vertex.properties[k].type);
      }
      add(v);
    }
  } else {
    // ascii: one element instance per line, values separated by blanks.
    std::string_view text(reinterpret_cast<const char*>(data) + body, size - body);
    std::size_t at = 0;
    std::uint64_t text_line = static_cast<std::uint64_t>(line_no);
    auto next = [&](const char* what) -> std::string_view {
      ++text_line;
      if (at >= text.size()) {
        throw IoError(name + ": PLY truncated: no line for " + what + " (line " + std::to_string(text_line) +
                      ", byte " + std::to_string(body + at) + ")");
      }
      const std::size_t end = std::min(text.find('\n', at), text.size());
      std::string_view line = text.substr(at, end - at);
      at = end + 1;
      return line;
    };
    for (auto e = elements.begin(); e != vertex_it; ++e) {
      for (std::uint64_t k = 0; k < e->count; ++k) next(e->name.c_str());
    }
    // Every vertex takes at least 2 bytes per property: a larger count is a lie.
    if (vertex.count > (text.size() - std::min(at, text.size())) / (2 * vertex.properties.size()) + 1) {
      throw IoError(name + ": PLY truncated: " + std::to_string(vertex.count) + " vertices announced, " +
                    std::to_string(text.size() - std::min(at, text.size())) + " bytes of text left");
    }
    for (std::uint64_t v = 0; v < vertex.count; ++v) {
      const std::uint64_t start = body + at;
      const std::string_view line = next("a vertex");
      std::size_t c = 0;
      for (std::size_t k = 0; k < vertex.properties.size(); ++k) {
        while (c < line.size() && (line[c] == ' ' || line[c] == '\t' || line[c] == '\r')) ++c;
        std::size_t e = c;
        while (e < line.size() && line[e] != ' ' && line[e] != '\t' && line[e] != '\r') ++e;
        // A float property is read as the float nearest to the text (as a binary file stores it),
        // not as a double.
        double value = 0.0;
        std::from_chars_result parsed{};
        if (vertex.properties[k].type == PlyType::kF32) {
          float f = 0.0f;
          parsed = std::from_chars(line.data() + c, line.data() + e, f);
          value = f;
        } else {
          parsed = std::from_chars(line.data() + c, line.data() + e, value);
        }
        const auto [end, ec] = parsed;
        if (c == e || ec != std::errc() || end != line.data() + e) {
          throw IoError(name + ": PLY vertex " + std::to_string(v) + " (line " + std::to_string(text_line) +
                        ", byte " + std::to_string(start) + "): property '" + vertex.properties[k].name +
                        "' is not a number");
        }
        values[k] = value;
        c = e;
      }
      add(v);
    }
  }
  if (!times.empty()) {
    const double first = *std::min_element(times.begin(), times.end());
    const double last = *std::max_element(times.begin(), times.end());
    const double shift = first >= 0.0 && last < 1.0 ? 0.0 : first;
    scan.times.reserve(times.size());
    for (double t : times) scan.times.push_back(static_cast<float>(t - shift));
  }
  if (report != nullptr) report->dropped = dropped;
  return scan;
}

Scan ReadPly(const std::filesystem::path& file, PlyReadReport* report) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw IoError(file.string() + ": cannot open");
  const std::vector<std::uint8_t> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  return ParsePly(bytes.data(), bytes.size(), file.string(), report);
}

}  // namespace dammloam::io
