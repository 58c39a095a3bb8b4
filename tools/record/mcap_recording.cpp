#include "tools/record/mcap_recording.hpp"

#include "core/odometry/ros_covariance.hpp"
#include "io/bag/ros2_output.hpp"
#include "io/bag/ros2_schemas.hpp"
#include "services/dds/messages.hpp"
#include "services/dds/point_cloud.hpp"

namespace dammloam::tools {
namespace {

std::uint64_t Nanoseconds(const dammloam_msg_Time& t) {
  return static_cast<std::uint64_t>(t.sec) * 1000000000ull + t.nanosec;
}

CloudStamp ToStamp(const dammloam_msg_Time& t) { return {t.sec, t.nanosec}; }

// rosbag2 needs the QoS a topic was offered with; empty means rclcpp's defaults.
const std::map<std::string, std::string> kRecordedChannelMetadata = {{"offered_qos_profiles", ""}};

}  // namespace

McapRecording::McapRecording(const std::filesystem::path& file)
    : writer_(file, io::McapWriteOptions{"zstd"}) {
  const auto channel = [&](const char* type, const std::string& schema, const char* topic) {
    return writer_.AddChannel(writer_.AddSchema(type, "ros2msg", schema), topic, "cdr",
                              kRecordedChannelMetadata);
  };
  odometry_ = channel("nav_msgs/msg/Odometry", io::OdometrySchema(), "/dammloam/odometry");
  tf_ = channel("tf2_msgs/msg/TFMessage", io::TfMessageSchema(), "/tf");
  cloud_ = channel("sensor_msgs/msg/PointCloud2", io::PointCloud2Schema(), "/dammloam/labelled_cloud");
  loops_ = channel("visualization_msgs/msg/MarkerArray", io::MarkerArraySchema(), "/dammloam/loop_closures");
  status_ = channel("std_msgs/msg/String", io::StringSchema(), "/dammloam/status");
}

void McapRecording::AddOdometry(const dammloam_msg_Odometry& m) {
  const Eigen::Isometry3d T = dds::FromMsgPose(m.pose);
  Matrix6d covariance;
  for (int r = 0; r < 6; ++r) {
    for (int c = 0; c < 6; ++c) covariance(r, c) = m.covariance[6 * r + c];
  }
  Vector6d twist;
  twist << m.linear_velocity.x, m.linear_velocity.y, m.linear_velocity.z, m.angular_velocity.x,
      m.angular_velocity.y, m.angular_velocity.z;
  const CloudStamp stamp = ToStamp(m.header.stamp);
  const std::uint64_t t = Nanoseconds(m.header.stamp);
  map_frame_ = m.header.frame_id;
  writer_.Write(odometry_, t, t,
                io::OdometryCdr(stamp, m.header.frame_id, m.child_frame_id, T,
                                PoseCovarianceToRos(covariance, T), twist, Matrix6d::Zero()));
  writer_.Write(tf_, t, t, io::TfCdr(stamp, m.header.frame_id, m.child_frame_id, T));
  positions_[t] = T.translation();
}

bool McapRecording::AddLabelledCloud(const dammloam_msg_LabelledCloud& m, std::string* error) {
  const auto points = dds::CloudToLabelled(m.cloud, error);
  if (!points) return false;
  Cloud2 cloud = LabelledRos2Cloud(points->points_sensor, points->normals, points->labels,
                                   m.child_frame_id);
  cloud.stamp = ToStamp(m.header.stamp);
  const std::uint64_t t = Nanoseconds(m.header.stamp);
  writer_.Write(cloud_, t, t, io::PointCloud2Cdr(cloud));
  return true;
}

// The recorded position at stamp t: keyframe stamps travel as seconds inside the back-end, so
// they may differ from the pose's by a rounding (a nanosecond or so).
const Eigen::Vector3d* McapRecording::PositionAt(std::uint64_t t) const {
  constexpr std::uint64_t kTolerance = 1000000;  // 1 ms
  auto it = positions_.lower_bound(t > kTolerance ? t - kTolerance : 0);
  if (it == positions_.end() || it->first > t + kTolerance) return nullptr;
  return &it->second;
}

void McapRecording::AddLoop(const dammloam_msg_LoopClosure& m) {
  const Eigen::Vector3d* query = PositionAt(Nanoseconds(m.query_stamp));
  const Eigen::Vector3d* match = PositionAt(Nanoseconds(m.match_stamp));
  if (!m.accepted || query == nullptr || match == nullptr) return;
  io::LineMarker marker;
  marker.ns = "loop_closures";
  marker.id = loop_count_++;
  marker.lines.emplace_back(*match, *query);
  const std::uint64_t t = Nanoseconds(m.header.stamp);
  writer_.Write(loops_, t, t, io::LineMarkerArrayCdr(ToStamp(m.header.stamp), map_frame_, marker));
}

void McapRecording::AddStatus(const dammloam_msg_Time& stamp, const std::string& json) {
  const std::uint64_t t = Nanoseconds(stamp);
  writer_.Write(status_, t, t, io::StringCdr(json));
}

}  // namespace dammloam::tools
