#include "tools/bridge/bridge_messages.hpp"

#include <Eigen/Geometry>
#include <cmath>
#include <cstring>
#include <nlohmann/json.hpp>
#include <stdexcept>

#include "core/cloud/labelled_cloud2.hpp"
#include "core/odometry/ros_covariance.hpp"
#include "io/bag/ros2_output.hpp"
#include "io/bag/ros2_schemas.hpp"

namespace dammloam::bridge {
namespace {

constexpr std::size_t kMaxLoopPoses = 200'000;  // ~5.5 h of poses at 10 Hz
constexpr std::size_t kMaxLoopLines = 10'000;

std::string Text(const char* s) { return s != nullptr ? s : ""; }

std::string AsString(const std::vector<std::uint8_t>& bytes) {
  return std::string(bytes.begin(), bytes.end());
}

CloudStamp ToStamp(const dammloam_msg_Time& t) { return {t.sec, t.nanosec}; }

Eigen::Isometry3d PoseOf(const dammloam_msg_Pose3D& p) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.translation() = Eigen::Vector3d(p.position.x, p.position.y, p.position.z);
  T.linear() = Eigen::Quaterniond(p.orientation.w, p.orientation.x, p.orientation.y,
                                  p.orientation.z)
                   .normalized()
                   .toRotationMatrix();
  return T;
}

// Offset of a named field of the given datatype, or throws naming the field.
std::uint32_t FieldOffset(const dammloam_msg_PointCloud& cloud, const char* name,
                          std::uint8_t datatype) {
  for (std::uint32_t i = 0; i < cloud.fields._length; ++i) {
    const dammloam_msg_PointField& f = cloud.fields._buffer[i];
    if (f.name == nullptr || std::strcmp(f.name, name) != 0) continue;
    if (f.datatype != datatype) {
      throw std::invalid_argument(std::string("labelled cloud field '") + name +
                                  "' has datatype " + PointFieldTypeName(f.datatype) +
                                  ", expected " + PointFieldTypeName(datatype));
    }
    if (f.offset + PointFieldSize(datatype) > cloud.point_step) {
      throw std::invalid_argument(std::string("labelled cloud field '") + name +
                                  "' lies outside point_step");
    }
    return f.offset;
  }
  throw std::invalid_argument(std::string("labelled cloud has no field '") + name + "'");
}

std::uint64_t VoxelKey(const Eigen::Vector3f& p, double voxel) {
  // 21 bits per axis: +-262 km at 0.25 m voxels.
  const auto cell = [voxel](float v) {
    return static_cast<std::uint64_t>(static_cast<std::int64_t>(std::floor(v / voxel)) +
                                      (1 << 20)) &
           0x1FFFFF;
  };
  return cell(p.x()) | (cell(p.y()) << 21) | (cell(p.z()) << 42);
}

}  // namespace

std::vector<Channel> BridgeChannels() {
  const std::string cdr = "cdr", ros2msg = "ros2msg";
  return {
      {kOdometryChannel, "/dammloam/odometry", cdr, "nav_msgs/msg/Odometry",
       io::OdometrySchema(), ros2msg},
      {kTfChannel, "/tf", cdr, "tf2_msgs/msg/TFMessage", io::TfMessageSchema(), ros2msg},
      {kLabelledCloudChannel, "/dammloam/labelled_cloud", cdr, "sensor_msgs/msg/PointCloud2",
       io::PointCloud2Schema(), ros2msg},
      {kMapChannel, "/dammloam/map", cdr, "sensor_msgs/msg/PointCloud2",
       io::PointCloud2Schema(), ros2msg},
      {kLoopClosureChannel, "/dammloam/loop_closures", cdr,
       "visualization_msgs/msg/MarkerArray", io::MarkerArraySchema(), ros2msg},
      {kTrajectoryChannel, "/dammloam/trajectory", cdr, "visualization_msgs/msg/MarkerArray",
       io::MarkerArraySchema(), ros2msg},
      {kStatusChannel, "/dammloam/status", "json", "dammloam.DaemonStatus",
       R"({"type":"object","properties":{"daemon":{"type":"object"},"bridge":{"type":"object"}}})",
       "jsonschema"},
  };
}

std::uint64_t StampNanoseconds(const dammloam_msg_Time& stamp) {
  if (stamp.sec < 0) return 0;
  return static_cast<std::uint64_t>(stamp.sec) * 1'000'000'000ull + stamp.nanosec;
}

std::string OdometryCdr(const dammloam_msg_Odometry& odometry) {
  const Eigen::Isometry3d T = PoseOf(odometry.pose);
  const Matrix6d covariance = Eigen::Map<const Eigen::Matrix<double, 6, 6, Eigen::RowMajor>>(
      odometry.covariance);
  Vector6d twist;
  twist << odometry.linear_velocity.x, odometry.linear_velocity.y, odometry.linear_velocity.z,
      odometry.angular_velocity.x, odometry.angular_velocity.y, odometry.angular_velocity.z;
  // The DDS message carries no twist covariance: zero, as ROS means "unknown" when all zero.
  return AsString(io::OdometryCdr(ToStamp(odometry.header.stamp), Text(odometry.header.frame_id),
                                  Text(odometry.child_frame_id), T,
                                  PoseCovarianceToRos(covariance, T), twist, Matrix6d::Zero()));
}

std::string TfCdr(const dammloam_msg_Odometry& odometry) {
  return AsString(io::TfCdr(ToStamp(odometry.header.stamp), Text(odometry.header.frame_id),
                            Text(odometry.child_frame_id), PoseOf(odometry.pose)));
}

std::vector<ClassPoint> LabelledMapPoints(const dammloam_msg_LabelledCloud& labelled,
                                          std::size_t budget) {
  const dammloam_msg_PointCloud& cloud = labelled.cloud;
  const std::uint32_t x = FieldOffset(cloud, "map_x", point_field::kFloat32);
  const std::uint32_t y = FieldOffset(cloud, "map_y", point_field::kFloat32);
  const std::uint32_t z = FieldOffset(cloud, "map_z", point_field::kFloat32);
  const std::uint32_t label = FieldOffset(cloud, "label", point_field::kUint8);
  const std::uint64_t count = static_cast<std::uint64_t>(cloud.width) * cloud.height;
  if (count * cloud.point_step > cloud.data._length) {
    throw std::invalid_argument("labelled cloud data holds " + std::to_string(cloud.data._length) +
                                " bytes, its size says " +
                                std::to_string(count * cloud.point_step));
  }
  const std::uint64_t stride = budget == 0 ? 1 : std::max<std::uint64_t>(1, (count + budget - 1) / budget);
  std::vector<ClassPoint> points;
  points.reserve(static_cast<std::size_t>(count / stride + 1));
  for (std::uint64_t i = 0; i < count; i += stride) {
    const std::uint8_t* p = cloud.data._buffer + i * cloud.point_step;
    ClassPoint point;
    std::memcpy(&point.position.x(), p + x, 4);
    std::memcpy(&point.position.y(), p + y, 4);
    std::memcpy(&point.position.z(), p + z, 4);
    point.label = p[label];
    if (point.position.allFinite()) points.push_back(point);
  }
  return points;
}

std::string ClassCloudCdr(const std::vector<ClassPoint>& points, const CloudStamp& stamp,
                          const std::string& frame_id) {
  Cloud2 cloud;
  cloud.stamp = stamp;
  cloud.frame_id = frame_id;
  cloud.width = static_cast<std::uint32_t>(points.size());
  cloud.fields = {{"x", 0, point_field::kFloat32, 1},
                  {"y", 4, point_field::kFloat32, 1},
                  {"z", 8, point_field::kFloat32, 1},
                  {"label", 12, point_field::kUint8, 1}};
  cloud.point_step = 16;
  cloud.row_step = cloud.point_step * cloud.width;
  cloud.data.assign(static_cast<std::size_t>(cloud.row_step), 0);
  for (std::size_t i = 0; i < points.size(); ++i) {
    std::uint8_t* p = cloud.data.data() + i * cloud.point_step;
    std::memcpy(p, points[i].position.data(), 12);
    p[12] = points[i].label;
  }
  return AsString(io::PointCloud2Cdr(cloud));
}

void VoxelMap::Add(const std::vector<ClassPoint>& points) {
  for (const ClassPoint& point : points) {
    const std::uint64_t key = VoxelKey(point.position, config_.voxel_size);
    const auto it = voxels_.find(key);
    if (it != voxels_.end()) {
      it->second.label = point.label;
    } else if (voxels_.size() < config_.max_points) {
      voxels_.emplace(key, point);
    } else {
      ++left_out_;
    }
  }
}

std::vector<ClassPoint> VoxelMap::Points() const {
  std::vector<ClassPoint> points;
  points.reserve(voxels_.size());
  for (const auto& [key, point] : voxels_) points.push_back(point);
  return points;
}

void LoopLines::AddPose(std::uint64_t stamp_ns, const Eigen::Vector3d& position) {
  positions_[stamp_ns] = position;
  if (positions_.size() > kMaxLoopPoses) positions_.erase(positions_.begin());
}

bool LoopLines::AddLoop(const dammloam_msg_LoopClosure& loop) {
  if (!loop.accepted) return false;
  const auto query = positions_.find(StampNanoseconds(loop.query_stamp));
  const auto match = positions_.find(StampNanoseconds(loop.match_stamp));
  if (query == positions_.end() || match == positions_.end()) return false;
  lines_.emplace_back(match->second, query->second);
  if (lines_.size() > kMaxLoopLines) lines_.erase(lines_.begin());
  return true;
}

std::string LoopLines::MarkerArrayCdr(const CloudStamp& stamp, const std::string& frame_id) const {
  io::LineMarker marker;
  marker.ns = "loop_closures";
  marker.lines = lines_;
  marker.rgba[0] = 1.f;  // magenta: apart from every class colour
  marker.rgba[1] = 0.f;
  marker.rgba[2] = 1.f;
  marker.width = 0.08;
  return AsString(io::LineMarkerArrayCdr(stamp, frame_id, marker));
}

std::string StatusJsonPayload(const dammloam_msg_DaemonStatus& s, const BridgeCounters& bridge) {
  using nlohmann::json;
  json reasons = json::object();
  for (std::uint32_t i = 0; i < s.rejected_by_reason._length; ++i) {
    reasons[Text(s.rejected_by_reason._buffer[i].reason)] = s.rejected_by_reason._buffer[i].count;
  }
  const json daemon = {
      {"node", Text(s.node)},
      {"state", s.state},
      {"tracking", Text(s.tracking)},
      {"scans_received", s.scans_received},
      {"scans_processed", s.scans_processed},
      {"scans_dropped", s.scans_dropped},
      {"scans_rejected", s.scans_rejected},
      {"rejected_by_reason", reasons},
      {"latency_median_ms", s.latency_median_ms},
      {"latency_p95_ms", s.latency_p95_ms},
      {"latency_p99_ms", s.latency_p99_ms},
      {"latency_max_ms", s.latency_max_ms},
      {"error_count", s.error_count},
      {"last_error", Text(s.last_error)},
      {"loop_closure", Text(s.loop_closure)},
      {"samples_lost", s.samples_lost},
      {"scans_degraded", s.scans_degraded},
      {"scans_lost", s.scans_lost},
  };
  const json own = {{"clients", bridge.clients},
                    {"frames_dropped", bridge.frames_dropped},
                    {"map_points", bridge.map_points},
                    {"bad_samples", bridge.bad_samples}};
  return json{{"daemon", daemon}, {"bridge", own}}.dump(-1, ' ', false,
                                                         json::error_handler_t::replace);
}

}  // namespace dammloam::bridge
