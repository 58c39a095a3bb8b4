#include "services/dds/point_cloud.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <initializer_list>
#include <set>
#include <string_view>

namespace dammloam::dds {
namespace {

std::size_t DatatypeSize(std::uint8_t datatype) {
  switch (datatype) {
    case dammloam_msg_DATATYPE_INT8:
    case dammloam_msg_DATATYPE_UINT8: return 1;
    case dammloam_msg_DATATYPE_INT16:
    case dammloam_msg_DATATYPE_UINT16: return 2;
    case dammloam_msg_DATATYPE_INT32:
    case dammloam_msg_DATATYPE_UINT32:
    case dammloam_msg_DATATYPE_FLOAT32: return 4;
    case dammloam_msg_DATATYPE_FLOAT64: return 8;
    default: return 0;
  }
}

std::string DatatypeName(std::uint8_t datatype) {
  static constexpr const char* kNames[] = {"invalid", "int8",   "uint8",   "int16", "uint16",
                                           "int32",   "uint32", "float32", "float64"};
  if (datatype >= 1 && datatype <= 8) return kNames[datatype];
  return "unknown datatype " + std::to_string(datatype);
}

template <typename T>
T Load(const std::uint8_t* p) {
  T value;
  std::memcpy(&value, p, sizeof(T));
  return value;
}

double ReadNumber(const std::uint8_t* p, std::uint8_t datatype) {
  switch (datatype) {
    case dammloam_msg_DATATYPE_INT8: return Load<std::int8_t>(p);
    case dammloam_msg_DATATYPE_UINT8: return Load<std::uint8_t>(p);
    case dammloam_msg_DATATYPE_INT16: return Load<std::int16_t>(p);
    case dammloam_msg_DATATYPE_UINT16: return Load<std::uint16_t>(p);
    case dammloam_msg_DATATYPE_INT32: return Load<std::int32_t>(p);
    case dammloam_msg_DATATYPE_UINT32: return Load<std::uint32_t>(p);
    case dammloam_msg_DATATYPE_FLOAT32: return Load<float>(p);
    case dammloam_msg_DATATYPE_FLOAT64: return Load<double>(p);
    default: return 0.0;
  }
}

template <typename T>
void Store(std::uint8_t* p, T value) {
  std::memcpy(p, &value, sizeof(T));
}

const CloudFieldView* FindField(const CloudInput& cloud, std::string_view name) {
  for (const auto& field : cloud.fields) {
    if (field.name == name) return &field;
  }
  return nullptr;
}

// The first of `names` the cloud has, or null.
const CloudFieldView* FindFirst(const CloudInput& cloud,
                                std::initializer_list<std::string_view> names) {
  for (std::string_view name : names) {
    if (const auto* f = FindField(cloud, name)) return f;
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
  return datatype == dammloam_msg_DATATYPE_FLOAT32 || datatype == dammloam_msg_DATATYPE_FLOAT64;
}

struct Problem {
  std::string code;     // short machine-readable category (DaemonStatus.rejected_by_reason)
  std::string message;  // empty when there is no problem
};

// Structural checks that do not look at points; empty message when the cloud is well formed.
Problem CheckLayout(const CloudInput& cloud, const CloudLimits& limits) {
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
    const std::size_t size = DatatypeSize(f.datatype);
    if (size == 0) return {"fields", "field '" + name + "' has " + DatatypeName(f.datatype)};
    if (f.count == 0) return {"fields", "field '" + name + "' has count 0"};
    if (std::uint64_t{f.offset} + std::uint64_t{size} * f.count > cloud.point_step) {
      return {"fields", "field '" + name + "' (offset " + std::to_string(f.offset) + ", " +
             std::to_string(size * f.count) + " bytes) ends beyond point_step " +
             std::to_string(cloud.point_step)};
    }
  }
  for (const char* axis : {"x", "y", "z"}) {
    const auto* f = FindField(cloud, axis);
    if (f == nullptr) {
      return {"missing_field", std::string("required field '") + axis + "' is missing (fields: " + FieldList(cloud) +
             ")"};
    }
    if (!IsFloat(f->datatype)) {
      return {"field_type", std::string("field '") + axis + "' is " + DatatypeName(f->datatype) +
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

// Per-point time field: seconds for float types, nanoseconds for 32-bit integers (ouster-ros t,
// nebula time_stamp). Narrower integers cannot hold a scan's nanoseconds: a wrong layout.
struct TimeField {
  const CloudFieldView* field = nullptr;
  double scale = 1.0;
};

Problem FindTimeField(const CloudInput& cloud, const CloudLimits& limits, TimeField& out) {
  out = {};
  if (limits.point_times == PointTimes::kIgnored) return {};
  const CloudFieldView* f = FindFirst(cloud, {"t", "time", "time_stamp"});
  if (f == nullptr) {
    if (limits.point_times == PointTimes::kOptional) return {};
    std::string message = "no per-point time field (looked for t, time, time_stamp; fields: " +
                          FieldList(cloud) + "): deskew needs one";
    if (!limits.missing_time_hint.empty()) message += "; " + limits.missing_time_hint;
    return {"missing_time", message};
  }
  if (IsFloat(f->datatype)) {
    out = {f, 1.0};
  } else if (f->datatype == dammloam_msg_DATATYPE_UINT32 ||
             f->datatype == dammloam_msg_DATATYPE_INT32) {
    out = {f, 1e-9};
  } else {
    return {"field_type", "field '" + std::string(f->name) + "' is " + DatatypeName(f->datatype) +
                              ", expected float32/float64 seconds or uint32/int32 nanoseconds " +
                              "since header.stamp"};
  }
  return {};
}

// Scans stamped at the end of the sweep have negative per-point times: move t_start to the
// first point so times run from 0 as the core expects (the stamp keeps nanosecond precision
// when nothing moves).
Problem StartAtFirstPoint(Scan& scan, double max_point_time) {
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

std::string PointName(std::uint64_t index, std::uint32_t width) {
  return "point " + std::to_string(index) + " (row " + std::to_string(index / width) +
         ", column " + std::to_string(index % width) + ")";
}

}  // namespace

dammloam_msg_Time ToMsgTime(double seconds) {
  double whole = std::floor(seconds);
  auto nanosec = static_cast<std::int64_t>(std::llround((seconds - whole) * 1e9));
  if (nanosec >= 1000000000) {
    whole += 1.0;
    nanosec -= 1000000000;
  }
  return {static_cast<std::int32_t>(whole), static_cast<std::uint32_t>(nanosec)};
}

double ToSeconds(const dammloam_msg_Time& time) { return time.sec + time.nanosec * 1e-9; }

CloudInput ViewOf(const dammloam_msg_PointCloud& cloud) {
  CloudInput view = ViewOfBody(cloud);
  view.stamp = cloud.header.stamp;
  view.frame_id = cloud.header.frame_id != nullptr ? cloud.header.frame_id : "";
  return view;
}

CloudView::CloudView(const CloudMessage& message) {
  ViewBodyOf(message, fields_, sample_);
  sample_.header.stamp = message.stamp;
  sample_.header.frame_id = const_cast<char*>(message.frame_id.c_str());
  sample_.header.seq = message.seq;
}

CloudMessage ScanToCloud(const Scan& scan, const std::string& frame_id, std::uint64_t seq) {
  CloudMessage msg;
  msg.stamp = ToMsgTime(scan.t_start);
  msg.frame_id = frame_id;
  msg.seq = seq;
  msg.width = static_cast<std::uint32_t>(scan.size());
  msg.fields = {{"x", 0, dammloam_msg_DATATYPE_FLOAT32, 1},
                {"y", 4, dammloam_msg_DATATYPE_FLOAT32, 1},
                {"z", 8, dammloam_msg_DATATYPE_FLOAT32, 1},
                {"intensity", 12, dammloam_msg_DATATYPE_FLOAT32, 1},
                {"t", 16, dammloam_msg_DATATYPE_FLOAT32, 1},
                {"ring", 20, dammloam_msg_DATATYPE_UINT16, 1}};
  msg.point_step = 24;
  msg.row_step = msg.point_step * msg.width;
  msg.data.assign(std::size_t{msg.row_step}, 0);
  const bool has_intensity = scan.intensities.size() == scan.size();
  for (std::size_t i = 0; i < scan.size(); ++i) {
    std::uint8_t* p = msg.data.data() + i * msg.point_step;
    Store(p + 0, static_cast<float>(scan.points[i].x()));
    Store(p + 4, static_cast<float>(scan.points[i].y()));
    Store(p + 8, static_cast<float>(scan.points[i].z()));
    Store(p + 12, has_intensity ? scan.intensities[i] : 0.0f);
    Store(p + 16, scan.has_times() ? scan.times[i] : 0.0f);
    Store(p + 20, static_cast<std::uint16_t>(scan.has_rings() ? scan.rings[i] : 0));
  }
  return msg;
}

CloudConversion CloudToScan(const dammloam_msg_PointCloud& cloud, const CloudLimits& limits) {
  return CloudToScan(ViewOf(cloud), limits);
}

CloudConversion CloudToScan(const CloudInput& cloud, const CloudLimits& limits) {
  CloudConversion result;
  TimeField ft;
  Problem problem = CheckLayout(cloud, limits);
  if (problem.message.empty()) problem = FindTimeField(cloud, limits, ft);
  if (!problem.message.empty()) {
    result.code = std::move(problem.code);
    result.error = std::move(problem.message);
    return result;
  }

  const auto* fx = FindField(cloud, "x");
  const auto* fy = FindField(cloud, "y");
  const auto* fz = FindField(cloud, "z");
  const auto* fi = FindField(cloud, "intensity");
  const auto* fr = FindFirst(cloud, {"ring", "channel"});

  const double min_time = limits.stamp_may_end_scan ? -limits.max_point_time : 0.0;
  Scan scan;
  scan.t_start = ToSeconds(cloud.stamp);
  const std::uint64_t num_points = std::uint64_t{cloud.height} * cloud.width;
  scan.points.reserve(num_points);
  for (std::uint64_t index = 0; index < num_points; ++index) {
    const std::uint8_t* p = cloud.data + (index / cloud.width) * cloud.row_step +
                            (index % cloud.width) * cloud.point_step;
    const Eigen::Vector3d xyz(ReadNumber(p + fx->offset, fx->datatype),
                              ReadNumber(p + fy->offset, fy->datatype),
                              ReadNumber(p + fz->offset, fz->datatype));
    if (!xyz.allFinite()) {
      if (cloud.is_dense) {
        result.code = "non_finite";
        result.error = PointName(index, cloud.width) +
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
      const double t = ReadNumber(p + ft.field->offset, ft.field->datatype) * ft.scale;
      if (!std::isfinite(t) || t < min_time || t > limits.max_point_time) {
        result.code = "point_time";
        result.error = PointName(index, cloud.width) + " has time " + std::to_string(t) +
                       " s, outside [" + std::to_string(min_time) + ", " +
                       std::to_string(limits.max_point_time) + "]";
        return result;
      }
      scan.times.push_back(static_cast<float>(t));
    }
    if (fr != nullptr) {
      const double ring = ReadNumber(p + fr->offset, fr->datatype);
      if (!(ring >= 0.0 && ring < limits.max_ring)) {
        result.code = "ring";
        result.error = PointName(index, cloud.width) + " has ring " + std::to_string(ring) +
                       ", outside [0, " + std::to_string(limits.max_ring) + ")";
        return result;
      }
      scan.rings.push_back(static_cast<std::int16_t>(ring));
    }
    if (fi != nullptr) {
      const double intensity = ReadNumber(p + fi->offset, fi->datatype);
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
  if (Problem span = StartAtFirstPoint(scan, limits.max_point_time); !span.message.empty()) {
    result.code = std::move(span.code);
    result.error = std::move(span.message);
    return result;
  }
  result.start_offset = scan.t_start - stamp;
  result.scan = std::move(scan);
  return result;
}

CloudMessage LabelledToCloud(const LabelledPoints& points, const std::string& frame_id,
                             std::uint64_t seq) {
  CloudMessage msg;
  msg.frame_id = frame_id;
  msg.seq = seq;
  msg.width = static_cast<std::uint32_t>(points.points_sensor.size());
  const char* names[] = {"x", "y", "z", "map_x", "map_y", "map_z",
                         "normal_x", "normal_y", "normal_z"};
  for (std::uint32_t k = 0; k < 9; ++k) {
    msg.fields.push_back({names[k], 4 * k, dammloam_msg_DATATYPE_FLOAT32, 1});
  }
  msg.fields.push_back({"label", 36, dammloam_msg_DATATYPE_UINT8, 1});
  msg.point_step = 40;
  msg.row_step = msg.point_step * msg.width;
  msg.data.assign(std::size_t{msg.row_step}, 0);
  const bool has_normals = points.normals.size() == points.points_sensor.size();
  for (std::size_t i = 0; i < points.points_sensor.size(); ++i) {
    std::uint8_t* p = msg.data.data() + i * msg.point_step;
    const Eigen::Vector3f normal = has_normals ? points.normals[i] : Eigen::Vector3f::Zero();
    const float values[9] = {
        static_cast<float>(points.points_sensor[i].x()), static_cast<float>(points.points_sensor[i].y()),
        static_cast<float>(points.points_sensor[i].z()), static_cast<float>(points.points_map[i].x()),
        static_cast<float>(points.points_map[i].y()),    static_cast<float>(points.points_map[i].z()),
        normal.x(), normal.y(), normal.z()};
    std::memcpy(p, values, sizeof(values));
    p[36] = static_cast<std::uint8_t>(points.labels[i]);
  }
  return msg;
}

std::optional<LabelledPoints> CloudToLabelled(const dammloam_msg_PointCloud& sample,
                                              std::string* error) {
  const CloudInput cloud = ViewOf(sample);
  CloudLimits limits;
  limits.max_bytes = ~0ull;
  limits.max_points = ~0ull;
  if (Problem problem = CheckLayout(cloud, limits); !problem.message.empty()) {
    if (error != nullptr) *error = problem.message;
    return std::nullopt;
  }
  const CloudFieldView* f[10];
  const char* names[] = {"x", "y", "z", "map_x", "map_y", "map_z",
                         "normal_x", "normal_y", "normal_z", "label"};
  for (int k = 0; k < 10; ++k) {
    f[k] = FindField(cloud, names[k]);
    if (f[k] == nullptr) {
      if (error != nullptr) *error = std::string("labelled cloud lacks field '") + names[k] + "'";
      return std::nullopt;
    }
  }
  LabelledPoints out;
  const std::uint64_t n = std::uint64_t{cloud.height} * cloud.width;
  for (std::uint64_t index = 0; index < n; ++index) {
    const std::uint8_t* p = cloud.data + (index / cloud.width) * cloud.row_step +
                            (index % cloud.width) * cloud.point_step;
    double v[10];
    for (int k = 0; k < 10; ++k) v[k] = ReadNumber(p + f[k]->offset, f[k]->datatype);
    out.points_sensor.emplace_back(v[0], v[1], v[2]);
    out.points_map.emplace_back(v[3], v[4], v[5]);
    out.normals.emplace_back(static_cast<float>(v[6]), static_cast<float>(v[7]),
                             static_cast<float>(v[8]));
    // Casting a label outside [0, 256) (any field type is allowed) to uint8 is undefined.
    if (!(v[9] >= 0.0 && v[9] < static_cast<double>(kNumPointClasses))) {
      if (error != nullptr) {
        *error = PointName(index, cloud.width) + " has label " + std::to_string(v[9]) +
                 ", not one of the " + std::to_string(kNumPointClasses) + " point classes";
      }
      return std::nullopt;
    }
    out.labels.push_back(static_cast<PointClass>(static_cast<std::uint8_t>(v[9])));
  }
  return out;
}

}  // namespace dammloam::dds
