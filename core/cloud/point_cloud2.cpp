#include "core/cloud/point_cloud2.hpp"

#include <algorithm>
#include <cstdio>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <initializer_list>
#include <set>

namespace dammloam {
namespace {

template <typename T>
T Load(const std::uint8_t* p) {
  T value;
  std::memcpy(&value, p, sizeof(T));
  return value;
}

// Inlined into the per-point loop (a call per field and point was a fifth of reading a bag).
inline double ReadValue(const std::uint8_t* p, std::uint8_t datatype) {
  switch (datatype) {
    case point_field::kInt8: return Load<std::int8_t>(p);
    case point_field::kUint8: return Load<std::uint8_t>(p);
    case point_field::kInt16: return Load<std::int16_t>(p);
    case point_field::kUint16: return Load<std::uint16_t>(p);
    case point_field::kInt32: return Load<std::int32_t>(p);
    case point_field::kUint32: return Load<std::uint32_t>(p);
    case point_field::kFloat32: return Load<float>(p);
    case point_field::kFloat64: return Load<double>(p);
    default: return 0.0;
  }
}

// The first of `names` the cloud has, or null.
const CloudFieldView* FindFirst(const CloudInput& cloud,
                                std::initializer_list<std::string_view> names) {
  for (std::string_view name : names) {
    if (const auto* f = FindCloudField(cloud, name)) return f;
  }
  return nullptr;
}

std::string FieldList(const CloudInput& cloud) {
  std::string list;
  for (const auto& field : cloud.fields) {
    if (!list.empty()) list += ", ";
    list += field.name.empty() ? std::string("<null>") : std::string(field.name);
  }
  return list.empty() ? "none" : list;
}

bool IsFloat(std::uint8_t datatype) {
  return datatype == point_field::kFloat32 || datatype == point_field::kFloat64;
}

// Per-point time field: seconds for float types, nanoseconds for 32-bit integers (ouster-ros t,
// nebula time_stamp). Narrower integers cannot hold a scan's nanoseconds: a wrong layout.
struct TimeField {
  const CloudFieldView* field = nullptr;
  double scale = 1.0;
};

CloudProblem FindTimeField(const CloudInput& cloud, const CloudLimits& limits, TimeField& out) {
  out = {};
  if (limits.point_times == PointTimes::kIgnored) return {};
  const CloudFieldView* f = FindFirst(cloud, {"t", "time", "time_stamp", "timestamp"});
  if (f == nullptr) {
    if (limits.point_times == PointTimes::kOptional) return {};
    std::string message =
        "no per-point time field (looked for t, time, time_stamp, timestamp; fields: " +
        FieldList(cloud) + "): deskew needs one";
    if (!limits.missing_time_hint.empty()) message += "; " + limits.missing_time_hint;
    return {"missing_time", message};
  }
  if (IsFloat(f->datatype)) {
    out = {f, 1.0};
  } else if (f->datatype == point_field::kUint32 || f->datatype == point_field::kInt32) {
    out = {f, 1e-9};
  } else {
    return {"field_type", "field '" + std::string(f->name) + "' is " +
                              PointFieldTypeName(f->datatype) +
                              ", expected float32/float64 seconds or uint32/int32 nanoseconds " +
                              "since header.stamp"};
  }
  return {};
}

// Scans stamped at the end of the sweep have negative per-point times: move t_start to the
// first point so times run from 0 as the core expects (the stamp keeps nanosecond precision
// when nothing moves).
CloudProblem StartAtFirstPoint(Scan& scan, double max_point_time) {
  if (scan.times.empty()) return {};
  const float first = *std::min_element(scan.times.begin(), scan.times.end());
  if (first >= 0.0f) return {};
  const float last = *std::max_element(scan.times.begin(), scan.times.end());
  if (last - first > max_point_time) {
    return {"point_time", "per-point times span " + std::to_string(last - first) +
                              " s, more than " + std::to_string(max_point_time) + " s"};
  }
  scan.t_start += first;
  for (float& t : scan.times) t -= first;
  return {};
}

}  // namespace

std::size_t PointFieldSize(std::uint8_t datatype) {
  switch (datatype) {
    case point_field::kInt8:
    case point_field::kUint8: return 1;
    case point_field::kInt16:
    case point_field::kUint16: return 2;
    case point_field::kInt32:
    case point_field::kUint32:
    case point_field::kFloat32: return 4;
    case point_field::kFloat64: return 8;
    default: return 0;
  }
}

std::string PointFieldTypeName(std::uint8_t datatype) {
  static constexpr const char* kNames[] = {"invalid", "int8",   "uint8",   "int16", "uint16",
                                           "int32",   "uint32", "float32", "float64"};
  if (datatype >= 1 && datatype <= 8) return kNames[datatype];
  return "unknown datatype " + std::to_string(datatype);
}

double ReadPointFieldValue(const std::uint8_t* p, std::uint8_t datatype) {
  return ReadValue(p, datatype);
}

double StampSeconds(const CloudStamp& stamp) {
  // sec + nanosec * 1e-9 can be one ulp off the decimal value; strtod rounds correctly.
  char text[32];
  const std::int64_t sec = stamp.sec;
  const bool negative = sec < 0 && stamp.nanosec > 0;
  // A negative stamp sec.ns means sec + ns/1e9: write it as -(|sec| - 1).(1e9 - ns).
  const std::int64_t whole = negative ? -(sec + 1) : sec;
  const std::uint32_t frac = negative ? 1000000000u - stamp.nanosec : stamp.nanosec;
  std::snprintf(text, sizeof(text), "%s%lld.%09u", negative ? "-" : "",
                static_cast<long long>(whole), static_cast<unsigned>(frac));
  return std::strtod(text, nullptr);
}

CloudStamp SecondsToStamp(double seconds) {
  double whole = std::floor(seconds);
  auto nanosec = static_cast<std::int64_t>(std::llround((seconds - whole) * 1e9));
  if (nanosec >= 1000000000) {
    whole += 1.0;
    nanosec -= 1000000000;
  }
  return {static_cast<std::int32_t>(whole), static_cast<std::uint32_t>(nanosec)};
}

const CloudFieldView* FindCloudField(const CloudInput& cloud, std::string_view name) {
  for (const auto& field : cloud.fields) {
    if (field.name == name) return &field;
  }
  return nullptr;
}

std::string CloudPointName(std::uint64_t index, std::uint32_t width) {
  return "point " + std::to_string(index) + " (row " + std::to_string(index / width) +
         ", column " + std::to_string(index % width) + ")";
}

CloudProblem CheckCloudLayout(const CloudInput& cloud, const CloudLimits& limits) {
  if (cloud.stamp.nanosec >= 1000000000u) {
    return {"stamp", "header.stamp.nanosec is " + std::to_string(cloud.stamp.nanosec) +
           ", must be below 1e9"};
  }
  if (cloud.is_bigendian) return {"byte_order", "is_bigendian is true: only little-endian clouds are supported"};
  if (cloud.data_size > limits.max_bytes) {
    return {"too_large", "payload of " + std::to_string(cloud.data_size) + " bytes exceeds the limit of " +
           std::to_string(limits.max_bytes) + " bytes (max_cloud_bytes)"};
  }
  const std::uint64_t num_points = std::uint64_t{cloud.height} * cloud.width;
  if (num_points == 0) {
    return {"zero_points", "cloud has zero points (height " + std::to_string(cloud.height) + " x width " +
           std::to_string(cloud.width) + ")"};
  }
  if (num_points > limits.max_points) {
    return {"too_many_points", "cloud has " + std::to_string(num_points) + " points, more than the limit of " +
           std::to_string(limits.max_points)};
  }
  if (cloud.point_step == 0) return {"point_step", "point_step is 0"};
  std::set<std::string_view> names;
  for (std::size_t i = 0; i < cloud.fields.size(); ++i) {
    const auto& f = cloud.fields[i];
    const std::string name(f.name);
    if (name.empty()) return {"fields", "field " + std::to_string(i) + " has an empty name"};
    if (!names.insert(f.name).second) return {"fields", "field '" + name + "' appears twice"};
    const std::size_t size = PointFieldSize(f.datatype);
    if (size == 0) return {"fields", "field '" + name + "' has " + PointFieldTypeName(f.datatype)};
    if (f.count == 0) return {"fields", "field '" + name + "' has count 0"};
    if (std::uint64_t{f.offset} + std::uint64_t{size} * f.count > cloud.point_step) {
      return {"fields", "field '" + name + "' (offset " + std::to_string(f.offset) + ", " +
             std::to_string(size * f.count) + " bytes) ends beyond point_step " +
             std::to_string(cloud.point_step)};
    }
  }
  for (const char* axis : {"x", "y", "z"}) {
    const auto* f = FindCloudField(cloud, axis);
    if (f == nullptr) {
      return {"missing_field", std::string("required field '") + axis + "' is missing (fields: " + FieldList(cloud) +
             ")"};
    }
    if (!IsFloat(f->datatype)) {
      return {"field_type", std::string("field '") + axis + "' is " + PointFieldTypeName(f->datatype) +
             ", expected float32 or float64"};
    }
  }
  const std::uint64_t min_row_step = std::uint64_t{cloud.width} * cloud.point_step;
  if (cloud.row_step < min_row_step) {
    return {"row_step", "row_step " + std::to_string(cloud.row_step) + " is smaller than width x point_step = " +
           std::to_string(min_row_step)};
  }
  const std::uint64_t expected_bytes = std::uint64_t{cloud.height} * cloud.row_step;
  if (cloud.data_size != expected_bytes) {
    return {"payload_size", "payload is " + std::to_string(cloud.data_size) +
           " bytes but height x row_step = " + std::to_string(expected_bytes) +
           (cloud.data_size < expected_bytes ? " (truncated)" : " (extra bytes)")};
  }
  return {};
}

CloudConversion CloudToScan(const CloudInput& cloud, const CloudLimits& limits) {
  CloudConversion result;
  TimeField ft;
  CloudProblem problem = CheckCloudLayout(cloud, limits);
  if (problem.message.empty()) problem = FindTimeField(cloud, limits, ft);
  if (!problem.message.empty()) {
    result.code = std::move(problem.code);
    result.error = std::move(problem.message);
    return result;
  }

  const auto* fx = FindCloudField(cloud, "x");
  const auto* fy = FindCloudField(cloud, "y");
  const auto* fz = FindCloudField(cloud, "z");
  const auto* fi = FindCloudField(cloud, "intensity");
  const auto* fr = FindFirst(cloud, {"ring", "channel"});

  const double min_time = limits.stamp_may_end_scan ? -limits.max_point_time : 0.0;
  Scan scan;
  // The daemon's arithmetic, kept as it was; recorded input re-stamps with StampSeconds.
  scan.t_start = cloud.stamp.sec + cloud.stamp.nanosec * 1e-9;
  const std::uint64_t num_points = std::uint64_t{cloud.height} * cloud.width;
  scan.points.reserve(num_points);
  if (ft.field != nullptr) scan.times.reserve(num_points);
  if (fr != nullptr) scan.rings.reserve(num_points);
  if (fi != nullptr) scan.intensities.reserve(num_points);
  for (std::uint64_t index = 0; index < num_points; ++index) {
    const std::uint8_t* p = cloud.data + (index / cloud.width) * cloud.row_step +
                            (index % cloud.width) * cloud.point_step;
    const Eigen::Vector3d xyz(ReadValue(p + fx->offset, fx->datatype),
                              ReadValue(p + fy->offset, fy->datatype),
                              ReadValue(p + fz->offset, fz->datatype));
    if (!xyz.allFinite()) {
      if (cloud.is_dense) {
        result.code = "non_finite";
        result.error = CloudPointName(index, cloud.width) +
                       " has a non-finite coordinate but the cloud says is_dense=true";
        return result;
      }
      ++result.skipped_points;
      continue;
    }
    if (xyz.isZero(0.0)) {  // no return
      ++result.skipped_points;
      continue;
    }
    if (ft.field != nullptr) {
      const double t = ReadValue(p + ft.field->offset, ft.field->datatype) * ft.scale;
      if (!std::isfinite(t) || t < min_time || t > limits.max_point_time) {
        result.code = "point_time";
        result.error = CloudPointName(index, cloud.width) + " has time " + std::to_string(t) +
                       " s, outside [" + std::to_string(min_time) + ", " +
                       std::to_string(limits.max_point_time) + "]";
        return result;
      }
      scan.times.push_back(static_cast<float>(t));
    }
    if (fr != nullptr) {
      const double ring = ReadValue(p + fr->offset, fr->datatype);
      if (!(ring >= 0.0 && ring < limits.max_ring)) {
        result.code = "ring";
        result.error = CloudPointName(index, cloud.width) + " has ring " + std::to_string(ring) +
                       ", outside [0, " + std::to_string(limits.max_ring) + ")";
        return result;
      }
      scan.rings.push_back(static_cast<std::int16_t>(ring));
    }
    if (fi != nullptr) {
      const double intensity = ReadValue(p + fi->offset, fi->datatype);
      scan.intensities.push_back(std::isfinite(intensity) ? static_cast<float>(intensity) : 0.f);
    }
    scan.points.push_back(xyz);
  }
  if (scan.points.empty()) {
    result.code = "no_valid_points";
    result.error = "no valid points: all " + std::to_string(num_points) +
                   " points are no-returns (at the origin) or non-finite";
    return result;
  }
  const double stamp = scan.t_start;
  if (CloudProblem span = StartAtFirstPoint(scan, limits.max_point_time); !span.message.empty()) {
    result.code = std::move(span.code);
    result.error = std::move(span.message);
    return result;
  }
  result.start_offset = scan.t_start - stamp;
  result.scan = std::move(scan);
  return result;
}

}  // namespace dammloam
