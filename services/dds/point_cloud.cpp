#include "services/dds/point_cloud.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <initializer_list>
#include <set>
#include <string_view>

namespace dammloam::dds {
namespace {

template <typename T>
void Store(std::uint8_t* p, T value) {
  std::memcpy(p, &value, sizeof(T));
}

}  // namespace

dammloam_msg_Time ToMsgTime(double seconds) {
  const CloudStamp stamp = SecondsToStamp(seconds);
  return {stamp.sec, stamp.nanosec};
}

double ToSeconds(const dammloam_msg_Time& time) { return time.sec + time.nanosec * 1e-9; }

CloudInput ViewOf(const dammloam_msg_PointCloud& cloud) {
  CloudInput view = ViewOfBody(cloud);
  view.stamp = {cloud.header.stamp.sec, cloud.header.stamp.nanosec};
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
  if (CloudProblem problem = CheckCloudLayout(cloud, limits); !problem.message.empty()) {
    if (error != nullptr) *error = problem.message;
    return std::nullopt;
  }
  const CloudFieldView* f[10];
  const char* names[] = {"x", "y", "z", "map_x", "map_y", "map_z",
                         "normal_x", "normal_y", "normal_z", "label"};
  for (int k = 0; k < 10; ++k) {
    f[k] = FindCloudField(cloud, names[k]);
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
    for (int k = 0; k < 10; ++k) v[k] = ReadPointFieldValue(p + f[k]->offset, f[k]->datatype);
    out.points_sensor.emplace_back(v[0], v[1], v[2]);
    out.points_map.emplace_back(v[3], v[4], v[5]);
    out.normals.emplace_back(static_cast<float>(v[6]), static_cast<float>(v[7]),
                             static_cast<float>(v[8]));
    // Casting a label outside [0, 256) (any field type is allowed) to uint8 is undefined.
    if (!(v[9] >= 0.0 && v[9] < static_cast<double>(kNumPointClasses))) {
      if (error != nullptr) {
        *error = CloudPointName(index, cloud.width) + " has label " + std::to_string(v[9]) +
                 ", not one of the " + std::to_string(kNumPointClasses) + " point classes";
      }
      return std::nullopt;
    }
    out.labels.push_back(static_cast<PointClass>(static_cast<std::uint8_t>(v[9])));
  }
  return out;
}

}  // namespace dammloam::dds
