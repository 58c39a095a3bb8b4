#include "io/pcd/labelled_pcd.hpp"

#include <pcl/PCLPointCloud2.h>
#include <pcl/exceptions.h>
#include <pcl/io/pcd_io.h>

#include <charconv>
#include <cstring>
#include <fstream>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "io/io_error.hpp"

namespace dammloam::io {
namespace {

using Field = pcl::PCLPointField;

Field MakeField(const char* name, std::uint32_t offset, std::uint8_t datatype) {
  Field field;
  field.name = name;
  field.offset = offset;
  field.datatype = datatype;
  field.count = 1;
  return field;
}

// Layout written by us: 7 float32 + 1 uint32 = 32 bytes per point.
struct Record {
  float x, y, z, intensity;
  std::uint32_t label;
  float normal_x, normal_y, normal_z;
};
static_assert(sizeof(Record) == 32);

pcl::PCLPointCloud2 ToCloud2(const LabelledCloud& cloud) {
  pcl::PCLPointCloud2 out;
  out.fields = {MakeField("x", offsetof(Record, x), Field::FLOAT32),
                MakeField("y", offsetof(Record, y), Field::FLOAT32),
                MakeField("z", offsetof(Record, z), Field::FLOAT32),
                MakeField("intensity", offsetof(Record, intensity), Field::FLOAT32),
                MakeField("label", offsetof(Record, label), Field::UINT32),
                MakeField("normal_x", offsetof(Record, normal_x), Field::FLOAT32),
                MakeField("normal_y", offsetof(Record, normal_y), Field::FLOAT32),
                MakeField("normal_z", offsetof(Record, normal_z), Field::FLOAT32)};
  const std::size_t n = cloud.size();
  out.height = 1;
  out.width = static_cast<std::uint32_t>(n);
  out.point_step = sizeof(Record);
  out.row_step = static_cast<std::uint32_t>(n * sizeof(Record));
  out.is_dense = true;
  out.data.resize(n * sizeof(Record));
  for (std::size_t i = 0; i < n; ++i) {
    const Eigen::Vector3f p = cloud.points[i].cast<float>();
    const Eigen::Vector3f normal =
        cloud.normals.empty() ? Eigen::Vector3f::Zero() : Eigen::Vector3f(cloud.normals[i].cast<float>());
    const Record record{p.x(), p.y(), p.z(),
                        cloud.intensities.empty() ? 0.0f : cloud.intensities[i],
                        cloud.labels.empty() ? 0u : static_cast<std::uint32_t>(cloud.labels[i]),
                        normal.x(), normal.y(), normal.z()};
    std::memcpy(out.data.data() + i * sizeof(Record), &record, sizeof(Record));
  }
  return out;
}

void CheckSizes(const std::filesystem::path& file, const LabelledCloud& cloud) {
  const auto check = [&](std::size_t size, const char* what) {
    if (size != 0 && size != cloud.size()) {
      throw IoError(file.string() + ": cannot write PCD, " + what + " has " + std::to_string(size) +
                    " entries for " + std::to_string(cloud.size()) + " points");
    }
  };
  check(cloud.intensities.size(), "intensities");
  check(cloud.labels.size(), "labels");
  check(cloud.normals.size(), "normals");
}

// Reads one scalar of any PCD numeric type as double.
double ValueAt(const std::uint8_t* bytes, std::uint8_t datatype) {
  auto get = [bytes](auto zero) {
    decltype(zero) value;
    std::memcpy(&value, bytes, sizeof(value));
    return static_cast<double>(value);
  };
  switch (datatype) {
    case Field::INT8: return get(std::int8_t{});
    case Field::UINT8: return get(std::uint8_t{});
    case Field::INT16: return get(std::int16_t{});
    case Field::UINT16: return get(std::uint16_t{});
    case Field::INT32: return get(std::int32_t{});
    case Field::UINT32: return get(std::uint32_t{});
    case Field::FLOAT32: return get(float{});
    case Field::FLOAT64: return get(double{});
    default: return 0.0;
  }
}

std::optional<Field> FindField(const pcl::PCLPointCloud2& cloud, const std::string& name) {
  for (const auto& field : cloud.fields) {
    if (field.name == name) return field;
  }
  return std::nullopt;
}

// PCL's split(): tokens between runs of tab, CR and space.
std::vector<std::string> SplitLikePcl(const std::string& line) {
  std::vector<std::string> tokens;
  std::size_t start = 0;
  while ((start = line.find_first_not_of("\t\r ", start)) != std::string::npos) {
    const std::size_t end = line.find_first_of("\t\r ", start);
    tokens.push_back(line.substr(start, end == std::string::npos ? std::string::npos : end - start));
    start = end;
  }
  return tokens;
}

// PCL 1.13's readHeader trusts the header: at POINTS it allocates POINTS x point_step bytes
// before anything is checked (a 100-byte file can ask for terabytes: bad_alloc or length_error,
// or the process is killed), a COUNT below 1 wraps to 2^32 - 1 and sends the body reader off
// the data, and a DATA line without an encoding throws std::out_of_range. So the header is
// walked here first, line by line as readHeader reads it, and such files are IoErrors.
void CheckPcdHeader(const std::filesystem::path& file) {
  std::error_code ec;
  const std::uintmax_t file_size = std::filesystem::file_size(file, ec);
  if (ec) throw IoError(file.string() + ": cannot read PCD (" + ec.message() + ")");
  // LZF expands at most ~88x, ASCII and binary data take at least as many bytes as they fill.
  const std::uintmax_t max_bytes = 100 * file_size + 4096;
  std::ifstream in(file, std::ios::binary);
  std::string line;
  std::size_t fields = 0;
  std::vector<long long> sizes;
  std::uint32_t point_step = 0;  // as readHeader computes it
  auto integers = [&](const std::vector<std::string>& tokens, const char* key, long long min,
                      long long max) {
    std::vector<long long> values;
    for (std::size_t i = 1; i < tokens.size(); ++i) {
      long long v = 0;
      const auto [end, err] = std::from_chars(tokens[i].data(), tokens[i].data() + tokens[i].size(), v);
      if (err != std::errc() || end != tokens[i].data() + tokens[i].size() || v < min || v > max) {
        throw IoError(file.string() + ": PCD header " + key + " has an invalid value '" + tokens[i] + "'");
      }
      values.push_back(v);
    }
    return values;
  };
  while (std::getline(in, line)) {
    if (line.empty()) continue;
    const std::vector<std::string> tokens = SplitLikePcl(line);
    std::istringstream stream(line);
    stream.imbue(std::locale::classic());
    std::string key;
    stream >> key;
    if (key.rfind('#', 0) == 0 || key.rfind("VERSION", 0) == 0) continue;
    if (key.rfind("FIELDS", 0) == 0 || key.rfind("COLUMNS", 0) == 0) {
      fields = tokens.size() - 1;
      sizes.clear();
      point_step = static_cast<std::uint32_t>(4 * fields);
    } else if (key.rfind("SIZE", 0) == 0) {
      if (tokens.size() - 1 != fields) return;  // readHeader fails on it, before allocating
      sizes = integers(tokens, "SIZE", 1, 8);
      point_step = 0;
      for (long long v : sizes) {
        if (v != 1 && v != 2 && v != 4 && v != 8) {
          throw IoError(file.string() + ": PCD header SIZE " + std::to_string(v) + " is not 1, 2, 4 or 8");
        }
        point_step += static_cast<std::uint32_t>(v);
      }
    } else if (key.rfind("COUNT", 0) == 0) {
      if (tokens.size() - 1 != fields || sizes.empty()) return;  // readHeader fails on it
      const auto counts = integers(tokens, "COUNT", 1, 1 << 20);
      point_step = 0;
      for (std::size_t i = 0; i < counts.size(); ++i) point_step += static_cast<std::uint32_t>(counts[i] * sizes[i]);
    } else if (key.rfind("POINTS", 0) == 0) {
      if (point_step == 0) return;  // readHeader fails on it
      std::size_t points = 0;
      stream >> points;  // as readHeader reads it (wrapping included)
      const std::size_t bytes = points * point_step;
      if (bytes > max_bytes) {
        throw IoError(file.string() + ": PCD header declares " + std::to_string(points) + " points of " +
                      std::to_string(point_step) + " bytes, more than a file of " +
                      std::to_string(file_size) + " bytes can hold");
      }
    } else if (key.rfind("DATA", 0) == 0) {
      if (tokens.size() < 2) throw IoError(file.string() + ": PCD header DATA names no encoding");
      return;
    }
  }
}

// binary_compressed: PCL 1.13 shrinks its buffers to the uncompressed size the file states and
// then unpacks POINTS x point_step bytes into them (a heap overflow when the file states less).
void CheckCompressedSize(const std::filesystem::path& file, std::size_t data_index, std::size_t expected) {
  std::ifstream in(file, std::ios::binary);
  in.seekg(static_cast<std::streamoff>(data_index));
  std::uint32_t sizes[2] = {0, 0};  // compressed, uncompressed
  if (!in.read(reinterpret_cast<char*>(sizes), sizeof(sizes))) return;  // read() reports the short file
  if (sizes[1] != expected) {
    throw IoError(file.string() + ": PCD binary_compressed data unpacks to " + std::to_string(sizes[1]) +
                  " bytes, but the header's points and fields need " + std::to_string(expected));
  }
}

}  // namespace

void WriteLabelledPcd(const std::filesystem::path& file, const LabelledCloud& cloud,
                      PcdEncoding encoding) {
  CheckSizes(file, cloud);
  const pcl::PCLPointCloud2 cloud2 = ToCloud2(cloud);
  pcl::PCDWriter writer;
  int status = -1;
  try {
    switch (encoding) {
      case PcdEncoding::kBinary: status = writer.writeBinary(file.string(), cloud2); break;
      case PcdEncoding::kBinaryCompressed:
        status = writer.writeBinaryCompressed(file.string(), cloud2);
        break;
      case PcdEncoding::kAscii:
        status = writer.writeASCII(file.string(), cloud2, Eigen::Vector4f::Zero(),
                                   Eigen::Quaternionf::Identity(), 9);
        break;
    }
  } catch (const pcl::PCLException& e) {
    throw IoError(file.string() + ": cannot write PCD (" + e.what() + ")");
  }
  if (status != 0) throw IoError(file.string() + ": cannot write PCD");
}

LabelledCloud ReadLabelledPcd(const std::filesystem::path& file) {
  if (!std::filesystem::exists(file)) throw IoError(file.string() + ": PCD file does not exist");
  pcl::PCLPointCloud2 cloud2;
  try {
    // PCL 1.13 crashes reading the body of a file whose header has no fields, so the header is
    // checked on its own first.
    CheckPcdHeader(file);
    pcl::PCDReader reader;
    Eigen::Vector4f origin;
    Eigen::Quaternionf orientation;
    int version = 0, data_type = 0;
    unsigned int data_index = 0;
    if (reader.readHeader(file.string(), cloud2, origin, orientation, version, data_type,
                          data_index) != 0) {
      throw IoError(file.string() + ": cannot read PCD header");
    }
    if (!FindField(cloud2, "x") || !FindField(cloud2, "y") || !FindField(cloud2, "z")) {
      throw IoError(file.string() + ": PCD has no x y z fields");
    }
    if (cloud2.width * cloud2.height == 0) return {};
    if (data_type == 2) CheckCompressedSize(file, data_index, cloud2.data.size());
    if (reader.read(file.string(), cloud2) != 0) {
      throw IoError(file.string() + ": cannot read PCD (malformed data)");
    }
  } catch (const pcl::PCLException& e) {
    throw IoError(file.string() + ": cannot read PCD (" + e.what() + ")");
  }

  const auto x = FindField(cloud2, "x"), y = FindField(cloud2, "y"), z = FindField(cloud2, "z");
  const auto intensity = FindField(cloud2, "intensity");
  const auto label = FindField(cloud2, "label");
  const auto nx = FindField(cloud2, "normal_x"), ny = FindField(cloud2, "normal_y"),
             nz = FindField(cloud2, "normal_z");
  const bool has_normals = nx && ny && nz;

  const std::size_t n = static_cast<std::size_t>(cloud2.width) * cloud2.height;
  if (cloud2.data.size() < n * cloud2.point_step) {
    throw IoError(file.string() + ": PCD data shorter than WIDTH x HEIGHT points");
  }
  LabelledCloud cloud;
  cloud.points.reserve(n);
  for (std::size_t i = 0; i < n; ++i) {
    const std::uint8_t* point = cloud2.data.data() + i * cloud2.point_step;
    const auto value = [point](const Field& f) { return ValueAt(point + f.offset, f.datatype); };
    cloud.points.emplace_back(value(*x), value(*y), value(*z));
    if (intensity) cloud.intensities.push_back(static_cast<float>(value(*intensity)));
    if (has_normals) cloud.normals.emplace_back(value(*nx), value(*ny), value(*nz));
    if (!label) continue;
    const double class_id = value(*label);
    if (!(class_id >= 0.0 && class_id < static_cast<double>(kNumPointClasses))) {
      throw IoError(file.string() + ": point " + std::to_string(i) + " has label " +
                    std::to_string(class_id) + ", not one of the 5 point classes");
    }
    cloud.labels.push_back(static_cast<PointClass>(static_cast<int>(class_id)));
  }
  return cloud;
}

}  // namespace dammloam::io
