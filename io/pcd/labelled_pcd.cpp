#include "io/pcd/labelled_pcd.hpp"

#include <pcl/PCLPointCloud2.h>
#include <pcl/exceptions.h>
#include <pcl/io/pcd_io.h>

#include <cstring>
#include <optional>
#include <string>

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
